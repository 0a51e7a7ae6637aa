#include "bench/sweep/SweepReport.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>

#include "sim/InputError.h"

namespace sph::sweep {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string number(double v, const char* format = "%.6g") {
  if (std::isnan(v)) return "";
  char text[64];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// CSV field: quoted when it holds a comma, a quote or a newline.
std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      return colon == std::string::npos ? line
                                        : line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown CPU";
}

// What happened, in words, for the table.
std::string statusText(const VariantResult& r) {
  char text[160];
  switch (r.status) {
    case RunStatus::Stable:
      if (r.speedBound > 0 && r.maxSpeed > 2 * r.speedBound) {
        std::snprintf(text, sizeof text, "stable, but max speed %.3g m/s = %.1fx the energy bound",
                      r.maxSpeed, r.maxSpeed / r.speedBound);
        return text;
      }
      return "stable";
    case RunStatus::Guard:
      std::snprintf(
          text, sizeof text, "guard stopped it at step %llu (t = %.4g s, %s)",
          static_cast<unsigned long long>(r.guardStep), r.guardTime,
          r.message.find("non-finite") != std::string::npos ? "non-finite" : "left the domain");
      return text;
    case RunStatus::Timeout:
      std::snprintf(text, sizeof text, "timeout after %.0f s wall (t = %.3g s)", r.wallSeconds,
                    r.simTime);
      return text;
    case RunStatus::Failed:
      return "failed: " + r.message;
  }
  return "?";
}

}  // namespace

ReportContext currentReportContext(const std::string& command) {
  ReportContext c;
  c.command = command;
  c.machine = std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " cores, " + cpuModel();
  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  c.date = date;
  return c;
}

double columnValue(const SweepResult& result, const VariantResult& row, const std::string& column) {
  if (column == "wall_s") return row.wallSeconds;
  if (column == "cpu_s") return row.cpuSeconds;
  if (column == "ms_per_step") return row.msPerStep();
  if (column == "steps") return static_cast<double>(row.steps);
  if (column == "particles") return static_cast<double>(row.particles);
  if (column == "setup_s") return row.setupSeconds;
  if (column == "max_speed") return row.maxSpeed;
  if (column == "rss_mb") return row.rssMb;
  for (std::size_t m = 0; m < result.metricColumns.size(); ++m) {
    if (result.metricColumns[m] == column && m < row.metrics.size()) return row.metrics[m];
  }
  return kNaN;
}

std::string plotErrorColumn(const SweepResult& result) {
  if (!result.spec.plot) return "";
  if (!result.spec.plotY.empty()) return result.spec.plotY;
  return result.metricColumns.empty() ? std::string() : result.metricColumns.front();
}

std::vector<bool> paretoFront(const SweepResult& result, const std::string& x,
                              const std::string& y) {
  const std::size_t n = result.rows.size();
  std::vector<bool> front(n, false);
  auto usable = [&](std::size_t i) {
    return result.rows[i].status == RunStatus::Stable &&
           std::isfinite(columnValue(result, result.rows[i], x)) &&
           std::isfinite(columnValue(result, result.rows[i], y));
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!usable(i)) continue;
    const double xi = columnValue(result, result.rows[i], x),
                 yi = columnValue(result, result.rows[i], y);
    bool dominated = false;
    for (std::size_t j = 0; j < n && !dominated; ++j) {
      if (j == i || !usable(j)) continue;
      const double xj = columnValue(result, result.rows[j], x),
                   yj = columnValue(result, result.rows[j], y);
      dominated = xj <= xi && yj <= yi && (xj < xi || yj < yi);
    }
    front[i] = !dominated;
  }
  return front;
}

void writeCsv(const SweepResult& result, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write the CSV");
  const std::string y = plotErrorColumn(result);
  const std::vector<bool> front = paretoFront(result, result.spec.plotX, y);
  out << "variant,label,case";
  for (const SweepAxis& a : result.spec.axes) out << "," << csvField(a.label);
  out << ",status,guard_step,guard_time,particles,particles_end,boundary_particles,steps,sim_time,"
         "setup_s,wall_s,cpu_s,"
         "ms_per_step,ns_per_particle_step,threads,speed_of_sound,stiffness,h,max_speed,speed_"
         "bound,rss_mb";
  for (int p = 0; p < static_cast<int>(solver::Pass::Count); ++p)
    out << ",pass_" << passName(static_cast<solver::Pass>(p)) << "_s";
  for (const std::string& c : result.metricColumns) out << "," << c;
  out << ",pareto,message\n";
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    const VariantResult& r = result.rows[i];
    out << i << "," << csvField(r.variant.label) << "," << csvField(r.variant.caseLabel);
    for (const std::string& v : r.variant.axisValues) out << "," << csvField(v);
    const double particleSteps = static_cast<double>(r.profile.particleSteps);
    out << "," << scene::enumName(r.status) << ","
        << (r.status == RunStatus::Guard ? std::to_string(r.guardStep) : "") << ","
        << (r.status == RunStatus::Guard ? number(r.guardTime) : "") << "," << r.particles << ","
        << r.particlesEnd << "," << r.boundaryParticles << "," << r.steps << ","
        << number(r.simTime) << "," << number(r.setupSeconds) << "," << number(r.wallSeconds) << ","
        << number(r.cpuSeconds) << "," << number(r.msPerStep()) << ","
        << number(particleSteps > 0 ? 1e9 * r.wallSeconds / particleSteps : kNaN) << ","
        << result.threads << "," << number(r.speedOfSound) << "," << number(r.stiffness) << ","
        << number(r.h) << "," << number(r.maxSpeed) << "," << number(r.speedBound) << ","
        << number(r.rssMb);
    for (double s : r.profile.seconds) out << "," << number(s);
    for (double v : r.metrics) out << "," << number(v);
    out << "," << (front[i] ? 1 : 0) << "," << csvField(r.message) << "\n";
  }
  if (!out) throw InputError(path + ": error while writing the CSV");
}

void writeMarkdown(const SweepResult& result, const ReportContext& context, const std::string& path,
                   const std::string& pngName) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write the markdown table");
  const SweepSpec& s = result.spec;
  const std::string y = plotErrorColumn(result);
  const std::vector<bool> front = paretoFront(result, s.plotX, y);
  out << "<!-- generated by sphsplat bench; do not edit by hand -->\n";
  if (!s.description.empty()) out << s.description << "\n\n";
  out << "Command: `" << context.command << "`  \n";
  out << "Machine: " << context.machine << "; " << result.threads << " thread"
      << (result.threads == 1 ? "" : "s") << "; " << context.date << ".\n\n";
  const bool cases = !s.cases.empty();
  out << "|";
  if (cases) out << " case |";
  for (const SweepAxis& a : s.axes) out << " " << a.label << " |";
  out << " what happened | particles | steps | wall s | cpu s | ms/step |";
  for (const std::string& c : result.metricColumns) out << " " << c << " |";
  if (!y.empty()) out << " Pareto |";
  out << "\n|";
  const std::size_t columns =
      (cases ? 1 : 0) + s.axes.size() + 6 + result.metricColumns.size() + (y.empty() ? 0 : 1);
  for (std::size_t c = 0; c < columns; ++c) out << " --- |";
  out << "\n";
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    const VariantResult& r = result.rows[i];
    out << "|";
    if (cases)
      out << " " << r.variant.caseLabel
          << (r.variant.note.empty() ? "" : " (" + r.variant.note + ")") << " |";
    for (const std::string& v : r.variant.axisValues) out << " " << v << " |";
    out << " " << statusText(r) << " | " << r.particles;
    if (r.particlesEnd != r.particles) out << " -> " << r.particlesEnd;
    out << " | " << r.steps << " | " << number(r.wallSeconds, "%.3g") << " | "
        << number(r.cpuSeconds, "%.3g") << " | " << number(r.msPerStep(), "%.3g") << " |";
    for (double v : r.metrics)
      out << " " << (std::isnan(v) ? std::string("-") : number(v, "%.3g")) << " |";
    if (!y.empty()) out << (front[i] ? " **yes** |" : " |");
    out << "\n";
  }
  if (!y.empty()) {
    out << "\nPareto: not beaten on both `" << s.plotX << "` and `" << y
        << "` by another stable variant.";
    if (!pngName.empty()) out << " Plot: `" << pngName << "`.";
    out << "\n";
  }
}

std::string runPlot(const SweepResult& result, const std::string& python, const std::string& script,
                    const std::string& csvPath, const std::string& pngPath) {
  const std::string y = plotErrorColumn(result);
  if (y.empty()) return "no error column to plot (the sweep has no metric)";
  std::vector<std::string> args = {
      python, script, csvPath,   pngPath,         "--x", result.spec.plotX,
      "--y",  y,      "--title", result.spec.name};
  if (result.spec.logY) args.push_back("--log-y");
  for (const SweepAxis& a : result.spec.axes) args.push_back("--axis"), args.push_back(a.label);
  // fork + exec: no shell, so paths and titles need no quoting.
  const pid_t pid = fork();
  if (pid < 0) return "cannot start " + python;
  if (pid == 0) {
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    std::fprintf(stderr, "sphsplat: cannot run %s\n", argv[0]);
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return python + " " + script + " failed (exit " +
           std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
           "); the CSV and the table are written";
  }
  return "";
}

}  // namespace sph::sweep
