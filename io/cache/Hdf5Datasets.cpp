// Datasets: creating and writing them (chunked, shuffled and deflated as Storage asks), the
// virtual column views, and reading 1-D numeric ones whole or in runs, each opened through
// openCheckedDataset (Hdf5StorageCheck.cpp) so that a damaged shape or layout is refused before
// anything is allocated by it.
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "io/cache/Hdf5.h"
#include "sim/Parallel.h"

namespace sph::io::cache::h5 {

namespace {

// The first axis of the chunks createDataset gives a dataset of shape `dims` whose elements take
// `elementBytes`: the whole extent, cut to at most storage.chunkBytes; 0 for a contiguous one
// (no compression, or empty: a chunk must fit the extent).
hsize_t chunkRows(const std::vector<hsize_t>& dims, std::size_t elementBytes,
                  const Storage& storage) {
  hsize_t elements = 1;
  for (hsize_t d : dims) elements *= d;
  if (storage.deflateLevel <= 0 || elements == 0) return 0;
  const hsize_t rowBytes = elementBytes * (elements / dims[0]);
  return std::max<hsize_t>(1, std::min<hsize_t>(dims[0], storage.chunkBytes / rowBytes));
}

}  // namespace

Handle createDataset(hid_t loc, const std::string& name, hid_t fileType,
                     const std::vector<hsize_t>& dims, const Storage& storage) {
  const std::string label =
      name.empty() ? std::string("an anonymous dataset") : "dataset '" + name + "'";
  Handle space = checked(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                         "create a dataspace");
  Handle dcpl = checked(H5Pcreate(H5P_DATASET_CREATE), "create a dataset creation property list");
  const hsize_t rows = chunkRows(dims, H5Tget_size(fileType), storage);
  if (rows > 0) {
    std::vector<hsize_t> chunk = dims;
    chunk[0] = rows;
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

namespace {

// One chunk as HDF5's filters leave it: `count` elements of `size` bytes from `in`, zeros after
// them up to `chunk` elements (an edge chunk is filtered at full size, padded as the library
// pads it), byte-shuffled (byte b of element e to b * chunk + e: H5Z's shuffle filter) and
// deflated (a zlib stream, which H5Z's deflate filter reads). Levels 2-9 as H5Z's filter writes
// them (compress2 at `level`); level 1 with zlib's run-length strategy (matches of distance 1
// only, Storage::deflateLevel says why). Empty if zlib failed (it runs inside a parallel loop,
// which an exception must not leave).
std::vector<Bytef> filteredChunk(const unsigned char* in, std::size_t count, std::size_t size,
                                 std::size_t chunk, int level) {
  std::vector<Bytef> shuffled(chunk * size, 0);
  for (std::size_t e = 0; e < count; ++e)
    for (std::size_t b = 0; b < size; ++b) shuffled[b * chunk + e] = in[e * size + b];
  std::vector<Bytef> out(compressBound(static_cast<uLong>(shuffled.size())));
  z_stream z{};
  // compress2() is deflateInit() at `level`, the default strategy, window 15 and memory level 8.
  const int strategy = level == kRunLengthLevel ? Z_RLE : Z_DEFAULT_STRATEGY;
  if (deflateInit2(&z, level, Z_DEFLATED, 15, 8, strategy) != Z_OK) return {};
  z.next_in = shuffled.data();
  z.avail_in = static_cast<uInt>(shuffled.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  const bool done = deflate(&z, Z_FINISH) == Z_STREAM_END;
  out.resize(done ? z.total_out : 0);
  deflateEnd(&z);
  return out;
}

// Writes `count` values to the 1-D dataset `set` (created by createDataset with the shuffle and
// deflate filters) chunk by chunk, the chunks filtered on all threads first. H5Dwrite filters a
// dataset's chunks one after another on the calling thread: deflate was most of a frame's
// write (docs/benchmarks.md, "HDF5 cache"), and the simulation waits for it. The file
// holds the same bytes as H5Dwrite would write (tests/test_cache_format.cpp,
// ChunksDeflatedOnAllThreadsAreHdf5sOwn).
void writeFilteredChunks(hid_t set, const void* data, std::size_t count, std::size_t size,
                         std::size_t chunk, int level, const std::string& name) {
  const std::size_t chunks = (count + chunk - 1) / chunk;
  std::vector<std::vector<Bytef>> filtered(chunks);
  const auto* bytes = static_cast<const unsigned char*>(data);
  parallelForDynamic(chunks, 1, [&](std::size_t c) {
    const std::size_t first = c * chunk;
    filtered[c] =
        filteredChunk(bytes + first * size, std::min(chunk, count - first), size, chunk, level);
  });
  for (std::size_t c = 0; c < chunks; ++c) {
    if (filtered[c].empty())
      throw Error("write dataset '" + name + "'", "zlib could not deflate it");
    const hsize_t offset[1] = {static_cast<hsize_t>(c * chunk)};
    check(H5Dwrite_chunk(set, H5P_DEFAULT, 0, offset, filtered[c].size(), filtered[c].data()),
          "write dataset '" + name + "'");
  }
}

}  // namespace

std::uint64_t writeDataset(hid_t loc, const std::string& name, hid_t memType, hid_t fileType,
                           const void* data, std::size_t count, const Storage& storage) {
  Handle set = createDataset(loc, name, fileType, {static_cast<hsize_t>(count)}, storage);
  // Values whose memory layout is the file's (native little-endian types on this CPU): filtered
  // here, the chunks on all threads. Otherwise HDF5 converts and filters.
  const std::size_t size = H5Tget_size(fileType);
  const hsize_t chunk = chunkRows({static_cast<hsize_t>(count)}, size, storage);
  if (chunk > 0 && !storage.collective && H5Tequal(memType, fileType) > 0) {
    writeFilteredChunks(set.get(), data, count, size, static_cast<std::size_t>(chunk),
                        storage.deflateLevel, name);
  } else if (count > 0) {
    check(H5Dwrite(set.get(), memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
          "write dataset '" + name + "'");
  }
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
