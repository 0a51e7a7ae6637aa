// The cache reader's fuzzer (docs/reliability.md, "Fuzzing"): damaged copies of a small real cache
// (fuzz/CacheMutator.h) given to `info`, `export`, `mesh`, `render` and `run --resume`, each in a
// forked child of this process (fuzz/ForkedCase.h). Every case must end in success or in one line
// and exit 2 (a resume may also stop at a numerical blow-up, exit 3: damaged numbers can be
// valid ones): no crash, no hang, no single allocation larger than the file's size allows.
//
//   fuzz_cache [--cases N] [--seed S] [--keep DIR] [--timeout SECONDS] [--render-every K]
//   fuzz_cache --replay CASE.h5     (a kept case again, through every command)
//   fuzz_cache --corpus             (the named damages of CacheMutator::corpus(), each of which
//                                    some command must refuse)
//
// Exit 0 when every case held, 1 when one did not (each such case is kept in DIR, default
// fuzz-failures/, with the command that failed). The default suite runs a short fixed-seed run
// (tests/CMakeLists.txt); docs/reliability.md has the nightly-sized run's command and result.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "fuzz/CacheMutator.h"
#include "fuzz/ForkedCase.h"
#include "fuzz/FuzzSession.h"

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
  const sph::fuzz::FuzzOptions o = sph::fuzz::parseFuzzOptions(
      argc, argv, 200, true,
      "fuzz_cache [--cases N] [--seed S] [--keep DIR] [--timeout SECONDS] [--render-every K] "
      "[--replay CASE.h5] [--corpus]");
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
  const std::string runs = o.corpus ? std::string("the corpus of named damages")
                                    : "seed " + std::to_string(o.seed) + ", " +
                                          std::to_string(o.cases) + " cases";
  std::printf("fuzz_cache: %s, a cache of %zu bytes: %s\n", runs.c_str(), original.size(),
              mutator.describe().c_str());
  std::fflush(stdout);

  std::mt19937_64 random(o.seed);
  sph::fuzz::FuzzTally tally("fuzz_cache", o);
  // Case `k`: `damaged` through every command; returns how many refused it (exit 2).
  auto runCase = [&](long k, const std::string& what, const Bytes& damaged, bool render) {
    const std::string path = dir + "/case.h5";
    std::vector<std::vector<std::string>> commands = {
        {"info", path},
        {"export", path, "--frames", "all", "--format", "csv", "-o", dir + "/export/",
         "--overwrite"},
        {"mesh", path, "--frames", "last", "--format", "ply", "--out", dir + "/mesh",
         "--overwrite"},
        {"run", scene, "--threads", "1", "-q", "--resume", path},
    };
    if (render)
      commands.push_back({"render", path, "--frames", "last", "--out", dir + "/render", "-q"});
    int refused = 0;
    for (const std::vector<std::string>& command : commands) {
      writeBytes(path, damaged);  // afresh: a resume writes to it
      const sph::fuzz::CaseResult r = sph::fuzz::runForked(command, o.timeout, limit);
      // A resume may stop at a numerical blow-up: damaged numbers can be valid ones.
      const std::vector<int> also = command[0] == "run" ? std::vector<int>{3} : std::vector<int>{};
      std::string line;
      for (const std::string& word : command) line += (line.empty() ? "" : " ") + word;
      tally.record(k, command[0], r, sph::fuzz::verdict(r, also), what, line,
                   "case" + std::to_string(k) + "_" + command[0] + ".h5",
                   std::string(damaged.begin(), damaged.end()));
      refused += r.exited && r.exitCode == 2;
    }
    return refused;
  };
  if (o.corpus) {
    // Each named damage must also be noticed: some command refuses the file.
    long k = 0;
    for (const auto& [name, damaged] : mutator.corpus()) {
      const int refused = runCase(k, name, damaged, true);
      std::printf("  %-52s refused by %d of 5 commands\n", name.c_str(), refused);
      if (refused == 0) {
        mkdir(o.keep.c_str(), 0755);
        const std::string kept = o.keep + "/corpus" + std::to_string(k) + ".h5";
        writeBytes(kept, damaged);
        tally.fail(k, name + ": no command noticed the damage; kept as " + kept);
      }
      ++k;
    }
  }
  for (long k = 0; k < (o.corpus ? 0 : o.cases); ++k) {
    std::string what = o.replay.empty() ? "" : "replayed " + o.replay;
    const Bytes damaged = o.replay.empty() ? mutator.mutate(random, what) : readBytes(o.replay);
    runCase(k, what, damaged, o.renderEvery > 0 && k % o.renderEvery == 0);
  }
  const int code = tally.finish();
  std::system(("rm -rf '" + dir + "'").c_str());
  return code;
}
