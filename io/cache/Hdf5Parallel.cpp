// The parallel half of io/cache/Hdf5.h: files opened through MPI-IO and datasets each process writes
// its part of (docs/scaling.md, "The cache is written by all ranks"). Built against parallel
// HDF5 (SPHSPLAT_PARALLEL_HDF5, io/CMakeLists.txt), whose hdf5.h brings mpi.h; against the serial
// library haveParallel() is false and nothing here is called.
#include <algorithm>

#include "io/cache/Hdf5.h"

namespace sph::io::cache::h5 {

std::size_t Part::count() const {
  std::size_t n = 0;
  for (const auto& run : runs) n += run.second;
  return n;
}

#ifdef SPHSPLAT_PARALLEL_HDF5

bool haveParallel() {
  return true;
}

}  // namespace sph::io::cache::h5

// HDF5's MPI-IO driver sets the file's size to its end of allocation (EOA) after every flush that
// allocated (H5FD__mpio_truncate, 1.10.8), the only MPI_File_set_size call in this program. A
// reader that takes the file's size right after such a cut and reads the superblock after the
// next commit has raised the EOA would refuse the cache as "truncated file": the margin that a
// single process keeps ahead of the EOA (io/cache/CacheCommit.cpp, point 4) would be gone after every
// flush of a frame the ranks write together, and h5py or ParaView opening the cache during it
// were refused now and then (tests/test_mpi_cache.cpp, ReadersDuringFramesWrittenTogetherNeverFail,
// about 1 run in 3 under load). So the cut leaves the same margin: a hole past the EOA, which no
// reader minds and the serial close at the end cuts off. The size is the same on every rank
// (HDF5 passes its EOA, which the ranks share), as the collective call requires. Linked into the
// program, this definition comes before the MPI library's for libhdf5 (the MPI profiling
// interface: PMPI_File_set_size is the library's own).
// (A size of 0, an emptied file, stays 0. Exported whatever the build's default visibility:
// without it libhdf5 would call the library's own and the readers' refusals would come back.)
extern "C" __attribute__((visibility("default"))) int MPI_File_set_size(MPI_File file,
                                                                        MPI_Offset size) {
  constexpr MPI_Offset kReaderMargin = 1 << 20;  // as io/cache/CacheCommit.cpp's kGrowthMargin
  return PMPI_File_set_size(file, size > 0 ? size + kReaderMargin : 0);
}

namespace sph::io::cache::h5 {

Handle parallelFileAccessProps() {
  Handle fapl = fileAccessProps();
  check(H5Pset_fapl_mpio(fapl.get(), MPI_COMM_WORLD, MPI_INFO_NULL), "use MPI-IO");
  return fapl;
}

std::uint64_t writeDatasetPart(hid_t loc, const std::string& name, hid_t memType, hid_t fileType,
                               const void* data, const Part& part, const Storage& storage) {
  Storage together = storage;
  together.collective = true;
  Handle set = createDataset(loc, name, fileType, {static_cast<hsize_t>(part.total)}, together);
  // Every process takes part in the write (it is collective), one with no values selecting none.
  if (part.total > 0) {
    const hsize_t n = part.count();
    const hsize_t memDims[1] = {std::max<hsize_t>(n, 1)};
    Handle memory = checked(H5Screate_simple(1, memDims, nullptr), "create a dataspace");
    Handle file = checked(H5Dget_space(set.get()), "read the shape of dataset '" + name + "'");
    check(H5Sselect_none(file.get()), "select in dataset '" + name + "'");
    for (const auto& [first, count] : part.runs) {
      const hsize_t start[1] = {first}, block[1] = {count};
      check(H5Sselect_hyperslab(file.get(), H5S_SELECT_OR, start, nullptr, block, nullptr),
            "select this process's part of dataset '" + name + "'");
    }
    if (n == 0) check(H5Sselect_none(memory.get()), "select in dataset '" + name + "'");
    Handle transfer = checked(H5Pcreate(H5P_DATASET_XFER), "create a transfer property list");
    check(H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_COLLECTIVE), "ask for collective writes");
    check(H5Dwrite(set.get(), memType, memory.get(), file.get(), transfer.get(), data),
          "write dataset '" + name + "'");
  }
  check(H5Dflush(set.get()), "write dataset '" + name + "'");
  const std::uint64_t bytes = H5Dget_storage_size(set.get());
  set.close("write dataset '" + name + "'");
  return bytes;
}

#else

bool haveParallel() {
  return false;
}

Handle parallelFileAccessProps() {
  throw Error("use MPI-IO", "this build has the serial HDF5 library");
}

std::uint64_t writeDatasetPart(hid_t, const std::string& name, hid_t, hid_t, const void*,
                               const Part&, const Storage&) {
  throw Error("write dataset '" + name + "' together", "this build has the serial HDF5 library");
}

#endif

}  // namespace sph::io::cache::h5
