#include "fuzz/FuzzSession.h"

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace sph::fuzz {

FuzzOptions parseFuzzOptions(int argc, char** argv, long defaultCases, bool cacheFlags,
                             const char* usage) {
  FuzzOptions o;
  o.cases = defaultCases;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
    if (a == "--cases" && v)
      o.cases = std::atol(v), ++i;
    else if (a == "--seed" && v)
      o.seed = std::strtoull(v, nullptr, 10), ++i;
    else if (a == "--keep" && v)
      o.keep = v, ++i;
    else if (a == "--timeout" && v)
      o.timeout = std::atof(v), ++i;
    else if (cacheFlags && a == "--render-every" && v)
      o.renderEvery = std::atol(v), ++i;
    else if (cacheFlags && a == "--corpus")
      o.corpus = true;
    else if (a == "--replay" && v)
      o.replay = v, o.cases = 1, o.renderEvery = 1, ++i;
    else {
      std::fprintf(stderr, "usage: %s\n", usage);
      std::exit(2);
    }
  }
  return o;
}

FuzzTally::FuzzTally(std::string program, FuzzOptions options)
    : program_(std::move(program)), options_(std::move(options)) {}

void FuzzTally::record(long k, const std::string& label, const CaseResult& r,
                       const std::string& wrong, const std::string& what,
                       const std::string& command, const std::string& keptName,
                       const std::string& input) {
  outcomes_[label + (r.exited ? " exit " + std::to_string(r.exitCode) : " killed")]++;
  if (wrong.empty()) return;
  ++failures_;
  mkdir(options_.keep.c_str(), 0755);
  const std::string kept = options_.keep + "/" + keptName;
  std::ofstream(kept, std::ios::binary | std::ios::trunc) << input;
  std::printf("case %ld (%s): sphsplat %s: %s; kept as %s\n%s", k, what.c_str(), command.c_str(),
              wrong.c_str(), kept.c_str(), r.errors.c_str());
  std::fflush(stdout);
}

void FuzzTally::fail(long k, const std::string& why) {
  ++failures_;
  std::printf("case %ld: %s\n", k, why.c_str());
  std::fflush(stdout);
}

int FuzzTally::finish() const {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::printf("%s: %s in %.0f s, %ld failed;", program_.c_str(),
              options_.corpus ? "the corpus" : (std::to_string(options_.cases) + " cases").c_str(),
              seconds, failures_);
  for (const auto& [outcome, n] : outcomes_) std::printf(" %s: %ld,", outcome.c_str(), n);
  std::printf("\n");
  return failures_ == 0 ? 0 : 1;
}

}  // namespace sph::fuzz
