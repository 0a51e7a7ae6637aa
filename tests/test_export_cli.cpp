// `sphsplat export` as a user meets it: exact CSV and PLY, VTU that meshio reads back bit for bit,
// whole sequences with the frame syntax of `render`, and never a write over the cache it reads
// or a half-written output.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "io/cache/CacheReader.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using test::lineCount;
using test::readFile;
using test::runShell;
using test::sphsplatShell;

class ExportCli : public test::TinyCacheSuite {};

TEST_F(ExportCli, ExportWritesExactCsvAndPly) {
  const io::cache::CacheReader reader(cache_);
  const Particles frame = reader.readFrame(7);
  const std::string csv = dir_ + "/f7.csv", ply = dir_ + "/f7.ply";
  auto r =
      runShell(sphsplatShell("export '" + cache_ + "' --frame 7 --format csv -o '" + csv + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::istringstream in(readFile(csv));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line,
            "x [m],y [m],z [m],vx [m/s],vy [m/s],vz [m/s],rho [kg/m^3],p [Pa],id");  // units
  std::size_t rows = 0;
  while (std::getline(in, line)) {
    float values[8];
    unsigned id = 0;
    ASSERT_EQ(
        std::sscanf(line.c_str(), "%f,%f,%f,%f,%f,%f,%f,%f,%u", &values[0], &values[1], &values[2],
                    &values[3], &values[4], &values[5], &values[6], &values[7], &id),
        9)
        << line;
    EXPECT_EQ(std::memcmp(&values[0], &frame.x[rows], 4), 0)
        << "row " << rows;  // the same float bits
    EXPECT_EQ(values[6], frame.rho[rows]);
    EXPECT_EQ(id, frame.id[rows]);
    ++rows;
  }
  EXPECT_EQ(rows, frame.size());
  r = runShell(sphsplatShell("export '" + cache_ + "' --frame last --format ply --fields rho -o '" +
                             ply + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::string text = readFile(ply);
  EXPECT_EQ(text.rfind("ply\nformat ascii 1.0\n", 0), 0u);
  EXPECT_NE(text.find("element vertex 98\nproperty float x\nproperty float y\nproperty float "
                      "z\nproperty float rho\nend_header\n"),
            std::string::npos)
      << text.substr(0, 300);
  r = runShell(sphsplatShell("export '" + cache_ + "' --boundary --format csv -o -"));
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_EQ(lineCount(r.output), 1 + reader.summary().boundaryParticles);
}

// The output is compared with the cache as a file, not by its name: compared by name, an output
// that named the cache by another path (relative, dotted, a symbolic or hard link) let `export`
// write CSV over the cache it read. Not even --overwrite lets `export` write over its cache or its
// sidecar, or `run` over its scene.
TEST_F(ExportCli, ExportNeverWritesOverTheCacheWhateverPathNamesIt) {
  const std::string before = readFile(cache_);
  ASSERT_EQ(symlink(cache_.c_str(), (dir_ + "/link.h5").c_str()), 0);
  ASSERT_EQ(link(cache_.c_str(), (dir_ + "/hard.h5").c_str()), 0);
  const std::string relative = "./" + cache_.substr(cache_.find_last_of('/') + 1);
  for (const std::string& other :
       {relative, dir_ + "/./tiny.h5", dir_ + "/link.h5", dir_ + "/hard.h5"}) {
    const auto r =
        runShell("cd '" + dir_ + "' && " +
                 sphsplatShell("export tiny.h5 --format csv --overwrite -o '" + other + "'"));
    EXPECT_EQ(r.exitCode, 2) << other << "\n" << r.output;
    EXPECT_EQ(r.output, "sphsplat: " + other +
                            ": is the cache being exported (tiny.h5); refusing to write over it, "
                            "even with --overwrite\n");
  }
  const auto sidecar = runShell(sphsplatShell(
      "export '" + cache_ + "' --format csv --overwrite -o '" + dir_ + "/tiny.xdmf'"));
  EXPECT_EQ(sidecar.exitCode, 2) << sidecar.output;
  EXPECT_EQ(readFile(cache_), before) << "the cache was touched";
  EXPECT_EQ(io::cache::CacheReader(cache_).frameCount(), 11u);
  unlink((dir_ + "/link.h5").c_str()), unlink((dir_ + "/hard.h5").c_str());
  // `run --overwrite` never writes its cache over the scene it runs (a hard link here).
  ASSERT_EQ(link(scene_.c_str(), (dir_ + "/scene-link.h5").c_str()), 0);
  const std::string sceneText = readFile(scene_);
  const auto run =
      runShell(sphsplatShell("run '" + scene_ + "' --overwrite -o '" + dir_ + "/scene-link.h5'"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("is the scene file being run"), std::string::npos) << run.output;
  EXPECT_EQ(readFile(scene_), sceneText);
  unlink((dir_ + "/scene-link.h5").c_str());
}

TEST_F(ExportCli, ExportAsksBeforeReplacingAndNeverLeavesAHalfWrittenFile) {
  const std::string out = dir_ + "/exists.csv";
  std::ofstream(out) << "keep me\n";
  auto r = runShell(sphsplatShell("export '" + cache_ + "' -o '" + out + "'"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.output, "sphsplat: " + out + ": already exists; pass --overwrite to replace it\n");
  EXPECT_EQ(readFile(out), "keep me\n");
  // A write that fails half-way (the file size limit stands in for a full disk): exit 2, the old
  // file untouched, no temporary left.
  const std::string folder = test::makeTempDir();
  const std::string kept = folder + "/f.csv";
  std::ofstream(kept) << "keep me\n";
  r = runShell("trap '' XFSZ; ulimit -f 4; " +
               sphsplatShell("export '" + cache_ + "' --frame 7 --overwrite -o '" + kept + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_EQ(r.output, "sphsplat: " + kept +
                          ": cannot write the file (File too large); nothing was written to it\n");
  EXPECT_EQ(readFile(kept), "keep me\n");
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    files += !entry.is_directory();
  EXPECT_EQ(files, 1u) << "a temporary was left behind";
  r = runShell(sphsplatShell("export '" + cache_ + "' --frame 7 --overwrite -o '" + kept + "'"));
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(lineCount(readFile(kept)), 1 + io::cache::CacheReader(cache_).readFrame(7).size());
}

// A python3 script that reads a .vtu with meshio and writes each array's raw bytes to DIR/NAME.bin
// plus a line describing cells and the time.
const char* kMeshioDump = R"(import sys, numpy as np, meshio
m = meshio.read(sys.argv[1])
out = sys.argv[2]
open(out + "/points.bin", "wb").write(np.ascontiguousarray(m.points).tobytes())
for name, a in m.point_data.items():
    open(out + "/" + name + ".bin", "wb").write(np.ascontiguousarray(a).tobytes())
block = m.cells[0]
print(block.type, len(m.cells), len(block.data),
      int((block.data.ravel() == np.arange(len(m.points))).all()),
      m.points.dtype, " ".join(sorted(m.point_data)), repr(float(m.field_data["TimeValue"][0])))
)";

// The bytes of a float array, and of three interleaved into x0 y0 z0 x1 ...
std::string bytesOf(const std::vector<float>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
}
std::string interleaved(const std::vector<float>& a, const std::vector<float>& b,
                        const std::vector<float>& c) {
  std::vector<float> v;
  for (std::size_t i = 0; i < a.size(); ++i) v.insert(v.end(), {a[i], b[i], c[i]});
  return bytesOf(v);
}

TEST_F(ExportCli, ExportVtuReadsBackExactlyThroughMeshio) {
  ASSERT_EQ(runShell("/usr/bin/python3 -c 'import meshio'").exitCode, 0)
      << "python3-meshio is missing: scripts/setup installs it";
  const io::cache::CacheReader reader(cache_);
  const Particles frame = reader.readFrame(7);
  const std::string vtu = dir_ + "/f7.vtu";
  auto r = runShell(
      sphsplatShell("export '" + cache_ + "' --frame 7 -o '" + vtu + "'"));  // format from the name
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output, "wrote " + vtu + ": 98 particles of frame 7 (t = 0.07 s), vtu\n");
  const std::string script = dir_ + "/dump.py", arrays = test::makeTempDir();
  std::ofstream(script) << kMeshioDump;
  r = runShell("/usr/bin/python3 '" + script + "' '" + vtu + "' '" + arrays + "'");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  // One vertex cell per point, in order; every field; the frame's time.
  EXPECT_EQ(r.output, "vertex 1 98 1 float32 id p rho velocity 0.07\n");
  EXPECT_EQ(readFile(arrays + "/points.bin"), interleaved(frame.x, frame.y, frame.z));
  EXPECT_EQ(readFile(arrays + "/velocity.bin"), interleaved(frame.vx, frame.vy, frame.vz));
  EXPECT_EQ(readFile(arrays + "/rho.bin"), bytesOf(frame.rho));
  EXPECT_EQ(readFile(arrays + "/p.bin"), bytesOf(frame.p));
  EXPECT_EQ(readFile(arrays + "/id.bin"),
            std::string(reinterpret_cast<const char*>(frame.id.data()), frame.id.size() * 4));
  // Well-formed XML, as a strict parser (expat, which ParaView reads it with) takes it: appended
  // raw bytes are not, and an up-to-date expat makes ParaView 5.11 read such a file as empty.
  r = runShell("/usr/bin/python3 -c 'import sys, xml.etree.ElementTree as t; "
               "print(len(t.parse(sys.argv[1]).getroot().iter(\"DataArray\").__next__().text))' '" +
               vtu + "'");
  EXPECT_EQ(r.exitCode, 0) << r.output;
}

TEST_F(ExportCli, ExportWritesASequenceWithTheFrameSyntaxOfRender) {
  // -1 and ranges, which `render` and `compare` took and `export` refused.
  const std::string last = dir_ + "/last.csv";
  auto r = runShell(sphsplatShell("export '" + cache_ + "' --frames -1 -o '" + last + "'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(lineCount(readFile(last)), 1u + 98u);
  const std::string seq = dir_ + "/seq";
  r = runShell(
      sphsplatShell("export '" + cache_ + "' --frames all -o '" + seq + "/frame_%05d.vtu'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output, "wrote 11 vtu files " + seq +
                          "/frame_00000.vtu .. frame_00010.vtu: frames 0-10 (t = 0 - 0.1 s), "
                          "96-98 particles each; open " +
                          seq + "/frame.pvd in ParaView for the times\n");
  const std::string pvd = readFile(seq + "/frame.pvd");
  EXPECT_NE(pvd.find("<DataSet timestep=\"0.070000000000000007\" part=\"0\" "
                     "file=\"frame_00007.vtu\"/>"),
            std::string::npos)
      << pvd;
  std::size_t entries = 0;
  for (std::size_t at = pvd.find("<DataSet"); at != std::string::npos;
       at = pvd.find("<DataSet", at + 1))
    ++entries;
  EXPECT_EQ(entries, 11u);
  for (int f = 0; f <= 10; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%05d.vtu", f);
    EXPECT_TRUE(test::fileExists(seq + name)) << name;
  }
  // A directory: SCENE_NNNNN.FORMAT; a range; and a second run needs --overwrite for all.
  r = runShell(
      sphsplatShell("export '" + cache_ + "' --frames 2:4 --format ply -o '" + dir_ + "/plys/'"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(test::fileExists(dir_ + "/plys/tiny_00004.ply"));
  EXPECT_FALSE(test::fileExists(dir_ + "/plys/tiny_00005.ply"));
  r = runShell(
      sphsplatShell("export '" + cache_ + "' --frames 2:5 --format ply -o '" + dir_ + "/plys/'"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.output, "sphsplat: " + dir_ +
                          "/plys/tiny_00002.ply: already exists; pass --overwrite to replace it\n");
  EXPECT_FALSE(test::fileExists(dir_ + "/plys/tiny_00005.ply")) << "checked before writing";
  // Several frames into one named file is refused, saying how to name them.
  r = runShell(sphsplatShell("export '" + cache_ + "' --frames 0:3 -o '" + dir_ + "/one.vtu'"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.output, "sphsplat: -o " + dir_ +
                          "/one.vtu: 4 frames need one file each: give a name with %05d where the "
                          "frame number goes (e.g. out/frame_%05d.vtu) or a directory (ending in "
                          "/)\n");
}

}  // namespace
}  // namespace sph
