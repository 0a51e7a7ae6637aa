// Helpers of the cache-format suites (tests/test_cache_format.cpp, tests/test_cache_root.cpp):
// a short run written in-process, and the raw HDF5 C API reads that check the file without our
// own reader.
#pragma once

#include <gtest/gtest.h>
#include <hdf5.h>

#include <set>
#include <string>
#include <vector>

#include "io/cache/CacheWriter.h"
#include "io/scene/SceneLoader.h"
#include "sim/Parallel.h"
#include "tests/CacheTestSupport.h"

namespace sph::test {

// Runs the tiny scene and writes `frames` frames (one every 0.01 s) to `path` in-process.
struct WrittenRun {
  scene::Scene scene;
  std::vector<Particles> frames;
  std::vector<run::RunState> states;
};

inline WrittenRun writeRun(const std::string& path, std::size_t frames,
                           const std::string& extraOutput = "", std::size_t expectedFrames = 0) {
  setThreadCount(1);  // a unit suite: it must not compete with others for the cores
  WrittenRun run;
  run.scene = io::scene::parseScene(tinyCacheScene(1.0, 100, extraOutput), path + ".json");
  run::Simulation sim(run.scene);
  auto writer =
      io::cache::CacheWriter::create(path, run.scene, sim.params(), sim.boundary().particles(),
                                     io::cache::CacheProvenance{"test", 1, {"solver.cfl=0.4"}},
                                     expectedFrames ? expectedFrames : frames);
  for (std::size_t k = 0; k < frames; ++k) {
    if (k > 0) sim.advanceTo(0.01 * static_cast<double>(k));
    writer->writeFrame(sim.fluid(), sim.runState());
    run.frames.push_back(sim.fluid());
    run.states.push_back(sim.runState());
  }
  writer->setStatus("finished");
  writer->close();
  return run;
}

// RAII for the raw C API checks below.
struct Id {
  hid_t id;
  explicit Id(hid_t i) : id(i) { EXPECT_GE(i, 0); }
  ~Id() {
    if (id >= 0) H5Idec_ref(id);
  }
  operator hid_t() const { return id; }
};

// Opens a cache with the raw C API, without HDF5's file lock like the project's reader (HDF5
// refuses a second open of a file within a process under other lock settings).
inline hid_t openRaw(const std::string& path) {
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_file_locking(fapl, false, true);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  return file;
}

// A string attribute of either kind, read with the C API.
inline std::string stringAttribute(hid_t obj, const char* name) {
  Id attr(H5Aopen(obj, name, H5P_DEFAULT));
  Id type(H5Aget_type(attr));
  EXPECT_EQ(H5Tget_class(type), H5T_STRING) << name;
  if (H5Tis_variable_str(type) > 0) {
    char* text = nullptr;
    EXPECT_GE(H5Aread(attr, type, &text), 0);
    std::string value = text ? text : "";
    H5free_memory(text);
    return value;
  }
  std::string value(H5Tget_size(type), '\0');
  EXPECT_GE(H5Aread(attr, type, value.data()), 0);
  return value.substr(0, value.find('\0'));
}

// "variable UTF-8", "fixed UTF-8", "fixed ASCII": how a string attribute is stored.
inline std::string stringKind(hid_t obj, const char* name) {
  Id attr(H5Aopen(obj, name, H5P_DEFAULT));
  Id type(H5Aget_type(attr));
  if (H5Tget_class(type) != H5T_STRING) return "not a string";
  return std::string(H5Tis_variable_str(type) > 0 ? "variable " : "fixed ") +
         (H5Tget_cset(type) == H5T_CSET_UTF8 ? "UTF-8" : "ASCII");
}

inline std::set<std::string> rootLinks(hid_t file) {
  std::set<std::string> names;
  hsize_t idx = 0;
  H5Literate(
      file, H5_INDEX_NAME, H5_ITER_INC, &idx,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::set<std::string>*>(data)->insert(name);
        return 0;
      },
      &names);
  return names;
}

}  // namespace sph::test
