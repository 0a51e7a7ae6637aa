// Datasets: creating and writing them (chunked, shuffled and deflated as Storage asks), the
// virtual column views, and reading 1-D numeric ones whole or in runs, each opened through
// openCheckedDataset (Hdf5StorageCheck.cpp) so that a damaged shape or layout is refused before
// anything is allocated by it.
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "io/cache/Hdf5.h"

namespace sph::io::cache::h5 {

Handle createDataset(hid_t loc, const std::string& name, hid_t fileType,
                     const std::vector<hsize_t>& dims, const Storage& storage) {
  const std::string label =
      name.empty() ? std::string("an anonymous dataset") : "dataset '" + name + "'";
  Handle space = checked(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                         "create a dataspace");
  Handle dcpl = checked(H5Pcreate(H5P_DATASET_CREATE), "create a dataset creation property list");
  hsize_t elements = 1;
  for (hsize_t d : dims) elements *= d;
  // An empty dataset cannot be chunked (a chunk must fit the extent); it stays contiguous.
  if (storage.deflateLevel > 0 && elements > 0) {
    std::vector<hsize_t> chunk = dims;
    const hsize_t rowBytes = H5Tget_size(fileType) * (elements / dims[0]);
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], storage.chunkBytes / rowBytes));
    check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()),
          "set the chunks of " + label);
    check(H5Pset_shuffle(dcpl.get()), "set the shuffle filter of " + label);
    check(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(storage.deflateLevel)),
          "set deflate on " + label);
  }
  if (storage.collective)
    check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), "set no fill values on " + label);
  if (name.empty()) {
    return checked(H5Dcreate_anon(loc, fileType, space.get(), dcpl.get(), H5P_DEFAULT),
                   "create " + label);
  }
  return checked(
      H5Dcreate2(loc, name.c_str(), fileType, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      "create " + label);
}

std::uint64_t writeDataset(hid_t loc, const std::string& name, hid_t memType, hid_t fileType,
                           const void* data, std::size_t count, const Storage& storage) {
  Handle set = createDataset(loc, name, fileType, {static_cast<hsize_t>(count)}, storage);
  if (count > 0)
    check(H5Dwrite(set.get(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
          "write dataset '" + name + "'");
  // Flushing compresses and writes the chunks now, before the frame's commit.
  check(H5Dflush(set.get()), "write dataset '" + name + "'");
  const std::uint64_t bytes = H5Dget_storage_size(set.get());
  set.close("write dataset '" + name + "'");
  return bytes;
}

void createColumnView(hid_t loc, const std::string& name, hid_t fileType, std::size_t count,
                      const std::vector<std::string>& columns) {
  const hsize_t n = count, width = columns.size();
  const hsize_t dims[2] = {n, width};
  Handle view = checked(H5Screate_simple(2, dims, nullptr), "create a dataspace");
  Handle source = checked(H5Screate_simple(1, &n, nullptr), "create a dataspace");
  Handle dcpl = checked(H5Pcreate(H5P_DATASET_CREATE), "create a dataset creation property list");
  for (hsize_t c = 0; c < width; ++c) {
    const hsize_t start[2] = {0, c}, block[2] = {n, 1};
    check(H5Sselect_hyperslab(view.get(), H5S_SELECT_SET, start, nullptr, block, nullptr),
          "select column " + std::to_string(c) + " of '" + name + "'");
    // "." is the file the virtual dataset is in.
    check(H5Pset_virtual(dcpl.get(), view.get(), ".", columns[c].c_str(), source.get()),
          "map " + columns[c] + " into '" + name + "'");
  }
  check(H5Sselect_all(view.get()), "select all of '" + name + "'");
  Handle set = checked(
      H5Dcreate2(loc, name.c_str(), fileType, view.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      "create the view '" + name + "'");
  set.close("create the view '" + name + "'");
}

namespace {

// The length of the 1-D numeric dataset `set`; throws Error if it is not one.
std::size_t lengthOf(hid_t set, const std::string& name) {
  Handle type = checked(H5Dget_type(set), "read the type of dataset '" + name + "'");
  const H5T_class_t cls = H5Tget_class(type.get());
  if (cls != H5T_FLOAT && cls != H5T_INTEGER)
    throw Error("dataset '" + name + "' does not hold numbers", "");
  Handle space = checked(H5Dget_space(set), "read the shape of dataset '" + name + "'");
  if (H5Sget_simple_extent_ndims(space.get()) != 1)
    throw Error("dataset '" + name + "' is not one-dimensional", "");
  hsize_t dims[1] = {0};
  check(H5Sget_simple_extent_dims(space.get(), dims, nullptr),
        "read the length of dataset '" + name + "'");
  return static_cast<std::size_t>(dims[0]);
}

}  // namespace

std::size_t datasetLength(hid_t loc, const std::string& name) {
  Handle set = openCheckedDataset(loc, name);
  return lengthOf(set.get(), name);
}

void readDatasetInto(hid_t loc, const std::string& name, hid_t memType,
                     const std::function<void*(std::size_t)>& place) {
  Handle set = openCheckedDataset(loc, name);  // checked once for its length and its read
  const std::size_t n = lengthOf(set.get(), name);
  void* out = place(n);
  if (n > 0)
    check(H5Dread(set.get(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, out),
          "read dataset '" + name + "'");
}

void readDataset(hid_t loc, const std::string& name, hid_t memType, void* out) {
  Handle set = openCheckedDataset(loc, name);
  check(H5Dread(set.get(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, out),
        "read dataset '" + name + "'");
}

void readDatasetRuns(hid_t loc, const std::string& name, hid_t memType, const Runs& runs,
                     void* out) {
  Handle set = openCheckedDataset(loc, name);
  Handle file = checked(H5Dget_space(set.get()), "read the shape of dataset '" + name + "'");
  check(H5Sselect_none(file.get()), "select in dataset '" + name + "'");
  hsize_t n = 0;
  for (const auto& [first, count] : runs) {
    const hsize_t start[1] = {first}, block[1] = {count};
    check(H5Sselect_hyperslab(file.get(), H5S_SELECT_OR, start, nullptr, block, nullptr),
          "select a part of dataset '" + name + "'");
    n += count;
  }
  if (n == 0) return;
  const hsize_t dims[1] = {n};
  Handle memory = checked(H5Screate_simple(1, dims, nullptr), "create a dataspace");
  check(H5Dread(set.get(), memType, memory.get(), file.get(), H5P_DEFAULT, out),
        "read dataset '" + name + "'");
}

}  // namespace sph::io::cache::h5
