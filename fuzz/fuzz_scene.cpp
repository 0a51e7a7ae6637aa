// The scene parser's fuzzer (docs/reliability.md, "Fuzzing"): damaged copies of the shipped scenes
// (fuzz/SceneMutator.h) given to `sphsplat run SCENE --check` (the scene read, validated and its
// memory estimated, nothing simulated), each in a forked child of this process. Every case must
// end in success or in one line and exit 2: no crash, no hang, no single allocation over 256 MB.
//
//   fuzz_scene [--cases N] [--seed S] [--keep DIR] [--timeout SECONDS]
//   fuzz_scene --replay CASE.json
//
// Exit 0 when every case held, 1 when one did not (kept in DIR, default fuzz-failures/).
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "fuzz/ForkedCase.h"
#include "fuzz/FuzzSession.h"
#include "fuzz/SceneMutator.h"

namespace {

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

int main(int argc, char** argv) {
  const sph::fuzz::FuzzOptions o = sph::fuzz::parseFuzzOptions(
      argc, argv, 300, false,
      "fuzz_scene [--cases N] [--seed S] [--keep DIR] [--timeout SECONDS] [--replay CASE.json]");
  // The shipped scenes, in name order: the corpus.
  const std::string scenes = std::string(SPHSPLAT_SOURCE_DIR) + "/scenes";
  std::vector<std::string> names;
  if (DIR* d = opendir(scenes.c_str())) {
    while (const dirent* e = readdir(d)) {
      const std::string n = e->d_name;
      if (n.size() > 5 && n.compare(n.size() - 5, 5, ".json") == 0) names.push_back(n);
    }
    closedir(d);
  }
  std::sort(names.begin(), names.end());
  std::vector<sph::fuzz::SceneMutator> corpus;
  for (const std::string& n : names) corpus.emplace_back(readText(scenes + "/" + n));
  if (corpus.empty()) {
    std::fprintf(stderr, "fuzz_scene: no scenes in %s\n", scenes.c_str());
    return 1;
  }
  char dirTemplate[] = "/tmp/sphsplat-fuzz-scene-XXXXXX";
  const std::string dir = mkdtemp(dirTemplate);
  std::printf("fuzz_scene: seed %llu, %ld cases over the %zu shipped scenes\n", o.seed, o.cases,
              corpus.size());
  std::fflush(stdout);

  std::mt19937_64 random(o.seed);
  sph::fuzz::FuzzTally tally("fuzz_scene", o);
  for (long k = 0; k < o.cases; ++k) {
    const std::size_t which = random() % corpus.size();
    std::string what = o.replay.empty() ? "" : "replayed " + o.replay;
    const std::string text =
        o.replay.empty() ? corpus[which].mutate(random, what) : readText(o.replay);
    const std::string path = dir + "/case.json";
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    const sph::fuzz::CaseResult r =
        sph::fuzz::runForked({"run", path, "--check", "-q"}, o.timeout, std::size_t{256} << 20);
    tally.record(k, "run --check", r, sph::fuzz::verdict(r), names[which] + ": " + what,
                 "run " + path + " --check -q", "scene" + std::to_string(k) + ".json", text);
  }
  const int code = tally.finish();
  std::system(("rm -rf '" + dir + "'").c_str());
  return code;
}
