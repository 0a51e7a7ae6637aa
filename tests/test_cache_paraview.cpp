// The cache as ParaView reads it (docs/cache-format.md, "Opening it"), with ParaView itself: the
// sidecar `run.xdmf` through the three readers ParaView offers for it (Xdmf3ReaderS, its
// default, Xdmf3ReaderT and the older XDMFReader), and `run.h5` through the H5Part reader. Every
// time step, every point and every array value must equal what the cache holds, and the boundary
// particles must show at every time beside the fluid.
//
// Needs pvpython: scripts/setup installs Debian's paraview and unpacks python3-paraview under
// build/paraview (scripts/pvpython); an installed pvpython also does. Skipped without one.
// SPHSPLAT_PVPYTHON names another command to run the probe with.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/CacheReader.h"
#include "io/RainCache.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using nlohmann::json;
using test::readFile;
using test::runShell;

// The ParaView that scripts/setup unpacks (build/paraview, run by scripts/pvpython), else an
// installed pvpython, else none.
std::string pvpython() {
  if (const char* command = std::getenv("SPHSPLAT_PVPYTHON")) return command;
  if (test::fileExists(test::sourcePath("build/paraview/usr/bin/pvpython")))
    return test::sourcePath("scripts/pvpython");
  return runShell("command -v pvpython >/dev/null 2>&1").exitCode == 0 ? "pvpython" : "";
}

// Loads the sidecar with each XDMF reader and the cache with the H5Part reader, and writes what
// each one gives per time step: its leaf datasets, with their points and point arrays in full.
constexpr const char* kProbe = R"(import json, sys
from paraview.simple import *
from paraview import servermanager as sm
from vtkmodules.util.numpy_support import vtk_to_numpy

xdmf, h5, out = sys.argv[1:4]

def leaves(obj):
    if obj is None:
        return []
    if obj.IsA('vtkMultiBlockDataSet'):
        return [l for i in range(obj.GetNumberOfBlocks()) for l in leaves(obj.GetBlock(i))]
    if obj.IsA('vtkMultiPieceDataSet'):
        return [l for i in range(obj.GetNumberOfPieces()) for l in leaves(obj.GetPiece(i))]
    return [obj]

def describe(ds):
    n = ds.GetNumberOfPoints()
    points = vtk_to_numpy(ds.GetPoints().GetData()).tolist() if n else []
    pd = ds.GetPointData()
    arrays = {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)).tolist()
              for i in range(pd.GetNumberOfArrays())}
    return {'points': points, 'arrays': arrays}

readers = [('Xdmf3ReaderS', lambda: Xdmf3ReaderS(FileName=xdmf)),
           ('Xdmf3ReaderT', lambda: Xdmf3ReaderT(FileName=xdmf)),
           ('XDMFReader', lambda: XDMFReader(FileNames=[xdmf])),
           ('H5PartReader', lambda: H5PartReader(FileName=h5))]
result = {}
for name, make in readers:
    reader = make()
    times = list(reader.TimestepValues)
    frames = []
    for t in times:
        reader.UpdatePipeline(t)
        frames.append([describe(leaf) for leaf in leaves(sm.Fetch(reader))])
    result[name] = {'times': times, 'frames': frames}
    Delete(reader)
json.dump(result, open(out, 'w'))
)";

class CacheParaView : public ::testing::Test {
 protected:
  void SetUp() override {
    command_ = pvpython();
    if (command_.empty()) {
      GTEST_SKIP() << "pvpython not found: install Debian's paraview and python3-paraview to "
                      "check the cache with ParaView's readers (or set SPHSPLAT_PVPYTHON)";
    }
    dir_ = test::makeTempDir();
  }

  // Runs `scene`, then every reader on the result; returns their description (json above).
  json readWithParaView(const std::string& scene, const std::string& name) {
    std::ofstream(dir_ + "/" + name + ".json") << scene;
    const auto run =
        runShell("OMP_WAIT_POLICY=PASSIVE " + test::sphsplatBinary() + " run '" + dir_ + "/" +
                 name + ".json' --threads 1 --quiet -o '" + dir_ + "/" + name + ".h5'");
    EXPECT_EQ(run.exitCode, 0) << run.output;
    std::ofstream(dir_ + "/probe.py") << kProbe;
    // An absolute path: ParaView 5.11's Xdmf3 readers look for the HDF5 file beside a sidecar
    // named with no directory in the wrong place.
    const auto probe =
        runShell(command_ + " '" + dir_ + "/probe.py' '" + dir_ + "/" + name + ".xdmf' '" + dir_ +
                 "/" + name + ".h5' '" + dir_ + "/" + name + ".out.json' 2>&1");
    EXPECT_EQ(probe.exitCode, 0) << probe.output;
    // What ParaView 5.11 printed for each frame of the sidecar before the [n][3] views.
    EXPECT_EQ(probe.output.find("Skipping unrecognized array type"), std::string::npos)
        << probe.output;
    return json::parse(readFile(dir_ + "/" + name + ".out.json"));
  }

  std::string command_, dir_;
};

// A float32 array of the cache as the doubles json holds.
std::vector<double> widened(const std::vector<float>& v) {
  return std::vector<double>(v.begin(), v.end());
}

// Every point of `leaf` equals the cache's x y z, in order.
::testing::AssertionResult samePoints(const json& leaf, const std::vector<float>& x,
                                      const std::vector<float>& y, const std::vector<float>& z) {
  const json& points = leaf.at("points");
  if (points.size() != x.size())
    return ::testing::AssertionFailure() << points.size() << " points, the cache " << x.size();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::vector<double> p = points[i].get<std::vector<double>>();
    if (p != std::vector<double>{x[i], y[i], z[i]})
      return ::testing::AssertionFailure() << "point " << i << " differs";
  }
  return ::testing::AssertionSuccess();
}

// What every reader must show of `cachePath`: its times, and per time the fluid (points and the
// arrays of `arrays`, named as that reader names them) and, for the XDMF readers, the boundary.
void expectWhatTheCacheHolds(const json& readers, const std::string& cachePath,
                             const std::vector<std::string>& names = {
                                 "Xdmf3ReaderS", "Xdmf3ReaderT", "XDMFReader", "H5PartReader"}) {
  const io::CacheReader cache(cachePath);
  const std::vector<std::vector<float>> boundary = cache.readBoundary();
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const json& r = readers.at(name);
    const bool h5part = name == "H5PartReader";
    ASSERT_EQ(r.at("times").size(), cache.frameCount());
    for (std::size_t k = 0; k < cache.frameCount(); ++k) {
      SCOPED_TRACE("frame " + std::to_string(k));
      EXPECT_EQ(r.at("times")[k].get<double>(), cache.summary().frames[k].time);
      const Particles p = cache.readFrame(k);
      const json& leaves = r.at("frames")[k];
      // The fluid is the leaf with arrays; the boundary the one without (XDMF readers only).
      const json* fluid = nullptr;
      const json* walls = nullptr;
      for (const json& leaf : leaves) (leaf.at("arrays").empty() ? walls : fluid) = &leaf;
      if (!h5part) {
        ASSERT_NE(walls, nullptr) << "no boundary block";
        EXPECT_TRUE(samePoints(*walls, boundary[0], boundary[1], boundary[2]));
      }
      if (p.size() == 0) {
        EXPECT_TRUE(fluid == nullptr || fluid->at("points").empty());
        continue;
      }
      ASSERT_NE(fluid, nullptr) << "no fluid block";
      EXPECT_TRUE(samePoints(*fluid, p.x, p.y, p.z));
      const json& a = fluid->at("arrays");
      if (h5part) {
        for (const auto& [field, values] :
             {std::pair<const char*, const std::vector<float>*>{"vx", &p.vx},
              {"vy", &p.vy},
              {"vz", &p.vz},
              {"rho", &p.rho},
              {"p", &p.p}}) {
          EXPECT_EQ(a.at(field).get<std::vector<double>>(), widened(*values)) << field;
        }
      } else {
        const auto velocity = a.at("velocity").get<std::vector<std::vector<double>>>();
        ASSERT_EQ(velocity.size(), p.size());
        for (std::size_t i = 0; i < p.size(); ++i) {
          EXPECT_EQ(velocity[i], (std::vector<double>{p.vx[i], p.vy[i], p.vz[i]})) << i;
          if (::testing::Test::HasFailure()) break;
        }
        EXPECT_EQ(a.at("rho").get<std::vector<double>>(), widened(p.rho));
        EXPECT_EQ(a.at("p").get<std::vector<double>>(), widened(p.p));
      }
      const auto ids = a.at("id").get<std::vector<double>>();
      EXPECT_EQ(ids, std::vector<double>(p.id.begin(), p.id.end()));
      if (::testing::Test::HasFailure()) return;
    }
  }
}

TEST_F(CacheParaView, EveryReaderShowsEveryFrameWithItsPointsArraysAndTime) {
  const json readers = readWithParaView(test::tinyCacheScene(0.05, 100), "tiny");
  expectWhatTheCacheHolds(readers, dir_ + "/tiny.h5");
}

TEST_F(CacheParaView, AnEmptyFirstFrameShowsTheBoundaryAlone) {
  // Only a nozzle: frame 0 holds no particle (a pour's first frame).
  std::string scene = test::tinyCacheScene(0.05, 100);
  const std::size_t fluids = scene.find("  \"fluids\"");
  scene.erase(fluids, scene.find('\n', fluids) + 1 - fluids);
  const json readers = readWithParaView(scene, "pour");
  ASSERT_EQ(io::CacheReader(dir_ + "/pour.h5").readFrame(0).size(), 0u);
  expectWhatTheCacheHolds(readers, dir_ + "/pour.h5");
}

TEST_F(CacheParaView, RainDropsShowAsAThirdPointSetBesideFluidAndBoundary) {
  // A scene with rain (docs/rain.md): every frame's drops are a point set of their own in the
  // sidecar; the H5Part reader shows the fluid alone (its format has one particle set).
  std::string scene = test::tinyCacheScene(0.05, 100);
  scene.insert(
      scene.find("  \"output\""),
      R"(  "camera": {"position": [0.5, 0.4, 0.5], "target": [0.1, 0.05, 0.075], "fov": 40},
  "rain": {"count": 50, "near": 0.05, "far": 1, "seed": 3},
)");
  const json readers = readWithParaView(scene, "rain");
  const io::CacheReader cache(dir_ + "/rain.h5");
  const std::vector<std::vector<float>> boundary = cache.readBoundary();
  for (const char* name : {"Xdmf3ReaderS", "Xdmf3ReaderT", "XDMFReader"}) {
    SCOPED_TRACE(name);
    const json& r = readers.at(name);
    ASSERT_EQ(r.at("times").size(), cache.frameCount());
    for (std::size_t k = 0; k < cache.frameCount(); ++k) {
      SCOPED_TRACE("frame " + std::to_string(k));
      const io::RainFrame rain = io::readRainFrame(cache, k);
      ASSERT_EQ(rain.positions.size(), 50u);
      std::vector<float> x, y, z;
      for (const Vec3& p : rain.positions)
        x.push_back(p.x()), y.push_back(p.y()), z.push_back(p.z());
      const Particles fluid = cache.readFrame(k);
      int drops = 0, walls = 0, water = 0;
      for (const json& leaf : r.at("frames")[k]) {
        drops += samePoints(leaf, x, y, z) ? 1 : 0;
        walls += samePoints(leaf, boundary[0], boundary[1], boundary[2]) ? 1 : 0;
        water += samePoints(leaf, fluid.x, fluid.y, fluid.z) ? 1 : 0;
      }
      EXPECT_EQ(drops, 1);
      EXPECT_EQ(walls, 1);
      EXPECT_EQ(water, 1);
      if (::testing::Test::HasFailure()) return;
    }
  }
  expectWhatTheCacheHolds(readers, dir_ + "/rain.h5", {"H5PartReader"});
}

}  // namespace
}  // namespace sph
