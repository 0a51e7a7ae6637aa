// The cache reader's fuzzer (docs/reliability.md, "Fuzzing"): damaged copies of a small real cache
// (fuzz/CacheMutator.h) given to `info`, `export`, `mesh`, `render` and `run --resume`, each in a
// forked child of this process (fuzz/ForkedCase.h). Every case must end in success or in one line
// and exit 2 (a resume may also stop at a numerical blow-up, exit 3: damaged numbers can be
// valid ones): no crash, no hang, no single allocation larger than the file's size allows.
//
//   fuzz_cache [--cases N] [--seed S] [--keep DIR] [--timeout SECONDS] [--render-every K]
//   fuzz_cache --replay CASE.h5     (a kept case again, through every command)
//
// Exit 0 when every case held, 1 when one did not (each such case is kept in DIR, default
// fuzz-failures/, with the command that failed). The default suite runs a short fixed-seed run
// (tests/CMakeLists.txt); docs/reliability.md has the nightly-sized run's command and result.
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "fuzz/CacheMutator.h"
#include "fuzz/ForkedCase.h"

namespace {

using sph::fuzz::Bytes;

// A tank, a nozzle, a camera, a few hundred rain drops and pictures stored in the cache: every
// kind of record a cache holds, in 5 frames.
const char* const kScene = R"({
  "name": "fuzz",
  "solver": {"spacing": 0.025, "end_time": 0.04},
  "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.2, 0.2, 0.15]}],
  "fluids": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.15]}],
  "emitters": [{"type": "nozzle", "position": [0.15, 0.17, 0.075], "direction": [0, -1, 0],
                "radius": 0.02, "speed": 0.5, "start": 0, "stop": 1}],
  "camera": {"position": [0.5, 0.4, 0.5], "target": [0.1, 0.05, 0.075], "fov": 40},
  "rain": {"count": 300, "near": 0.05, "far": 0.8, "fall_speed": 3, "seed": 7},
  "render": {"splat": "quad", "width": 48, "height": 32},
  "output": {"fps": 100}
}
)";

struct Options {
  long cases = 200;
  unsigned long long seed = 1;
  std::string keep = "fuzz-failures";
  double timeout = 20;
  long renderEvery = 10;
  std::string replay;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
    if (a == "--cases" && v) o.cases = std::atol(v), ++i;
    else if (a == "--seed" && v) o.seed = std::strtoull(v, nullptr, 10), ++i;
    else if (a == "--keep" && v) o.keep = v, ++i;
    else if (a == "--timeout" && v) o.timeout = std::atof(v), ++i;
    else if (a == "--render-every" && v) o.renderEvery = std::atol(v), ++i;
    else if (a == "--replay" && v) o.replay = v, o.cases = 1, o.renderEvery = 1, ++i;
    else {
      std::fprintf(stderr,
                   "usage: fuzz_cache [--cases N] [--seed S] [--keep DIR] [--timeout SECONDS] "
                   "[--render-every K] [--replay CASE.h5]\n");
      std::exit(2);
    }
  }
  return o;
}

Bytes readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

void writeBytes(const std::string& path, const Bytes& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  char dirTemplate[] = "/tmp/sphsplat-fuzz-XXXXXX";
  const std::string dir = mkdtemp(dirTemplate);
  const std::string scene = dir + "/fuzz.json", base = dir + "/base.h5";
  std::ofstream(scene) << kScene;
  const sph::fuzz::CaseResult made =
      sph::fuzz::runForked({"run", scene, "--threads", "1", "-q", "-o", base}, 120, 0);
  if (!made.exited || made.exitCode != 0) {
    std::fprintf(stderr, "fuzz_cache: cannot write the cache to damage: %s\n", made.errors.c_str());
    return 1;
  }
  const Bytes original = readBytes(base);
  const sph::fuzz::CacheMutator mutator(original);
  // One allocation may take the file's size many times over (a frame's arrays, their
  // decompression, the pictures), never a size that only a damaged field would ask for.
  const std::size_t limit = (std::size_t{64} << 20) + 16 * original.size();
  std::printf("fuzz_cache: seed %llu, %ld cases, a cache of %zu bytes: %s\n", o.seed, o.cases,
              original.size(), mutator.describe().c_str());
  std::fflush(stdout);

  std::mt19937_64 random(o.seed);
  std::map<std::string, long> outcomes;  // "info exit 2" -> count
  long failures = 0;
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < o.cases; ++k) {
    std::string what = "replayed " + o.replay;
    const Bytes damaged = o.replay.empty() ? mutator.mutate(random, what) : readBytes(o.replay);
    const std::string path = dir + "/case.h5";
    std::vector<std::vector<std::string>> commands = {
        {"info", path},
        {"export", path, "--frames", "all", "--format", "csv", "-o", dir + "/export/",
         "--overwrite"},
        {"mesh", path, "--frames", "last", "--format", "ply", "--out", dir + "/mesh",
         "--overwrite"},
        {"run", scene, "--threads", "1", "-q", "--resume", path},
    };
    if (o.renderEvery > 0 && k % o.renderEvery == 0)
      commands.push_back({"render", path, "--frames", "last", "--out", dir + "/render", "-q"});
    for (const std::vector<std::string>& command : commands) {
      writeBytes(path, damaged);  // afresh: a resume writes to it
      const bool resume = command[0] == "run";
      const sph::fuzz::CaseResult r = sph::fuzz::runForked(command, o.timeout, limit);
      const std::string wrong = sph::fuzz::verdict(r, resume ? std::vector<int>{3} : std::vector<int>{});
      outcomes[command[0] + (r.exited ? " exit " + std::to_string(r.exitCode) : " killed")]++;
      if (wrong.empty()) continue;
      ++failures;
      mkdir(o.keep.c_str(), 0755);
      const std::string kept = o.keep + "/case" + std::to_string(k) + "_" + command[0] + ".h5";
      writeBytes(kept, damaged);
      std::string line;
      for (const std::string& word : command) line += " " + word;
      std::printf("case %ld (%s): sphsplat%s: %s; kept as %s\n%s", k, what.c_str(), line.c_str(),
                  wrong.c_str(), kept.c_str(), r.errors.c_str());
      std::fflush(stdout);
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("fuzz_cache: %ld cases in %.0f s, %ld failed;", o.cases, seconds, failures);
  for (const auto& [outcome, n] : outcomes) std::printf(" %s: %ld,", outcome.c_str(), n);
  std::printf("\n");
  std::system(("rm -rf '" + dir + "'").c_str());
  return failures == 0 ? 0 : 1;
}
