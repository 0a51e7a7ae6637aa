// How the writer filters a dataset's chunks itself (io/cache/Hdf5Datasets.cpp, writeDataset):
// the bytes HDF5's own filters would write, on any thread count, and at level 1 zlib's
// run-length strategy, which HDF5's filter reads back bit for bit.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "io/cache/Hdf5.h"
#include "sim/Parallel.h"
#include "tests/CacheFormatSupport.h"
#include "tests/CacheTestSupport.h"

namespace sph {
namespace {

using test::Id;

class CacheChunks : public test::TempDirTest {};

// writeDataset deflates a dataset's chunks on all threads and hands them to HDF5 filtered: the
// file must hold exactly what HDF5's own filters would have written (shuffle, then deflate; the
// edge chunk padded at full size), whatever the thread count, and read back through them.
TEST_F(CacheChunks, ChunksDeflatedOnAllThreadsAreHdf5sOwn) {
  const std::string path = dir_ + "/chunks.h5";
  Id file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  io::cache::h5::Storage storage;
  storage.deflateLevel = 4;
  // 100,003 values: 3 full chunks of 32,768 floats and an edge chunk (12,501 doubles a chunk).
  const std::size_t n = 100003;
  std::vector<float> floats(n);
  std::vector<double> doubles(n);
  std::vector<std::uint32_t> ids(n);
  for (std::size_t i = 0; i < n; ++i) {
    floats[i] = std::sin(0.001f * static_cast<float>(i)) + 1e-4f * static_cast<float>(i % 97);
    doubles[i] = 3.0 + 1e-5 * static_cast<double>(i) * static_cast<double>(i % 13);
    ids[i] = static_cast<std::uint32_t>((i * 2654435761u) % n);
  }
  struct Case {
    const char* name;
    hid_t memType, fileType;
    const void* data;
  };
  const int before = threadCount();
  const Case cases[] = {{"f", H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, floats.data()},
                        {"d", H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, doubles.data()},
                        {"u", H5T_NATIVE_UINT32, H5T_STD_U32LE, ids.data()}};
  for (const Case& c : cases) {
    for (const int threads : {1, 3}) {
      setThreadCount(threads);
      const std::string ours = std::string(c.name) + std::to_string(threads);
      io::cache::h5::writeDataset(file, ours, c.memType, c.fileType, c.data, n, storage);
    }
    // HDF5 filtering the same values itself.
    const std::string theirs = std::string(c.name) + "_hdf5";
    {
      io::cache::h5::Handle set = io::cache::h5::createDataset(file, theirs, c.fileType,
                                                               {static_cast<hsize_t>(n)}, storage);
      ASSERT_GE(H5Dwrite(set.get(), c.memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.data), 0);
    }
    Id reference(H5Dopen2(file, theirs.c_str(), H5P_DEFAULT));
    hsize_t chunks = 0;
    {
      Id space(H5Dget_space(reference));
      ASSERT_GE(H5Dget_num_chunks(reference, space, &chunks), 0);
    }
    ASSERT_GE(chunks, 4u) << c.name;
    for (const int threads : {1, 3}) {
      const std::string ours = std::string(c.name) + std::to_string(threads);
      Id set(H5Dopen2(file, ours.c_str(), H5P_DEFAULT));
      Id space(H5Dget_space(set));
      hsize_t count = 0;
      ASSERT_GE(H5Dget_num_chunks(set, space, &count), 0);
      ASSERT_EQ(count, chunks) << ours;
      for (hsize_t k = 0; k < chunks; ++k) {
        hsize_t offset[1] = {0}, theirOffset[1] = {0};
        unsigned mask = 1, theirMask = 1;
        haddr_t address = 0;
        hsize_t size = 0, theirSize = 0;
        ASSERT_GE(H5Dget_chunk_info(set, space, k, offset, &mask, &address, &size), 0);
        ASSERT_GE(
            H5Dget_chunk_info(reference, space, k, theirOffset, &theirMask, &address, &theirSize),
            0);
        ASSERT_EQ(offset[0], theirOffset[0]);
        ASSERT_EQ(mask, 0u) << ours << " chunk " << k << ": a filter was skipped";
        ASSERT_EQ(mask, theirMask);
        ASSERT_EQ(size, theirSize) << ours << " chunk " << k;
        std::vector<unsigned char> a(size), b(theirSize);
        uint32_t filters = 0;
        ASSERT_GE(H5Dread_chunk(set, H5P_DEFAULT, offset, &filters, a.data()), 0);
        ASSERT_GE(H5Dread_chunk(reference, H5P_DEFAULT, offset, &filters, b.data()), 0);
        EXPECT_TRUE(a == b) << ours << " chunk " << k << " differs from HDF5's";
      }
      // And the values through HDF5's filters, bit for bit.
      std::vector<unsigned char> back(n * H5Tget_size(c.fileType));
      ASSERT_GE(H5Dread(set, c.memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()), 0);
      EXPECT_EQ(std::memcmp(back.data(), c.data, back.size()), 0) << ours;
    }
  }
  setThreadCount(before);
}

// Level 1 (the default) deflates the chunks with zlib's run-length strategy: other bytes than
// HDF5's level 1 writes, read back through HDF5's filters bit for bit, and not much larger than
// level 4 (this field: 12%; the frames of the peer's dam break: 8%, docs/benchmarks.md, "HDF5
// cache").
TEST_F(CacheChunks, RunLengthChunksReadBackThroughHdf5sFilters) {
  const std::string path = dir_ + "/rle.h5";
  Id file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  const std::size_t n = 100003;  // 4 chunks
  std::vector<float> values(n);
  for (std::size_t i = 0; i < n; ++i)
    values[i] = std::sin(0.001f * static_cast<float>(i)) + 1e-4f * static_cast<float>(i % 97);
  auto storedBytes = [&](const std::string& name, int level) {
    io::cache::h5::Storage storage;
    storage.deflateLevel = level;
    return io::cache::h5::writeDataset(file, name, H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, values.data(),
                                       n, storage);
  };
  const std::uint64_t runLength = storedBytes("rle", io::cache::h5::kRunLengthLevel);
  const std::uint64_t level4 = storedBytes("level4", 4);
  // HDF5 deflating the same values itself at level 1 (zlib's fastest matches).
  {
    io::cache::h5::Storage storage;
    storage.deflateLevel = 1;
    io::cache::h5::Handle set =
        io::cache::h5::createDataset(file, "hdf5", H5T_IEEE_F32LE, {n}, storage);
    ASSERT_GE(H5Dwrite(set.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
              0);
  }
  Id ours(H5Dopen2(file, "rle", H5P_DEFAULT)), theirs(H5Dopen2(file, "hdf5", H5P_DEFAULT));
  const std::uint64_t hdf5Level1 = H5Dget_storage_size(theirs);
  EXPECT_NE(runLength, hdf5Level1);  // not zlib's level 1
  EXPECT_LT(runLength, n * sizeof(float) * 8 / 10);
  EXPECT_LT(static_cast<double>(runLength), 1.15 * static_cast<double>(level4));
  std::vector<float> back(n);
  ASSERT_GE(H5Dread(ours, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, back.data()), 0);
  EXPECT_EQ(std::memcmp(back.data(), values.data(), n * sizeof(float)), 0);
  std::printf("run-length %llu, HDF5 level 1 %llu, level 4 %llu bytes of %zu\n",
              static_cast<unsigned long long>(runLength),
              static_cast<unsigned long long>(hdf5Level1), static_cast<unsigned long long>(level4),
              n * sizeof(float));
}

}  // namespace
}  // namespace sph
