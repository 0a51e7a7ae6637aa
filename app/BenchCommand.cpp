// `sphsplat bench SWEEP.json`: run a sweep of scene variants (bench/sweep/Sweep.h) and write the
// CSV, the markdown table and the plot of wall time against error (docs/benchmarks.md).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/CliChecks.h"
#include "app/Commands.h"
#include "bench/sweep/SweepReport.h"
#include "bench/sweep/SweepRunner.h"
#include "io/MessageText.h"
#include "sim/InputError.h"

namespace sph::app {
namespace {

struct BenchOptions {
  std::string sweep;
  std::string output;  // folder; default results/<sweep name>
  int threads = -1;
  std::vector<std::string> overrides;
  std::string only;
  bool noPlot = false;
  bool quiet = false;
  std::string python;
  std::string plotScript = SPHSPLAT_SOURCE_DIR "/scripts/plot_sweep.py";
};

std::string defaultPython() {
  return access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
}

std::string reproduceCommand(const BenchOptions& o, const std::string& output) {
  std::string c = "sphsplat bench " + o.sweep;
  if (o.threads >= 0) c += " --threads " + std::to_string(o.threads);
  for (const std::string& s : o.overrides) c += " --set " + s;
  if (!o.only.empty()) c += " --only '" + o.only + "'";
  return c + " --output " + output;
}

void printVariant(const sweep::VariantResult& r, const std::vector<std::string>& columns,
                  std::size_t index, std::size_t count) {
  std::printf("[%zu/%zu] %s: %s", index + 1, count, r.variant.label.c_str(),
              scene::enumName(r.status));
  if (r.status == sweep::RunStatus::Guard)
    std::printf(" at step %llu", static_cast<unsigned long long>(r.guardStep));
  std::printf(", %zu particles, %llu steps, %.3g s (%.3g ms/step)", r.particles,
              static_cast<unsigned long long>(r.steps), r.wallSeconds, r.msPerStep());
  for (std::size_t m = 0; m < columns.size() && m < r.metrics.size(); ++m) {
    if (!std::isnan(r.metrics[m])) std::printf(", %s %.3g", columns[m].c_str(), r.metrics[m]);
  }
  std::printf("\n");
  std::fflush(stdout);
}

int bench(const BenchOptions& o) {
  const sweep::SweepSpec spec = sweep::loadSweep(o.sweep, o.overrides);
  const std::string output = o.output.empty() ? "results/" + spec.name : o.output;
  std::error_code error;
  std::filesystem::create_directories(output, error);
  if (error)
    throw InputError(output + ": cannot create the output folder (" + error.message() + ")");

  sweep::SweepRunOptions run;
  run.outputDir = output;
  run.threads = o.threads;
  run.only = o.only;
  if (!o.quiet) run.onVariant = printVariant;
  const sweep::SweepResult result = sweep::runSweep(spec, run);

  const std::string csv = output + "/" + spec.name + ".csv", md = output + "/" + spec.name + ".md";
  const std::string png = output + "/" + spec.name + ".png";
  sweep::writeCsv(result, csv);
  const bool plot = spec.plot && !o.noPlot;
  const std::string plotError =
      plot ? sweep::runPlot(result, o.python.empty() ? defaultPython() : o.python, o.plotScript,
                            csv, png)
           : "";
  sweep::writeMarkdown(result, sweep::currentReportContext(reproduceCommand(o, output)), md,
                       plot && plotError.empty() ? spec.name + ".png" : "");
  if (!o.quiet) {
    io::sayWritten(csv + ", " + md + (plot && plotError.empty() ? ", " + png : ""));
  }
  if (!plotError.empty()) std::fprintf(stderr, "sphsplat: plot: %s\n", plotError.c_str());
  return job::kOk;
}

}  // namespace

std::function<int()> addBenchCommand(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bench", "Run a sweep of scene variants: wall time against error (docs/benchmarks.md)");
  cmd->add_option("sweep", o->sweep, "Sweep file, e.g. bench/sweeps/dam_break.json")->required();
  cmd->add_option("--output,-o", o->output,
                  "Folder for NAME.csv, NAME.md and NAME.png (default results/NAME)");
  cmd->add_option("--threads,-j", o->threads,
                  "Worker threads (default: the sweep's `threads`, else all cores; at most 4 x "
                  "the cores)")
      ->check(threadsCheck());
  cmd->add_option("--set", o->overrides,
                  "Scene edit KEY.PATH=VALUE applied to every variant, repeatable");
  cmd->add_option("--only", o->only, "Run only the variants whose label contains TEXT");
  cmd->add_flag("--no-plot", o->noPlot, "Write the CSV and the table but no PNG");
  cmd->add_flag("--quiet,-q", o->quiet, "No progress lines");
  cmd->add_option("--python", o->python,
                  "Python with matplotlib for the plot (default /usr/bin/python3)");
  cmd->add_option("--plot-script", o->plotScript,
                  "The plot script (default: the source tree's scripts/plot_sweep.py)");
  cmd->footer(
      "A sweep file names a base scene, the axes and cases of scene edits, the metrics and the\n"
      "thread count (docs/benchmarks.md, \"Run time vs error: simulation\"). Variants that blow\n"
      "up are data: the table says where the guard stopped them. Exit codes: 0 done, 2 bad sweep\n"
      "or scene.");
  return [o, cmd]() { return cmd->parsed() ? bench(*o) : -1; };
}

}  // namespace sph::app
