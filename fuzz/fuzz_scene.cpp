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
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz/ForkedCase.h"
#include "fuzz/SceneMutator.h"

namespace {

struct Options {
  long cases = 300;
  unsigned long long seed = 1;
  std::string keep = "fuzz-failures";
  double timeout = 20;
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
    else if (a == "--replay" && v) o.replay = v, o.cases = 1, ++i;
    else {
      std::fprintf(stderr, "usage: fuzz_scene [--cases N] [--seed S] [--keep DIR] "
                           "[--timeout SECONDS] [--replay CASE.json]\n");
      std::exit(2);
    }
  }
  return o;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
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
  std::map<std::string, long> outcomes;
  long failures = 0;
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < o.cases; ++k) {
    const std::size_t which = random() % corpus.size();
    std::string what = "replayed " + o.replay;
    const std::string text =
        o.replay.empty() ? corpus[which].mutate(random, what) : readText(o.replay);
    const std::string path = dir + "/case.json";
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    const sph::fuzz::CaseResult r =
        sph::fuzz::runForked({"run", path, "--check", "-q"}, o.timeout, std::size_t{256} << 20);
    outcomes[r.exited ? "exit " + std::to_string(r.exitCode) : "killed"]++;
    const std::string wrong = sph::fuzz::verdict(r);
    if (wrong.empty()) continue;
    ++failures;
    mkdir(o.keep.c_str(), 0755);
    const std::string kept = o.keep + "/scene" + std::to_string(k) + ".json";
    std::ofstream(kept, std::ios::binary) << text;
    std::printf("case %ld (%s, %s): %s; kept as %s\n%s", k, names[which].c_str(), what.c_str(),
                wrong.c_str(), kept.c_str(), r.errors.c_str());
    std::fflush(stdout);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("fuzz_scene: %ld cases in %.0f s, %ld failed;", o.cases, seconds, failures);
  for (const auto& [outcome, n] : outcomes) std::printf(" %s: %ld,", outcome.c_str(), n);
  std::printf("\n");
  std::system(("rm -rf '" + dir + "'").c_str());
  return failures == 0 ? 0 : 1;
}
