#include "tests/TestSupport.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numeric>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "io/scene/SceneLoader.h"

namespace sph::test {

std::string sourcePath(const std::string& relative) {
  return std::string(SPHSPLAT_SOURCE_DIR) + "/" + relative;
}

scene::Scene shippedScene(const std::string& name, const std::vector<std::string>& overrides) {
  return io::scene::loadScene(sourcePath("scenes/" + name + ".json"), overrides);
}

std::vector<SurgePoint> martinMoyce() {
  std::ifstream in(sourcePath("tests/data/martin_moyce_1952.csv"));
  std::vector<SurgePoint> points;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'T') continue;
    SurgePoint p;
    char comma;
    std::istringstream(line) >> p.T >> comma >> p.Z;
    points.push_back(p);
  }
  return points;
}

std::uint64_t stateHash(const Particles& p) {
  std::vector<std::size_t> byId(p.size());
  std::iota(byId.begin(), byId.end(), 0);
  std::sort(byId.begin(), byId.end(),
            [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* data, std::size_t n) {
    const unsigned char* c = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < n; ++k) h = (h ^ c[k]) * 1099511628211ull;
  };
  p.forEachField([&](const auto& field) {
    for (std::size_t i : byId) mix(&field[i], sizeof(field[i]));
  });
  return h;
}

std::string sphsplatCommand() {
#ifdef SPHSPLAT_CHILD_LEAK_CHECK_OFF
  // Sanitizer builds: a run that draws reports 128-240 bytes "leaked" from an unknown module: Mesa's
  // swrast_dri.so, whose globals still point at them when EGL unloads it before exit (with the
  // driver preloaded, so that it stays mapped, nothing is reported). LeakSanitizer can neither
  // attribute nor suppress a module that is gone; the binary's runs skip the leak check (the
  // in-process suites keep it for all of our library code, GL included).
  return std::string("env ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 ") + SPHSPLAT_BINARY;
#else
  return SPHSPLAT_BINARY;
#endif
}

CommandResult runShell(const std::string& command) {
  CommandResult result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) throw std::runtime_error("popen failed: " + command);
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

CommandResult runSphsplat(const std::string& arguments) {
  return runShell(sphsplatCommand() + " " + arguments);
}

Measured measure(const std::string& command) {
  const std::string log = makeTempDirectory() + "/out.log";
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(log.c_str(), "w", stdout) || !freopen(log.c_str(), "a", stderr)) _exit(126);
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  Measured m;
  m.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  m.peakBytes = usage.ru_maxrss * 1024.0;
  std::ifstream in(log);
  m.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return m;
}

double estimatedBytes(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex("memory: about ([0-9.]+) (MB|GB)"))) return 0;
  return std::stod(m[1]) * (m[2] == "GB" ? 1e9 : 1e6);
}

}  // namespace sph::test
