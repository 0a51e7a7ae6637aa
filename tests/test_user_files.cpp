// Files the user names (io/UserFiles.h): inputs that are directories, devices, FIFOs or too big
// are refused before a byte is read; outputs never replace the file being read (whatever path
// names it), a non-regular file, or an existing file without --overwrite; and an output appears
// complete or not at all.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "io/UserFiles.h"
#include "sim/InputError.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Every file in `dir` (names only).
std::vector<std::string> listing(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(UserFiles, InputsMustBeRegularFilesOfAtMost64MiB) {
  const std::string dir = test::makeTempDir();
  std::ofstream(dir + "/scene.json") << "{}";
  EXPECT_EQ(io::readInputFile(dir + "/scene.json", "scene file"), "{}");
  EXPECT_EQ(errorOf([&] { io::readInputFile(dir, "scene file"); }),
            dir + ": is a directory; expected a scene file");
  // /dev/zero used to be read forever.
  EXPECT_EQ(errorOf([&] { io::readInputFile("/dev/zero", "scene file"); }),
            "/dev/zero: is a character device, not a regular file; expected a scene file");
  // A FIFO nobody writes to would block the open (and a read) forever.
  const std::string fifo = dir + "/fifo.json";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0644), 0);
  EXPECT_EQ(errorOf([&] { io::readInputFile(fifo, "sweep file"); }),
            fifo + ": is a FIFO (named pipe), not a regular file; expected a sweep file");
  // A sparse file of 65 MiB: refused from its size, nothing read.
  const std::string big = dir + "/big.json";
  std::ofstream(big).close();
  std::filesystem::resize_file(big, 65ull << 20);
  EXPECT_EQ(errorOf([&] { io::readInputFile(big, "scene file"); }),
            big + ": 65 MiB is too large for a scene file (at most 64 MiB)");
  EXPECT_EQ(errorOf([&] { io::readInputFile(dir + "/none.json", "scene file"); }),
            dir + "/none.json: cannot open the scene file (No such file or directory)");
}

TEST(UserFiles, OutputsNeverReplaceWhatIsReadNorNonRegularFiles) {
  const std::string dir = test::makeTempDir();
  const std::string cache = dir + "/run.h5";
  std::ofstream(cache) << "cache";
  const std::vector<io::ReadFile> reads = {{cache, "the cache being exported"}};
  ASSERT_EQ(symlink(cache.c_str(), (dir + "/link.h5").c_str()), 0);
  ASSERT_EQ(link(cache.c_str(), (dir + "/hard.h5").c_str()), 0);
  ASSERT_EQ(chdir(dir.c_str()), 0);
  // The same file by another path text: relative, ./, a symlink, a hard link.
  for (const std::string& other : {std::string("run.h5"), std::string("./run.h5"),
                                   dir + "/../" + dir.substr(dir.rfind('/') + 1) + "/run.h5",
                                   std::string("link.h5"), std::string("hard.h5")}) {
    EXPECT_EQ(errorOf([&] { io::checkOutputPath(other, true, reads); }),
              other + ": is the cache being exported (" + cache +
                  "); refusing to write over it, even with --overwrite")
        << other;
  }
  EXPECT_EQ(errorOf([&] { io::checkOutputPath("/dev/null", true, {}); }),
            "/dev/null: is a character device, not a regular file; refusing to replace it "
            "(choose a file name)");
  ASSERT_EQ(mkfifo((dir + "/fifo").c_str(), 0644), 0);
  EXPECT_NE(errorOf([&] { io::checkOutputPath(dir + "/fifo", true, {}); }).find("is a FIFO"),
            std::string::npos);
  std::ofstream(dir + "/old.csv") << "old";
  EXPECT_EQ(errorOf([&] { io::checkOutputPath(dir + "/old.csv", false, {}); }),
            dir + "/old.csv: already exists; pass --overwrite to replace it");
  EXPECT_EQ(errorOf([&] { io::checkOutputPath(dir + "/old.csv", true, reads); }), "");
  EXPECT_EQ(errorOf([&] { io::checkOutputPath(dir + "/new.csv", false, reads); }), "");
  EXPECT_EQ(chdir("/"), 0);
}

TEST(UserFiles, AnOutputAppearsCompleteOrNotAtAll) {
  const std::string dir = test::makeTempDir();
  const std::string path = dir + "/out.csv";
  std::ofstream(path) << "old contents\n";
  {
    io::AtomicOutput out(path);
    std::fputs("half of the new", out.file());
    // Destroyed without commit (an exception mid-write): the old file stays, no temporary.
  }
  EXPECT_EQ(test::readFile(path), "old contents\n");
  EXPECT_EQ(listing(dir), std::vector<std::string>{"out.csv"});
  {
    io::AtomicOutput out(path);
    std::fputs("new contents\n", out.file());
    EXPECT_EQ(test::readFile(path), "old contents\n") << "replaced before commit";
    out.commit();
  }
  EXPECT_EQ(test::readFile(path), "new contents\n");
  EXPECT_EQ(listing(dir), std::vector<std::string>{"out.csv"});
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  const mode_t mask = umask(0);
  umask(mask);
  EXPECT_EQ(st.st_mode & 0777, 0666 & ~mask) << "the mode of a plain fopen(), not mkstemp's 0600";
  // Through a symlink: the file it points at is replaced, the link stays a link.
  ASSERT_EQ(symlink(path.c_str(), (dir + "/link.csv").c_str()), 0);
  {
    io::AtomicOutput out(dir + "/link.csv");
    std::fputs("through the link\n", out.file());
    out.commit();
  }
  EXPECT_TRUE(std::filesystem::is_symlink(dir + "/link.csv"));
  EXPECT_EQ(test::readFile(path), "through the link\n");
  EXPECT_EQ(errorOf([&] { io::AtomicOutput(dir + "/no/such/dir/x.csv"); }),
            dir + "/no/such/dir/x.csv: cannot create the file (No such file or directory)");
}

}  // namespace
}  // namespace sph
