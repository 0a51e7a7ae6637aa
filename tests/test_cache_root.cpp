// The cache's root (docs/cache-format.md): its string attributes are UTF-8 text that h5py reads
// as str, caches written with the older fixed-length strings still read and resume, and the
// scene text it records is kept whole and validated when read back.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/cache/CacheWriter.h"
#include "io/scene/SceneLoader.h"
#include "sim/InputError.h"
#include "tests/CacheFormatSupport.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

namespace cache = io::cache;
using test::Id;
using test::openRaw;
using test::stringAttribute;
using test::stringKind;
using test::writeRun;
using test::WrittenRun;

class CacheRoot : public test::TempDirTest {};

TEST_F(CacheRoot, H5pyReadsTheRootStringsAsText) {
  // What a Python user meets: /usr/bin/python3 with h5py (scripts/setup installs it).
  const std::string path = dir_ + "/py.h5";
  const WrittenRun run = writeRun(path, 2);
  const std::string script = dir_ + "/attrs.py";
  std::ofstream(script) << R"(import sys, h5py
with h5py.File(sys.argv[1], 'r') as f:
    for name in ('sphsplat_format', 'scene_text', 'scene_name', 'created', 'output.fields',
                 'solver.eos', 'run_status'):
        value = f.attrs[name]
        print(name, type(value).__name__, len(value))
    assert f.attrs['scene_text'] == open(sys.argv[2]).read(), 'scene_text differs'
    assert f.attrs['sphsplat_format'] == 'sphsplat-cache'
    assert f.attrs['run_status'].decode() == 'finished'
)";
  std::ofstream(dir_ + "/scene.txt") << run.scene.sourceText;
  const auto r = test::runShell("/usr/bin/python3 '" + script + "' '" + path + "' '" + dir_ +
                                "/scene.txt' 2>&1");
  ASSERT_EQ(r.exitCode, 0) << "h5py (python3-h5py, installed by scripts/setup):\n" << r.output;
  for (const char* name :
       {"sphsplat_format", "scene_text", "scene_name", "created", "output.fields", "solver.eos"}) {
    EXPECT_NE(r.output.find(std::string(name) + " str "), std::string::npos) << name << "\n"
                                                                             << r.output;
  }
  // The one fixed-length string: h5py gives bytes (docs/cache-format.md says to decode it).
  EXPECT_NE(r.output.find("run_status bytes_ "), std::string::npos) << r.output;
}

// Rewrites every variable-length string attribute of the root as a fixed-length one, in the
// given character set: what caches written before the switch to variable-length strings hold.
void makeStringsFixedLength(const std::string& path, H5T_cset_t cset) {
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_file_locking(fapl, false, true);
  Id file(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl));
  H5Pclose(fapl);
  H5O_info_t info;
  ASSERT_GE(H5Oget_info2(file, &info, H5O_INFO_NUM_ATTRS), 0);
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    char name[256] = {0};
    H5Aget_name_by_idx(file, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT);
    if (stringKind(file, name).rfind("variable", 0) == 0) names.push_back(name);
  }
  ASSERT_GE(names.size(), 10u);
  for (const std::string& name : names) {
    const std::string value = stringAttribute(file, name.c_str());
    ASSERT_GE(H5Adelete(file, name.c_str()), 0);
    Id type(H5Tcopy(H5T_C_S1));
    H5Tset_size(type, value.size() + 1);
    H5Tset_strpad(type, H5T_STR_NULLTERM);
    H5Tset_cset(type, cset);
    Id space(H5Screate(H5S_SCALAR));
    Id attr(H5Acreate2(file, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT));
    ASSERT_GE(H5Awrite(attr, type, value.c_str()), 0);
  }
}

TEST_F(CacheRoot, CachesWithFixedLengthStringsStillReadAndResume) {
  for (const H5T_cset_t cset : {H5T_CSET_ASCII, H5T_CSET_UTF8}) {
    const std::string label = cset == H5T_CSET_ASCII ? "ASCII" : "UTF-8";
    const std::string path = dir_ + "/old" + label + ".h5";
    const WrittenRun run = writeRun(path, 3);
    const io::cache::CacheSummary fresh = io::cache::CacheReader(path).summary();
    makeStringsFixedLength(path, cset);
    {
      Id file(openRaw(path));
      EXPECT_EQ(stringKind(file, "scene_text"), "fixed " + label);
    }
    const io::cache::CacheReader reader(path);
    const io::cache::CacheSummary& old = reader.summary();
    EXPECT_EQ(old.sceneText, run.scene.sourceText) << label;
    EXPECT_EQ(old.sceneText, fresh.sceneText) << label;
    EXPECT_EQ(old.created, fresh.created) << label;
    EXPECT_EQ(old.sceneFingerprint, fresh.sceneFingerprint) << label;
    EXPECT_EQ(old.sceneOverrides, "solver.cfl=0.4") << label;
    EXPECT_EQ(old.fields, cache::defaultFields()) << label;
    ASSERT_EQ(old.parameters.size(), fresh.parameters.size()) << label;
    for (std::size_t i = 0; i < old.parameters.size(); ++i) {
      EXPECT_EQ(old.parameters[i].text, fresh.parameters[i].text) << old.parameters[i].name;
      EXPECT_EQ(old.parameters[i].number, fresh.parameters[i].number) << old.parameters[i].name;
    }
    EXPECT_TRUE(test::sameBits(run.frames[2], reader.readFrame(2))) << label;
  }
  // The writer reads its settings back from such a cache to append to it (resume).
  const std::string path = dir_ + "/oldASCII.h5";
  const auto [state, last] = io::cache::CacheReader(path).readRestart(2);
  {
    auto writer = io::cache::CacheWriter::append(path, 3);
    writer->writeFrame(last, state);
    writer->close();
  }
  const io::cache::CacheReader after(path);
  ASSERT_EQ(after.frameCount(), 4u);
  EXPECT_TRUE(test::sameBits(last, after.readFrame(3)));
}

TEST_F(CacheRoot, SceneFieldsAreValidated) {
  auto load = [](const std::string& output) {
    return io::scene::parseScene(test::tinyCacheScene(0.1, 100, output), "s.json");
  };
  EXPECT_EQ(load(R"("fields": ["velocity", "position", "rho"])").output.fields,
            (std::vector<std::string>{"x", "y", "z", "vx", "vy", "vz", "rho"}));
  auto message = [&](const std::string& output) {
    try {
      load(output);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(R"("fields": ["x", "y", "z", "speed"])")
                .rfind("s.json: output.fields: unknown field \"speed\"", 0),
            0u);
  EXPECT_EQ(message(R"("fields": ["rho"])")
                .rfind("s.json: output.fields: expected \"x\", \"y\" and \"z\"", 0),
            0u);
  EXPECT_EQ(message(R"("compression": 11)")
                .rfind("s.json: output.compression: expected an integer deflate level", 0),
            0u);
  EXPECT_EQ(
      message(R"("restart": "yes")").rfind("s.json: output.restart: expected true or false", 0),
      0u);
}

TEST_F(CacheRoot, ALongSceneFileIsKeptWhole) {
  // Scene text past HDF5's 64 kB limit for a compact attribute.
  std::string description(100000, 'a');
  std::string text = test::tinyCacheScene(0.1, 100);
  text.insert(1, "\"description\": \"" + description + "\",");
  const std::string path = dir_ + "/long.h5";
  const scene::Scene scene = io::scene::parseScene(text, path + ".json");
  run::Simulation sim(scene);
  auto writer = io::cache::CacheWriter::create(path, scene, sim.params(),
                                               sim.boundary().particles(), {"test", 1, {}}, 1);
  writer->writeFrame(sim.fluid(), sim.runState());
  writer->close();
  EXPECT_EQ(io::cache::CacheReader(path).summary().sceneText, text);
}

}  // namespace
}  // namespace sph
