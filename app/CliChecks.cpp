#include "app/CliChecks.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "job/distributed/DistributedRun.h"
#include "io/MessageText.h"
#include "sim/Parallel.h"

namespace sph::app {
namespace {

// Strict integer: optional sign and digits only; false on overflow.
bool readInteger(const std::string& text, long long& value) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(text.c_str(), &end, 10);
  return errno == 0 && end == text.c_str() + text.size();
}

std::string got(const std::string& text) {
  return "got '" + io::printable(text) + "'";
}

// Where the limit comes from. omp_get_num_procs counts the processors this process may run on:
// under mpirun, which binds each rank to its share of the cores, that is the rank's share.
std::string coresText() {
  const std::string count = std::to_string(omp_get_num_procs()) + " cores";
  if (job::distributed::world()) return "4 x the " + count + " mpirun binds this rank to";
  return "4 x the " + count + " here";
}

}  // namespace

CLI::Validator threadsCheck() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const int limit = maxThreadCount();
        long long n = 0;
        if (readInteger(text, n) && n >= 0 && n <= limit) return "";
        return "expected 0 (all cores) or a thread count up to " + std::to_string(limit) + " (" +
               coresText() + "), " + got(text);
      },
      "0-" + std::to_string(maxThreadCount()));
}

CLI::Validator positiveUpTo(double hi, const std::string& unit) {
  return CLI::Validator(
      [hi, unit](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool number = !text.empty() && end == text.c_str() + text.size();
        if (number && std::isfinite(v) && v > 0 && v <= hi) return "";
        return "expected a number of " + unit + " in (0, " + io::readableNumber(hi) + "], " +
               got(text);
      },
      "(0, " + io::readableNumber(hi) + "]");
}

CLI::Validator integerIn(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        long long n = 0;
        if (readInteger(text, n) && n >= lo && n <= hi) return "";
        return "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], " +
               got(text);
      },
      "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

std::string oneLineFailure(const CLI::App* app, const CLI::Error& e) {
  // The subcommand the user was in, so the hint points at its options.
  std::string command = "sphsplat";
  for (const CLI::App* sub : app->get_subcommands()) command += " " + sub->get_name();
  // A file name that begins with '-' reads as options ("run -x.json" then misses its scene):
  // say how to name it.
  std::string hint;
  for (const CLI::App* sub : app->get_subcommands()) {
    for (const std::string& extra : sub->remaining()) {
      if (extra.size() > 1 && extra[0] == '-' && extra.find('.') != std::string::npos) {
        hint = "; " + io::printable(extra, 80) + " is read as options: name the file ./" +
               io::printable(extra, 80);
        break;
      }
    }
  }
  return "sphsplat: " + io::printable(e.what(), 200) + hint + " (see " + command + " --help)\n";
}

}  // namespace sph::app
