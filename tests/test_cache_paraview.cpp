// The cache as ParaView reads it and shows it (docs/cache-format.md, "Opening it"), with ParaView
// itself: the sidecar `run.xdmf` through the three readers ParaView offers for it (Xdmf3ReaderS,
// its default, Xdmf3ReaderT and the older XDMFReader), `run.h5` through the H5Part reader and the
// `.pvd` of `sphsplat export --frames all --format vtu`. Every time step, every point and every
// array value must equal what the cache holds, and the boundary particles must show at every time
// beside the fluid. ParaView draws cells, not bare points: every block must give a cell per point,
// and each reader's output, shown as ParaView shows it, must draw pixels in a picture.
//
// Needs pvpython: scripts/setup installs Debian's paraview and unpacks python3-paraview under
// build/paraview (scripts/pvpython); an installed pvpython also does. Skipped without one.
// SPHSPLAT_PVPYTHON names another command to run the probe with. Debian's ParaView draws through
// X alone (no EGL or OSMesa build; without a display pvpython crashes when it renders), so the
// suite starts an Xvfb of its own (scripts/setup installs it) and skips without one.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/cache/RainCache.h"
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

// An X server of the suite's own for pvpython to draw into. Xvfb picks a free display itself
// and writes its number once it accepts connections (-displayfd), so suites started side by side
// never race for one; it is stopped by its pid, and dies with the test program if that dies first.
class VirtualDisplay {
 public:
  // The display, or null with the reason in `why` (no Xvfb, or it did not come up in 30 s).
  static std::unique_ptr<VirtualDisplay> start(std::string& why) {
    int ready[2];
    if (pipe2(ready, O_CLOEXEC) != 0) {
      why = "cannot make a pipe";
      return nullptr;
    }
    const std::string fd = std::to_string(ready[1]);  // the child makes no allocation
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid == 0) {
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent) _exit(1);
      fcntl(ready[1], F_SETFD, 0);  // for Xvfb
      const int quiet = ::open("/dev/null", O_WRONLY);
      dup2(quiet, STDOUT_FILENO), dup2(quiet, STDERR_FILENO);
      // Xvfb resets when its last client leaves and writes its number again, into a pipe no one
      // reads any more: no reset, and no SIGPIPE should it write.
      signal(SIGPIPE, SIG_IGN);
      execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-noreset", "-screen", "0", "640x480x24",
             "-nolisten", "tcp", static_cast<char*>(nullptr));
      _exit(127);
    }
    ::close(ready[1]);
    // "N\n" once it accepts connections; end of file if it exits first.
    std::string number;
    char c = 0;
    pollfd in{ready[0], POLLIN, 0};
    while (pid > 0 && poll(&in, 1, 30000) == 1 && ::read(ready[0], &c, 1) == 1 && c != '\n')
      number += c;
    ::close(ready[0]);
    if (pid < 0) {
      why = "cannot fork";
      return nullptr;
    }
    auto display = std::unique_ptr<VirtualDisplay>(new VirtualDisplay(pid, ":" + number));
    if (c != '\n' || number.empty()) {
      why = "Xvfb did not start (Debian: apt-get install xvfb)";
      return nullptr;  // display's destructor stops it if it runs
    }
    return display;
  }
  ~VirtualDisplay() {
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
  }
  const std::string& name() const { return name_; }

 private:
  VirtualDisplay(pid_t pid, std::string name) : pid_(pid), name_(std::move(name)) {}
  pid_t pid_;
  std::string name_;
};

// Loads the sidecar with each XDMF reader, the cache with the H5Part reader and the export's
// .pvd, and writes what each one gives per time step: its leaf datasets, with their points, cells
// and point arrays in full. Then it shows each reader's output as ParaView's Show does (the
// defaults, what a user gets after Apply) at the last time, draws it into a 400x300 picture and
// counts the pixels that are not the background.
constexpr const char* kProbe = R"(import json, sys
import numpy
from paraview.simple import *
from paraview import servermanager as sm
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

xdmf, h5, pvd, out, pictures = sys.argv[1:6]

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
    return {'points': points, 'cells': ds.GetNumberOfCells(), 'arrays': arrays}

view = CreateView('RenderView')
view.ViewSize = [400, 300]
view.OrientationAxesVisibility = 0  # its pixels are not the data's

def drawn(reader, time, png):
    view.ViewTime = time
    Show(reader, view)
    view.ResetCamera()
    Render(view)
    SaveScreenshot(png, view, ImageResolution=[400, 300])
    Hide(reader, view)
    image = vtkPNGReader()
    image.SetFileName(png)
    image.Update()
    rgb = vtk_to_numpy(image.GetOutput().GetPointData().GetScalars())[:, :3]
    # The background is the most frequent colour (whatever the palette).
    colours, counts = numpy.unique(rgb, axis=0, return_counts=True)
    return int((rgb != colours[counts.argmax()]).any(axis=1).sum())

readers = [('Xdmf3ReaderS', lambda: Xdmf3ReaderS(FileName=xdmf)),
           ('Xdmf3ReaderT', lambda: Xdmf3ReaderT(FileName=xdmf)),
           ('XDMFReader', lambda: XDMFReader(FileNames=[xdmf])),
           ('H5PartReader', lambda: H5PartReader(FileName=h5)),
           ('PVDReader', lambda: PVDReader(FileName=pvd))]
result = {}
for name, make in readers:
    reader = make()
    times = list(reader.TimestepValues)
    frames = []
    for t in times:
        reader.UpdatePipeline(t)
        frames.append([describe(leaf) for leaf in leaves(sm.Fetch(reader))])
    png = pictures + '_' + name + '.png'
    result[name] = {'times': times, 'frames': frames, 'picture': png,
                    'pixels': drawn(reader, times[-1], png)}
    Delete(reader)
json.dump(result, open(out, 'w'))
)";

class CacheParaView : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!pvpython().empty()) display_ = VirtualDisplay::start(noDisplay_);
  }
  static void TearDownTestSuite() { display_.reset(); }

  void SetUp() override {
    command_ = pvpython();
    if (command_.empty()) {
      GTEST_SKIP() << "pvpython not found: install Debian's paraview and python3-paraview to "
                      "check the cache with ParaView's readers (or set SPHSPLAT_PVPYTHON)";
    }
    if (!display_) GTEST_SKIP() << "no X display for ParaView to draw into: " << noDisplay_;
    dir_ = test::makeTempDir();
  }

  // Runs `scene`, exports its frames as VTK files, then every reader on the result; returns their
  // description (json above).
  json readWithParaView(const std::string& scene, const std::string& name) {
    const std::string base = dir_ + "/" + name;
    std::ofstream(base + ".json") << scene;
    const auto run = runShell(
        test::sphsplatShell("run '" + base + ".json' --threads 1 --quiet -o '" + base + ".h5'"));
    EXPECT_EQ(run.exitCode, 0) << run.output;
    const auto vtk =
        runShell(test::sphsplatShell("export '" + base + ".h5' --frames all --format vtu -o '" +
                                     dir_ + "/vtk/" + name + "_%05d.vtu'"));
    EXPECT_EQ(vtk.exitCode, 0) << vtk.output;
    std::ofstream(dir_ + "/probe.py") << kProbe;
    // An absolute path: ParaView 5.11's Xdmf3 readers look for the HDF5 file beside a sidecar
    // named with no directory in the wrong place.
    const auto probe =
        runShell("DISPLAY=" + display_->name() + " " + command_ + " '" + dir_ + "/probe.py' '" +
                 base + ".xdmf' '" + base + ".h5' '" + dir_ + "/vtk/" + name + ".pvd' '" + base +
                 ".out.json' '" + base + "' 2>&1");
    EXPECT_EQ(probe.exitCode, 0) << probe.output;
    // What ParaView 5.11 printed for each frame of the sidecar before the [n][3] views.
    EXPECT_EQ(probe.output.find("Skipping unrecognized array type"), std::string::npos)
        << probe.output;
    return json::parse(readFile(base + ".out.json"));
  }

  static std::unique_ptr<VirtualDisplay> display_;
  static std::string noDisplay_;
  std::string command_, dir_;
};
std::unique_ptr<VirtualDisplay> CacheParaView::display_;
std::string CacheParaView::noDisplay_;

// What a user sees of each reader's output. ParaView draws cells, not bare points: every block
// of every time step must hold a cell per point. And the last time step, shown with ParaView's
// defaults, must put at least as many pixels on the picture as it has points: each point is a
// dot of 2x2 pixels (ParaView's default point size), and in these small scenes seen from its
// default camera few hide behind others (2 to 4.5 pixels a point measured), so this fails when
// half of them are missing, and an empty view has none.
void expectWhatAUserSees(const json& readers) {
  for (const auto& [name, r] : readers.items()) {
    SCOPED_TRACE(name);
    const json& frames = r.at("frames");
    std::size_t blocks = 0, drawable = 0;
    std::string firstNot;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      for (const json& leaf : frames[k]) {
        const std::size_t points = leaf.at("points").size();
        const auto cells = leaf.at("cells").get<std::size_t>();
        ++blocks;
        if (cells == points) {
          ++drawable;
        } else if (firstNot.empty()) {
          firstNot = "frame " + std::to_string(k) + ": " + std::to_string(points) + " points, " +
                     std::to_string(cells) + " cells";
        }
      }
    }
    EXPECT_EQ(drawable, blocks) << "blocks with a cell per point, of all time steps; the first "
                                   "without: "
                                << firstNot;
    std::size_t shown = 0;
    for (const json& leaf : frames.back()) shown += leaf.at("points").size();
    EXPECT_GE(r.at("pixels").get<std::size_t>(), shown)
        << "pixels drawn for " << shown << " points: " << r.at("picture").get<std::string>();
  }
}

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
                                 "Xdmf3ReaderS", "Xdmf3ReaderT", "XDMFReader", "H5PartReader",
                                 "PVDReader"}) {
  const io::cache::CacheReader cache(cachePath);
  const std::vector<std::vector<float>> boundary = cache.readBoundary();
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const json& r = readers.at(name);
    const bool h5part = name == "H5PartReader";
    const bool xdmf = !h5part && name != "PVDReader";
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
      if (xdmf) {
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
  expectWhatAUserSees(readers);
  expectWhatTheCacheHolds(readers, dir_ + "/tiny.h5");
}

TEST_F(CacheParaView, AnEmptyFirstFrameShowsTheBoundaryAlone) {
  // Only a nozzle: frame 0 holds no particle (a pour's first frame).
  std::string scene = test::tinyCacheScene(0.05, 100);
  const std::size_t fluids = scene.find("  \"fluids\"");
  scene.erase(fluids, scene.find('\n', fluids) + 1 - fluids);
  const json readers = readWithParaView(scene, "pour");
  expectWhatAUserSees(readers);
  ASSERT_EQ(io::cache::CacheReader(dir_ + "/pour.h5").readFrame(0).size(), 0u);
  expectWhatTheCacheHolds(readers, dir_ + "/pour.h5");
}

TEST_F(CacheParaView, RainDropsShowAsAThirdPointSetBesideFluidAndBoundary) {
  // A scene with rain (docs/rain.md): every frame's drops are a point set of their own in the
  // sidecar; the H5Part reader and the exported files show the fluid alone (one particle set).
  std::string scene = test::tinyCacheScene(0.05, 100);
  scene.insert(
      scene.find("  \"output\""),
      R"(  "camera": {"position": [0.5, 0.4, 0.5], "target": [0.1, 0.05, 0.075], "fov": 40},
  "rain": {"count": 50, "near": 0.05, "far": 1, "seed": 3},
)");
  const json readers = readWithParaView(scene, "rain");
  expectWhatAUserSees(readers);
  const io::cache::CacheReader cache(dir_ + "/rain.h5");
  const std::vector<std::vector<float>> boundary = cache.readBoundary();
  for (const char* name : {"Xdmf3ReaderS", "Xdmf3ReaderT", "XDMFReader"}) {
    SCOPED_TRACE(name);
    const json& r = readers.at(name);
    ASSERT_EQ(r.at("times").size(), cache.frameCount());
    for (std::size_t k = 0; k < cache.frameCount(); ++k) {
      SCOPED_TRACE("frame " + std::to_string(k));
      const io::cache::RainFrame rain = io::cache::readRainFrame(cache, k);
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
  expectWhatTheCacheHolds(readers, dir_ + "/rain.h5", {"H5PartReader", "PVDReader"});
}

}  // namespace
}  // namespace sph
