// Caches the commands cannot use, each refused with one line and exit code 2: missing, not HDF5,
// truncated, another program's HDF5, a dataset or resume record the command needs missing, a
// damaged global heap object of the header, and a frame that does not read back after the frames
// that do.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/CacheCliSuite.h"

namespace sph {
namespace {

using test::CacheCli;
using test::lineCount;
using test::readFile;
using test::runShell;
using test::sphsplat;

struct BadCache {
  std::string what, command, message;  // message: the whole expected line after "sphsplat: "
};

TEST_F(CacheCli, EveryBadCacheGivesOneLineAndExitTwo) {
  const std::string text = dir_ + "/notes.txt";
  std::ofstream(text) << "not a cache\n";
  // A cache cut in half (an interrupted copy).
  const std::string truncated = dir_ + "/truncated.h5";
  const std::string whole = readFile(cache_);
  std::ofstream(truncated, std::ios::binary) << whole.substr(0, whole.size() / 2);
  // An HDF5 file from another program.
  const std::string foreign = dir_ + "/foreign.h5";
  {
    const hid_t f = H5Fcreate(foreign.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t n = 4;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t d = H5Dcreate2(f, "temperature", H5T_NATIVE_FLOAT, space, H5P_DEFAULT, H5P_DEFAULT,
                               H5P_DEFAULT);
    H5Dclose(d), H5Sclose(space), H5Fclose(f);
  }
  // A cache with positions only, asked for densities.
  const std::string positions = dir_ + "/positions.h5";
  const std::string posScene = dir_ + "/positions.json";
  std::ofstream(posScene) << test::tinyCacheScene(0.02, 100,
                                                  R"("fields": ["position"], "restart": false)");
  ASSERT_EQ(runShell(sphsplat("run '" + posScene + "' --threads 1 --quiet -o '" + positions + "'"))
                .exitCode,
            0);

  const std::vector<BadCache> cases = {
      {"missing", "info '" + dir_ + "/nope.h5'",
       dir_ + "/nope.h5: cannot open the cache (No such file or directory)"},
      {"directory", "info '" + dir_ + "'", dir_ + ": is a directory, expected an HDF5 cache file"},
      {"not HDF5", "info '" + text + "'",
       text + ": not an HDF5 file (no HDF5 signature); expected a sphsplat cache"},
      {"truncated", "info '" + truncated + "'",
       truncated + ": truncated HDF5 file: " + std::to_string(whole.size() / 2) +
           " bytes, but its superblock says " + std::to_string(whole.size()) +
           " (an interrupted copy or download?)"},
      {"foreign HDF5", "export '" + foreign + "' --frame 0 --format csv -o -",
       foreign + ": an HDF5 file but not a sphsplat cache (no root attribute 'sphsplat_format'; "
                 "written by another program?)"},
      {"missing dataset", "export '" + positions + "' --frame 1 --format csv --fields rho -o -",
       positions + ": frame 1 has no dataset /Step#1/rho (it holds x y z)"},
      {"frame out of range", "export '" + cache_ + "' --frame 11 --format ply -o -",
       "--frames: frames 11 are not in the cache (it has frames 0 to 10)"},
      {"bad frame text", "export '" + cache_ + "' --frame two --format csv -o -",
       "--frames: expected a frame index (0, 1, ...), 'last' or -1, got 'two'"},
      {"resume a foreign file", "run '" + scene_ + "' --resume '" + foreign + "'",
       foreign + ": an HDF5 file but not a sphsplat cache (no root attribute 'sphsplat_format'; "
                 "written by another program?)"},
      {"resume a truncated file", "run '" + scene_ + "' --resume '" + truncated + "'",
       truncated + ": truncated HDF5 file: " + std::to_string(whole.size() / 2) +
           " bytes, but its superblock says " + std::to_string(whole.size()) +
           " (an interrupted copy or download?)"},
      {"resume without records", "run '" + posScene + "' --end 0.05 --resume '" + positions + "'",
       positions + ": frame 2 has no resume record (/Restart#2): the run was written with "
                   "output.restart = false"},
  };
  for (const BadCache& c : cases) {
    const auto r = runShell(sphsplat(c.command));
    EXPECT_EQ(r.exitCode, 2) << c.what << "\n" << r.output;
    EXPECT_EQ(r.output, "sphsplat: " + c.message + "\n") << c.what;
  }
  EXPECT_EQ(readFile(truncated).size(), whole.size() / 2)
      << "a failed resume must not touch the file";
}

// The header's texts (the format name, the scene) are variable-length strings, which HDF5 keeps
// in a global heap without a checksum and copies by the sizes it finds there: a damaged size or
// index is said in one line with exit 2 by every command that reads the header, never a crash.
TEST_F(CacheCli, ADamagedHeapObjectOfTheHeaderIsSaidNotCrashedOn) {
  const std::string whole = readFile(cache_);
  const std::string name("sphsplat-cache\0", 15);
  const std::size_t at = whole.find(name);
  ASSERT_NE(at, std::string::npos);
  ASSERT_GE(at, 16u);
  const std::string damaged = dir_ + "/heap.h5";
  int refused = 0;
  // The heap object's header before the text: index (2 bytes), references (2), reserved (4),
  // size (8).
  for (std::size_t offset = at - 16; offset < at; ++offset) {
    for (const unsigned char value : {0x00, 0x32, 0xff}) {
      if (static_cast<unsigned char>(whole[offset]) == value) continue;
      std::string bytes = whole;
      bytes[offset] = static_cast<char>(value);
      std::ofstream(damaged, std::ios::binary | std::ios::trunc) << bytes;
      const std::string label = "byte " + std::to_string(offset - at + 16) + " of the object's "
                                "header set to " + std::to_string(value);
      for (const std::string& command :
           {"info '" + damaged + "'", "export '" + damaged + "' --frame 0 --format csv -o -",
            "mesh '" + damaged + "' --frame 0 -o '" + dir_ + "/heap_mesh'",
            "run '" + scene_ + "' --resume '" + damaged + "'"}) {
        const auto r = runShell(sphsplat(command));
        EXPECT_TRUE(r.exitCode == 0 || r.exitCode == 2) << label << ": " << command << "\n"
                                                        << r.output;
        if (r.exitCode == 2) {
          EXPECT_EQ(lineCount(r.output), 1u) << label << ": " << command << "\n" << r.output;
          ++refused;
        }
        std::filesystem::remove_all(dir_ + "/heap_mesh");
      }
      // The size and the index (not the reference count or the reserved bytes) make the text
      // unreadable.
      const std::size_t field = offset - (at - 16);
      if (field < 2 || field >= 8) {
        const auto r = runShell(sphsplat("info '" + damaged + "'"));
        EXPECT_NE(r.output.find("global heap"), std::string::npos) << label << "\n" << r.output;
      }
      if (HasFailure()) return;
    }
  }
  EXPECT_GT(refused, 0);
}

// info, export, mesh: what the complete frames allow, then the damage in one line and exit 2
// ("all" and "last" quietly meaning the frames before the damaged one was the old behaviour).
TEST_F(CacheCli, ADamagedCacheIsSaidAndExitsTwoAfterWhatCouldBeRead) {
  const std::string damaged = dir_ + "/damaged.h5";
  std::filesystem::copy_file(cache_, damaged);
  {
    const hid_t f = H5Fopen(damaged.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    const hid_t g = H5Gopen2(f, "Step#3", H5P_DEFAULT);
    ASSERT_GE(H5Adelete(g, "TimeValue"), 0);
    H5Gclose(g), H5Fclose(f);
  }
  const auto r = runShell(sphsplat("info '" + damaged + "'"));
  EXPECT_EQ(r.exitCode, 2) << r.output;  // was 0
  EXPECT_NE(r.output.find("frames     3 (Step#0 - Step#2)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sphsplat: " + damaged +
                          ": damaged cache: frame 3 does not read back (/Step#3: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("; frames 0-2 are complete\n"), std::string::npos) << r.output;
  const std::string damageLine = damaged + ": damaged cache: frame 3 does not read back";
  struct Case {
    std::string command, firstFile, lastFile;
  };
  const Case cases[] = {
      {"export '" + damaged + "' --frames all --format csv -o '" + dir_ + "/all/'",
       dir_ + "/all/tiny_00000.csv", dir_ + "/all/tiny_00002.csv"},
      {"export '" + damaged + "' --frames last -o '" + dir_ + "/last.csv'", dir_ + "/last.csv",
       dir_ + "/last.csv"},
      {"mesh '" + damaged + "' --frames all -q -o '" + dir_ + "/mesh/'",
       dir_ + "/mesh/tiny_00000.ply", dir_ + "/mesh/tiny_00002.ply"},
  };
  for (const Case& c : cases) {
    const auto e = runShell(sphsplat(c.command));
    EXPECT_EQ(e.exitCode, 2) << c.command << "\n" << e.output;  // was 0, silently
    EXPECT_NE(e.output.find(damageLine), std::string::npos) << c.command << "\n" << e.output;
    EXPECT_TRUE(test::fileExists(c.firstFile)) << c.command;
    EXPECT_TRUE(test::fileExists(c.lastFile)) << c.command;
  }
  EXPECT_FALSE(test::fileExists(dir_ + "/all/tiny_00003.csv"));
}

}  // namespace
}  // namespace sph
