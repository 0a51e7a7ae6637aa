// The HDF5 cache format (docs/cache-format.md): frames written by CacheWriter read back bit for
// bit; the H5Part names, types and attributes are as documented, checked with the HDF5 C API
// rather than with our own reader; only the fields asked for are written; compression as set;
// the XDMF sidecar is well-formed XML (parsed by Python's parser) whose every dataset path exists
// in the file with the stated length (its cells' point indexes hold 0, 1, ...); rendered frames
// round-trip.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/cache/CacheWriter.h"
#include "io/cache/Hdf5.h"
#include "io/cache/XdmfWriter.h"
#include "io/scene/SceneLoader.h"
#include "sim/InputError.h"
#include "sim/Parallel.h"
#include "tests/CacheFormatSupport.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

namespace cache = io::cache;
using test::Id;
using test::openRaw;
using test::rootLinks;
using test::stringAttribute;
using test::stringKind;
using test::writeRun;
using test::WrittenRun;

class CacheFormat : public test::TempDirTest {};

TEST_F(CacheFormat, FramesAndResumeRecordsReadBackBitForBit) {
  const std::string path = dir_ + "/roundtrip.h5";
  const WrittenRun run = writeRun(path, 8);
  const io::cache::CacheReader reader(path);
  ASSERT_EQ(reader.frameCount(), 8u);
  EXPECT_EQ(reader.summary().status, "finished");
  EXPECT_EQ(reader.summary().sceneName, "tiny");
  EXPECT_EQ(reader.summary().sceneText, run.scene.sourceText);
  EXPECT_EQ(reader.summary().sceneOverrides, "solver.cfl=0.4");
  EXPECT_EQ(reader.summary().fields, cache::defaultFields());
  for (std::size_t k = 0; k < 8; ++k) {
    EXPECT_TRUE(test::sameBits(run.frames[k], reader.readFrame(k))) << "frame " << k;
    EXPECT_EQ(reader.summary().frames[k].time, run.states[k].time);
    const auto [state, fluid] = reader.readRestart(k);
    // Everything a resume needs, exactly: the arrays in memory order and the run state.
    for (cache::Field f : {cache::Field::X, cache::Field::Y, cache::Field::Z, cache::Field::VX,
                           cache::Field::VY, cache::Field::VZ, cache::Field::CollideTime}) {
      EXPECT_EQ(fluid.*cache::floatMember(f), run.frames[k].*cache::floatMember(f))
          << cache::fieldName(f);
    }
    EXPECT_EQ(fluid.id, run.frames[k].id);
    EXPECT_EQ(state.time, run.states[k].time);
    EXPECT_EQ(state.step, run.states[k].step);
    EXPECT_EQ(state.lastDt, run.states[k].lastDt);
    EXPECT_EQ(state.maxSpeed, run.states[k].maxSpeed);
    EXPECT_EQ(state.maxAcceleration, run.states[k].maxAcceleration);
    EXPECT_EQ(state.nextId, run.states[k].nextId);
    ASSERT_EQ(state.emitters.size(), 1u);
    EXPECT_EQ(state.emitters[0].travelled, run.states[k].emitters[0].travelled);
    EXPECT_EQ(state.emitters[0].emitted, run.states[k].emitters[0].emitted);
    EXPECT_EQ(state.emitters[0].started, run.states[k].emitters[0].started);
  }
  // The emitter works during the run, so frames differ in size: the layout must allow it.
  EXPECT_GT(run.frames.back().size(), run.frames.front().size());
}

TEST_F(CacheFormat, H5PartLayoutAsDocumentedThroughTheHdf5Api) {
  const std::string path = dir_ + "/layout.h5";
  const WrittenRun run = writeRun(path, 12);
  Id file(openRaw(path));
  const std::set<std::string> links = rootLinks(file);
  std::size_t steps = 0;
  for (const std::string& name : links) {
    // H5Part readers take every root group starting with "Step" for a time step.
    if (name.rfind("Step", 0) == 0) {
      EXPECT_TRUE(std::regex_match(name, std::regex("Step#(0|[1-9][0-9]*)"))) << name;
      ++steps;
    }
  }
  EXPECT_EQ(steps, 12u);
  for (std::size_t k = 0; k < 12; ++k) {
    const std::string group = "Step#" + std::to_string(k);
    ASSERT_TRUE(links.count(group)) << group;
    Id g(H5Gopen2(file, group.c_str(), H5P_DEFAULT));
    // TimeValue: a scalar double, what ParaView's H5Part reader requires.
    Id attr(H5Aopen(g, "TimeValue", H5P_DEFAULT));
    Id type(H5Aget_type(attr));
    EXPECT_TRUE(H5Tequal(type, H5T_NATIVE_DOUBLE) > 0);
    Id aspace(H5Aget_space(attr));
    EXPECT_EQ(H5Sget_simple_extent_type(aspace), H5S_SCALAR);
    double time = -1;
    H5Aread(attr, H5T_NATIVE_DOUBLE, &time);
    EXPECT_EQ(time, run.states[k].time);
    H5G_info_t info;
    H5Gget_info(g, &info);
    EXPECT_EQ(info.nlinks, 9u) << group << " holds exactly x y z vx vy vz rho p id";
    for (const char* name : {"x", "y", "z", "vx", "vy", "vz", "rho", "p", "id"}) {
      Id set(H5Dopen2(g, name, H5P_DEFAULT));
      Id space(H5Dget_space(set));
      ASSERT_EQ(H5Sget_simple_extent_ndims(space), 1) << name;
      hsize_t n = 0;
      H5Sget_simple_extent_dims(space, &n, nullptr);
      EXPECT_EQ(n, run.frames[k].size()) << group << "/" << name;
      Id dtype(H5Dget_type(set));
      const bool isId = std::string(name) == "id";
      EXPECT_TRUE(H5Tequal(dtype, isId ? H5T_STD_U32LE : H5T_IEEE_F32LE) > 0) << name;
      if (n > 0) {
        Id dcpl(H5Dget_create_plist(set));
        ASSERT_EQ(H5Pget_nfilters(dcpl), 2) << name;
        unsigned flags = 0, level = 0;
        std::size_t nvalues = 1;
        EXPECT_EQ(H5Pget_filter2(dcpl, 0, &flags, &nvalues, &level, 0, nullptr, nullptr),
                  H5Z_FILTER_SHUFFLE);
        nvalues = 1;
        EXPECT_EQ(H5Pget_filter2(dcpl, 1, &flags, &nvalues, &level, 0, nullptr, nullptr),
                  H5Z_FILTER_DEFLATE);
        EXPECT_EQ(level, 1u);  // the default: zlib's run-length strategy where sphsplat deflates
      }
    }
  }
  // The boundary once, in a group that is not a step.
  Id b(H5Gopen2(file, "Boundary", H5P_DEFAULT));
  for (const char* name : {"x", "y", "z"}) EXPECT_GT(H5Lexists(b, name, H5P_DEFAULT), 0);
  // Root attributes: the scene's full text, program version, resolved solver parameters, creation
  // time.
  EXPECT_EQ(stringAttribute(file, "scene_text"), run.scene.sourceText);
  EXPECT_EQ(stringAttribute(file, "sphsplat_version"), "test");
  EXPECT_EQ(stringAttribute(file, "sphsplat_format"), "sphsplat-cache");
  EXPECT_TRUE(
      std::regex_match(stringAttribute(file, "created"),
                       std::regex("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}Z")));
  double spacing = 0;
  Id sp(H5Aopen(file, "solver.spacing", H5P_DEFAULT));
  H5Aread(sp, H5T_NATIVE_DOUBLE, &spacing);
  EXPECT_EQ(spacing, 0.025f);
  for (const char* name : {"solver.speed_of_sound", "solver.viscosity", "solver.support_radius",
                           "solver.particle_mass"}) {
    EXPECT_GT(H5Aexists(file, name), 0) << name;
  }
  EXPECT_EQ(stringAttribute(file, "solver.eos"), "tait");
  // Strings written once are variable-length UTF-8 (h5py reads them as str); run_status is
  // rewritten in place, so it keeps a fixed width in the root header.
  for (const char* name :
       {"sphsplat_format", "sphsplat_version", "created", "scene_name", "scene_path", "scene_text",
        "scene_overrides", "scene_fingerprint", "output.fields", "solver.eos", "solver.walls"}) {
    EXPECT_EQ(stringKind(file, name), "variable UTF-8") << name;
  }
  EXPECT_EQ(stringKind(file, "run_status"), "fixed UTF-8");
}

TEST_F(CacheFormat, RootHeaderStaysOneBlockSoEachCommitIsOneWrite) {
  // Sized for 10 frames, written with 40 (a run resumed far past its planned end): the root's
  // object header must not have grown a second block (io/cache/CacheCommit.cpp, commitObjects).
  const std::string path = dir_ + "/root.h5";
  writeRun(path, 40, "", 10);
  Id file(openRaw(path));
  H5O_info_t info;
  ASSERT_GE(H5Oget_info2(file, &info, H5O_INFO_HDR), 0);
  EXPECT_EQ(info.hdr.nchunks, 1u);
  EXPECT_EQ(info.hdr.version, 2u) << "checksummed object headers";
}

// The cache's field table is checked against Particles at compile time (io/cache/CacheFormat.cpp); this
// is the same promise kept at run time: a frame written with every field gives back every array
// of Particles, bit for bit.
TEST_F(CacheFormat, EveryParticlesArrayIsADatasetThatReadsBackBitForBit) {
  const std::string path = dir_ + "/all.h5";
  const WrittenRun run = writeRun(
      path, 3,
      R"("fields": ["position", "velocity", "acceleration", "rho", "p", "collide_time", "id"])");
  const io::cache::CacheReader reader(path);
  EXPECT_EQ(reader.summary().fields.count(), cache::kFieldCount);
  const Particles read = reader.readFrame(2);
  const Particles& written = run.frames[2];
  ASSERT_GT(written.size(), 0u);
  std::vector<const void*> a, b;
  std::vector<std::size_t> bytes;
  written.forEachField([&](const auto& f) {
    a.push_back(f.data());
    bytes.push_back(f.size() * sizeof(f[0]));
  });
  read.forEachField([&](const auto& f) {
    b.push_back(f.data());
    EXPECT_EQ(f.size(), written.size());
  });
  ASSERT_EQ(a.size(), static_cast<std::size_t>(Particles::kFieldCount));
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_EQ(std::memcmp(a[k], b[k], bytes[k]), 0) << "Particles array " << k;
}

TEST_F(CacheFormat, OnlyTheFieldsAskedForAreWritten) {
  const std::string path = dir_ + "/positions.h5";
  const WrittenRun run = writeRun(path, 3, R"("fields": ["position"])");
  Id file(openRaw(path));
  Id g(H5Gopen2(file, "Step#2", H5P_DEFAULT));
  H5G_info_t info;
  H5Gget_info(g, &info);
  EXPECT_EQ(info.nlinks, 3u);
  for (const char* name : {"x", "y", "z"}) EXPECT_GT(H5Lexists(g, name, H5P_DEFAULT), 0);
  // The resume record carries what a resume needs and the frame lacks.
  Id r(H5Gopen2(file, "Restart#2", H5P_DEFAULT));
  for (const char* name : {"vx", "vy", "vz", "id"})
    EXPECT_GT(H5Lexists(r, name, H5P_DEFAULT), 0) << name;
  EXPECT_EQ(H5Lexists(r, "x", H5P_DEFAULT), 0);
  // Without a collision pass every cooldown stays at its initial value: one attribute.
  EXPECT_EQ(H5Lexists(r, "collide_time", H5P_DEFAULT), 0);
  EXPECT_GT(H5Aexists(r, "collide_time_constant"), 0);
  const io::cache::CacheReader reader(path);
  const auto [state, fluid] = reader.readRestart(2);
  EXPECT_EQ(fluid.vx, run.frames[2].vx);
  EXPECT_EQ(fluid.x, run.frames[2].x);
  EXPECT_EQ(fluid.collideTime, run.frames[2].collideTime);
  // And nothing else when resume records are off.
  const std::string bare = dir_ + "/bare.h5";
  writeRun(bare, 3, R"("fields": ["position"], "restart": false)");
  Id bareFile(openRaw(bare));
  EXPECT_EQ(H5Lexists(bareFile, "Restart#0", H5P_DEFAULT), 0);
  try {
    io::cache::CacheReader(bare).readRestart(2);
    ADD_FAILURE() << "a cache without resume records was resumed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("output.restart = false"), std::string::npos) << e.what();
  }
}

TEST_F(CacheFormat, VaryingCollisionCooldownsAreRecordedForResume) {
  // With a collision pass the cooldowns differ between particles: the resume record keeps them.
  setThreadCount(1);
  const std::string path = dir_ + "/cooldown.h5";
  const scene::Scene scene = io::scene::parseScene(test::tinyCacheScene(1.0, 100), path + ".json");
  run::Simulation sim(scene);
  Particles fluid = sim.fluid();
  for (std::size_t i = 0; i < fluid.size(); ++i)
    fluid.collideTime[i] = 0.001f * static_cast<float>(i % 7) - 0.002f;
  auto writer = io::cache::CacheWriter::create(path, scene, sim.params(),
                                               sim.boundary().particles(), {"test", 1, {}}, 1);
  writer->writeFrame(fluid, sim.runState());
  writer->close();
  const auto [state, back] = io::cache::CacheReader(path).readRestart(0);
  EXPECT_EQ(back.collideTime, fluid.collideTime);
}

TEST_F(CacheFormat, CompressionOffAndDoublePositions) {
  const std::string path = dir_ + "/plain.h5";
  const WrittenRun run = writeRun(path, 3, R"("compression": 0, "double_positions": true)");
  Id file(openRaw(path));
  Id x(H5Dopen2(file, "Step#1/x", H5P_DEFAULT));
  Id type(H5Dget_type(x));
  EXPECT_TRUE(H5Tequal(type, H5T_IEEE_F64LE) > 0);
  Id dcpl(H5Dget_create_plist(x));
  EXPECT_EQ(H5Pget_nfilters(dcpl), 0);
  EXPECT_EQ(H5Pget_layout(dcpl), H5D_CONTIGUOUS);
  const io::cache::CacheReader reader(path);
  EXPECT_TRUE(test::sameBits(run.frames[1], reader.readFrame(1)));
}

TEST_F(CacheFormat, XdmfSidecarIsWellFormedAndPointsAtExistingDatasets) {
  const std::string path = dir_ + "/side.h5";
  writeRun(path, 5);
  const io::cache::CacheReader reader(path);
  const io::cache::CacheSummary& s = reader.summary();
  const std::string xdmfPath = io::cache::XdmfWriter::sidecarPath(path);
  EXPECT_EQ(xdmfPath, dir_ + "/side.xdmf");
  {
    // Written with two frames, then three appended one by one, as a run does.
    std::vector<io::cache::CacheFrame> first(s.frames.begin(), s.frames.begin() + 2);
    io::cache::XdmfWriter xdmf(xdmfPath, "side.h5", s.fields, false, s.boundaryParticles, first);
    for (std::size_t k = 2; k < 5; ++k) xdmf.append(s.frames[k]);
  }
  io::cache::XdmfWriter whole(dir_ + "/whole.xdmf", "side.h5", s.fields, false, s.boundaryParticles,
                              s.frames);
  EXPECT_EQ(test::readFile(xdmfPath), test::readFile(dir_ + "/whole.xdmf"))
      << "appending equals writing at once";
  // Python's XML parser lists every time and every HDF5 reference with its length.
  const std::string script = dir_ + "/list.py";
  std::ofstream(script) << R"(import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
for grid in root.iter('Grid'):
    t = grid.find('Time')
    if t is not None: print('time', grid.get('Name'), t.get('Value'))
for item in root.iter('DataItem'):
    if item.get('Format') == 'HDF':
        print('data', item.text.strip(), item.get('Dimensions').replace(' ', 'x'))
)";
  const auto listed = test::runShell("python3 '" + script + "' '" + xdmfPath + "'");
  ASSERT_EQ(listed.exitCode, 0) << listed.output;
  Id file(openRaw(path));
  std::istringstream lines(listed.output);
  std::string kind, a, b;
  int times = 0, items = 0;
  while (lines >> kind >> a >> b) {
    if (kind == "time") {
      const std::size_t k = std::stoul(a.substr(a.find('#') + 1));
      EXPECT_EQ(std::stod(b), s.frames.at(k).time) << a;
      ++times;
      continue;
    }
    ASSERT_EQ(a.rfind("side.h5:/", 0), 0u) << a;
    const std::string dataset = a.substr(std::string("side.h5:").size());
    ASSERT_GT(H5Oexists_by_name(file, dataset.c_str(), H5P_DEFAULT), 0) << dataset;
    Id set(H5Dopen2(file, dataset.c_str(), H5P_DEFAULT));
    Id space(H5Dget_space(set));
    hsize_t dims[2] = {0, 0};
    const int rank = H5Sget_simple_extent_dims(space, dims, nullptr);
    EXPECT_EQ(std::to_string(dims[0]) + (rank == 2 ? "x" + std::to_string(dims[1]) : ""), b)
        << dataset;
    if (dataset.rfind("/Index#", 0) == 0) {
      // A point index: the numbers 0, 1, ... that the cells take.
      std::vector<std::uint32_t> numbers(dims[0]);
      ASSERT_GE(H5Dread(set, H5T_NATIVE_UINT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, numbers.data()), 0);
      for (std::size_t i = 0; i < numbers.size(); ++i) ASSERT_EQ(numbers[i], i) << dataset;
    }
    ++items;
  }
  EXPECT_EQ(times, 5);
  // Per frame: the positions and velocities ([n][3] views), rho, p, id, the boundary's positions,
  // and the point index of the fluid's cells and of the boundary's.
  EXPECT_EQ(items, 5 * 8);
}

TEST_F(CacheFormat, RenderedFramesRoundTripUnderTheirRenderer) {
  const std::string path = dir_ + "/render.h5";
  const WrittenRun run = writeRun(path, 2);
  const int w = 5, h = 3;
  std::vector<std::uint8_t> image(w * h * 3);
  for (std::size_t i = 0; i < image.size(); ++i) image[i] = static_cast<std::uint8_t>(i * 7);
  {
    auto writer = io::cache::CacheWriter::append(path, 2);
    writer->writeRenderedFrame("point", 1, w, h, image.data());
    writer->writeRenderedFrame("pyramid", 0, w, h, image.data());
    EXPECT_THROW(writer->writeRenderedFrame("point", 1, w, h, image.data()), InputError)
        << "written twice";
    EXPECT_THROW(writer->writeRenderedFrame("po int", 0, w, h, image.data()), InputError)
        << "bad name";
    EXPECT_THROW(writer->writeRenderedFrame("point", 2, w, h, image.data()), InputError)
        << "no such frame";
    writer->close();
  }
  const io::cache::CacheReader reader(path);
  ASSERT_EQ(reader.summary().renderers.size(), 2u);
  EXPECT_EQ(reader.summary().renderers[0].first, "point");
  EXPECT_EQ(reader.summary().renderers[0].second, std::vector<std::size_t>{1})
      << "a picture of frame 1 alone counts (render.every pictures skip frames)";
  EXPECT_EQ(reader.summary().renderers[1].second, std::vector<std::size_t>{0});
  EXPECT_THROW(reader.readRenderedFrame("point", 0), InputError) << "no picture of frame 0";
  const io::cache::RenderedFrame back = reader.readRenderedFrame("pyramid", 0);
  EXPECT_EQ(back.width, w);
  EXPECT_EQ(back.height, h);
  EXPECT_EQ(back.rgb, image);
  EXPECT_EQ(back.time, run.states[0].time);
  Id file(openRaw(path));
  Id set(H5Dopen2(file, "Render#point#1", H5P_DEFAULT));
  EXPECT_EQ(stringAttribute(set, "CLASS"), "IMAGE");
  EXPECT_EQ(stringAttribute(set, "IMAGE_SUBCLASS"), "IMAGE_TRUECOLOR");
}

}  // namespace
}  // namespace sph

TEST(CacheReader, DescribesTheFramesARendererHasPicturesOf) {
  using V = std::vector<std::size_t>;
  EXPECT_EQ(sph::io::cache::describeFrames(V{}), "no frame");
  EXPECT_EQ(sph::io::cache::describeFrames(V{5}), "1 frame (5)");
  EXPECT_EQ(sph::io::cache::describeFrames(V{0, 1}), "2 frames (0, 1)");
  EXPECT_EQ(sph::io::cache::describeFrames(V{0, 1, 2, 3}), "4 frames (0-3)");
  EXPECT_EQ(sph::io::cache::describeFrames(V{0, 10, 20, 30}), "4 frames (0-30, every 10 frames)");
  EXPECT_EQ(sph::io::cache::describeFrames(V{1, 4, 9}), "3 frames (1, 4, 9)");
  EXPECT_EQ(sph::io::cache::describeFrames(V{0, 1, 2, 3, 4, 5, 6, 7, 9, 11}),
            "10 frames (0, 1, 2, 3, 4, 5, 6, 7, ... 11)");
}
