// `sphsplat mesh`: the frame syntax and file naming of `export`, files that meshio reads back as
// closed triangle meshes with unit normals, PLY and OBJ of one frame holding the same numbers, and
// the refusals (frames not in the cache, an existing output, several frames into one file, the
// cache itself), each one line with exit code 2 and nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using test::runShell;

using test::lineCount;
std::string sphsplat(const std::string& args) {
  return test::sphsplatShell(args);
}

// Reads a mesh with meshio; prints the cell type, points, triangles, whether every undirected
// edge is in exactly two triangles and every directed edge in one (closed, consistently wound),
// whether every normal has length 1 (to 1e-5), the signed volume's sign, and the points' and
// normals' float32 bytes to argv[2].
const char* kMeshioCheck = R"(import sys, numpy as np, meshio
m = meshio.read(sys.argv[1])
tri = m.cells_dict["triangle"]
d = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
u = np.sort(d, axis=1)
_, uc = np.unique(u, axis=0, return_counts=True)
_, dc = np.unique(d, axis=0, return_counts=True)
pd = m.point_data
if "nx" in pd: n = np.stack([pd["nx"], pd["ny"], pd["nz"]], axis=1)
else: n = pd["obj:vn"]
p = m.points.astype(np.float64)
vol = np.einsum("ij,ij->i", p[tri[:, 0]], np.cross(p[tri[:, 1]], p[tri[:, 2]])).sum() / 6
open(sys.argv[2], "wb").write(np.ascontiguousarray(np.concatenate([m.points, n]), dtype=np.float32).tobytes())
print(len(m.cells), m.cells[0].type, len(m.points), len(tri), int((uc == 2).all()),
      int((dc == 1).all()), int(abs(np.linalg.norm(n, axis=1) - 1).max() < 1e-5), int(vol > 0))
)";

// Reads every mesh in a directory (not the temporaries): prints "whole N" if each is a closed
// triangle mesh meshio reads, else the first that is not.
const char* kMeshioAll = R"(import sys, os, numpy as np, meshio
n = 0
for name in sorted(os.listdir(sys.argv[1])):
    if ".partial-" in name: continue
    tri = meshio.read(os.path.join(sys.argv[1], name)).cells_dict["triangle"]
    d = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    _, uc = np.unique(np.sort(d, axis=1), axis=0, return_counts=True)
    if len(tri) == 0 or not (uc == 2).all(): print("broken", name); sys.exit(0)
    n += 1
print("whole", n)
)";

class MeshCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = test::makeTempDir();
    std::ofstream(dir_ + "/tiny.json") << test::tinyCacheScene(0.1, 100);
    cache_ = dir_ + "/tiny.h5";
    runOutput_ = runShell(sphsplat("run '" + dir_ + "/tiny.json' --threads 1 -o '" + cache_ + "'"));
    std::ofstream(dir_ + "/check.py") << kMeshioCheck;
    std::ofstream(dir_ + "/all.py") << kMeshioAll;
  }
  static test::CommandResult check(const std::string& mesh) {
    return runShell("/usr/bin/python3 '" + dir_ + "/check.py' '" + mesh + "' '" + mesh + ".xyz'");
  }
  static std::string dir_, cache_;
  static test::CommandResult runOutput_;
};
std::string MeshCli::dir_, MeshCli::cache_;
test::CommandResult MeshCli::runOutput_;

TEST_F(MeshCli, PlyAndObjOfAFrameReadBackThroughMeshioClosedAndEqual) {
  ASSERT_EQ(runOutput_.exitCode, 0) << runOutput_.output;
  ASSERT_EQ(runShell("/usr/bin/python3 -c 'import meshio'").exitCode, 0)
      << "python3-meshio is missing: scripts/setup installs it";
  const std::string ply = dir_ + "/f7.ply", obj = dir_ + "/f7.obj";
  auto r = runShell(sphsplat("mesh '" + cache_ + "' --frames 7 --out '" + ply + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.rfind("wrote " + ply + ": ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(" triangles, "), std::string::npos) << r.output;
  EXPECT_EQ(lineCount(r.output), 1u) << r.output;
  r = runShell(sphsplat("mesh '" + cache_ + "' -f 7 -o '" + obj + "' -q"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output, "");
  const auto fromPly = check(ply), fromObj = check(obj);
  ASSERT_EQ(fromPly.exitCode, 0) << fromPly.output;
  ASSERT_EQ(fromObj.exitCode, 0) << fromObj.output;
  // One triangle block, closed and consistently wound, unit normals, outward (positive volume).
  std::istringstream words(fromPly.output);
  std::string blocks, type, points, triangles, closed, wound, unit, outward;
  words >> blocks >> type >> points >> triangles >> closed >> wound >> unit >> outward;
  EXPECT_EQ(blocks + " " + type, "1 triangle") << fromPly.output;
  EXPECT_GT(std::stoi(triangles), 200) << fromPly.output;
  EXPECT_EQ(closed + wound + unit + outward, "1111") << fromPly.output;
  // The OBJ holds the same mesh: the same counts, float32 positions and normals bit for bit.
  EXPECT_EQ(fromObj.output, fromPly.output);
  EXPECT_EQ(test::readFile(ply + ".xyz"), test::readFile(obj + ".xyz"));
  // Binary little-endian PLY with the normals and a comment naming the source.
  const std::string head = test::readFile(ply).substr(0, 600);
  EXPECT_NE(head.find("format binary_little_endian 1.0\n"), std::string::npos) << head;
  EXPECT_NE(head.find("property float nx\n"), std::string::npos) << head;
  EXPECT_NE(head.find("comment cache " + cache_ + ", frame 7 (t = 0.07 s)"), std::string::npos)
      << head;
}

TEST_F(MeshCli, SequencesAreNamedAsExportNamesThem) {
  ASSERT_EQ(runOutput_.exitCode, 0) << runOutput_.output;
  // A directory: SCENE_NNNNN.ply, a line per tenth of the frames and a summary.
  const std::string seq = dir_ + "/seq/";
  auto r = runShell(sphsplat("mesh '" + cache_ + "' --frames all --out '" + seq + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (int f = 0; f <= 10; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "tiny_%05d.ply", f);
    EXPECT_TRUE(test::fileExists(seq + name)) << name;
  }
  EXPECT_NE(r.output.find("tiny 100%  frame 10 (11 of 11)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("wrote 11 ply files " + seq + "tiny_00000.ply .. tiny_00010.ply"),
            std::string::npos)
      << r.output;
  // A pattern, -1 and ranges; the format from the pattern's extension.
  r = runShell(sphsplat("mesh '" + cache_ + "' --frames 2:4 --out '" + dir_ + "/w_%03d.obj'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* name : {"w_002.obj", "w_003.obj", "w_004.obj"})
    EXPECT_TRUE(test::fileExists(dir_ + "/" + name)) << name;
  EXPECT_FALSE(test::fileExists(dir_ + "/w_005.obj"));
  r = runShell(sphsplat("mesh '" + cache_ + "' --frames -1 --out '" + dir_ + "/last.obj'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("of frame 10 "), std::string::npos) << r.output;
  // No temporary is left behind.
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir_))
    EXPECT_EQ(entry.path().string().find(".partial-"), std::string::npos) << entry.path();
}

TEST_F(MeshCli, RefusalsAreOneLineWithExitCode2AndWriteNothing) {
  ASSERT_EQ(runOutput_.exitCode, 0) << runOutput_.output;
  const std::string out = dir_ + "/refused.ply";
  struct Case {
    std::string args, says;
  };
  // Names the system cannot look up: a symlink loop, a component over 255 bytes.
  const std::string loop = dir_ + "/loop", longName = dir_ + "/" + std::string(300, 'a');
  std::filesystem::create_symlink("loop", loop);
  const Case cases[] = {
      {"--frames 1 --out '" + loop + "'", "does not say which"},
      {"--frames 1 --out '" + loop + "/x.ply'", "Too many levels of symbolic links"},
      {"--frames 1 --out '" + longName + ".ply'", "File name too long"},
      {"--frames 1:2 --out '" + longName + "/'", "File name too long"},
      {"--frames 99 --out '" + out + "'", "--frames"},
      {"--frames x --out '" + out + "'", "--frames"},
      {"--frames 3:1 --out '" + out + "'", "--frames"},
      {"--frames all --out '" + out + "'", "frames need one file each"},
      {"--frames 1 --out '" + dir_ + "/a.stl'", "--format: expected ply or obj"},
      {"--frames 1 --format stl --out '" + out + "'", "--format"},
      {"--frames 1 --cell 0 --out '" + out + "'", "--cell"},
      {"--frames 1 --out ''", "--out: expected a file"},
      {"--frames 1 --format ply --out '" + cache_ + "'", "the cache being meshed"},
  };
  for (const Case& c : cases) {
    const auto r = runShell(sphsplat("mesh '" + cache_ + "' " + c.args));
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.output;
    EXPECT_EQ(lineCount(r.output), 1u) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(test::fileExists(out)) << c.args;
  }
  const auto missing = runShell(sphsplat("mesh '" + dir_ + "/none.h5' --out '" + out + "'"));
  EXPECT_EQ(missing.exitCode, 2) << missing.output;

  // An existing output stays as it was without --overwrite, in a sequence too: nothing written.
  std::ofstream(out) << "keep";
  auto r = runShell(sphsplat("mesh '" + cache_ + "' --frames 5 --out '" + out + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find(out + ": already exists; pass --overwrite to replace it"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(test::readFile(out), "keep");
  const std::string seq = dir_ + "/seq2";
  std::filesystem::create_directories(seq);
  std::ofstream(seq + "/tiny_00003.ply") << "keep";
  r = runShell(sphsplat("mesh '" + cache_ + "' --frames 1:4 --out '" + seq + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_FALSE(test::fileExists(seq + "/tiny_00001.ply")) << "checked before the first write";
  r = runShell(sphsplat("mesh '" + cache_ + "' --frames 5 --out '" + out + "' --overwrite"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(test::readFile(out).substr(0, 4), "ply\n");
}

// kill -9 at some moment of a sequence: each file under its own name is whole (written under a
// temporary name and renamed once complete); at most the temporary of the frame in progress is
// left. Three moments, taken from the run's own progress (once 1, 4 and 8 of its 11 files are
// there), not from a clock, which a slow build (sanitizers) or a loaded machine would outrun; at
// least one run must really have been killed between its first file and its last.
TEST_F(MeshCli, AKillLeavesOnlyWholeFiles) {
  ASSERT_EQ(runOutput_.exitCode, 0) << runOutput_.output;
  int killed = 0;
  for (const char* done : {"1", "4", "8"}) {
    const std::string out = dir_ + "/killed_" + done + "/";
    const auto r = runShell(
        "(" +
        sphsplat("mesh '" + cache_ + "' --frames all --cell 0.05 --format obj -q --out '" + out +
                 "'") +
        ") & pid=$!; for i in $(seq 3000); do [ $(ls '" + out +
        "' 2>/dev/null | grep -c '[0-9]\\.obj$') -ge " + done +
        " ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.02; done; kill -9 $pid "
        "2>/dev/null; wait $pid; echo rc=$?");
    const bool wasKilled = r.output.find("rc=137") != std::string::npos;
    std::filesystem::create_directories(out);
    const auto whole = runShell("/usr/bin/python3 '" + dir_ + "/all.py' '" + out + "'");
    EXPECT_EQ(whole.output.rfind("whole ", 0), 0u) << done << " files: " << whole.output;
    // Killed after some files were done and before the last: the case that matters.
    killed += wasKilled && whole.output.rfind("whole 0", 0) != 0 &&
              whole.output.rfind("whole 11", 0) != 0;
    std::size_t temporaries = 0;
    for (const auto& entry : std::filesystem::directory_iterator(out))
      temporaries += entry.path().filename().string().find(".partial-") != std::string::npos;
    EXPECT_LE(temporaries, 1u) << done;
  }
  EXPECT_GE(killed, 1) << "every run finished before its kill, or was killed before its first file";
}

}  // namespace
}  // namespace sph
