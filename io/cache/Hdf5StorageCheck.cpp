// The check of a dataset's storage before the reader reads it (Hdf5.h: openCheckedDataset).
// HDF5 allocates a chunk by the dimensions its layout records, and a reader allocates the
// dataset's bytes by its shape: a layout's fields pass their header's checksum when only they
// were changed with it. So every chunk must lie in the file, be no larger than the dataset, be
// stored as its filters say, and the dataset hold no more bytes than its stored ones can inflate
// to. These checks ask HDF5 for the layout, once checkHeaders() has checked the headers it
// decodes it from.
#include <cstdint>
#include <string>

#include "io/cache/Hdf5.h"

namespace sph::io::cache::h5 {

Handle openCheckedDataset(hid_t loc, const std::string& name) {
  checkHeaders(loc, name);
  Handle set = checked(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), "open dataset '" + name + "'");
  auto damaged = [&](const std::string& what) {
    return Error("dataset '" + name + "' is damaged", what);
  };
  Handle type = checked(H5Dget_type(set.get()), "read the type of dataset '" + name + "'");
  Handle space = checked(H5Dget_space(set.get()), "read the shape of dataset '" + name + "'");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0 || rank > 8) throw damaged("a shape of " + std::to_string(rank) + " dimensions");
  hsize_t dims[8] = {0};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  // Its bytes once read, overflow checked: what the caller allocates.
  long double bytes = static_cast<long double>(H5Tget_size(type.get()));
  for (int d = 0; d < rank; ++d) bytes *= static_cast<long double>(dims[d]);
  if (bytes == 0) return set;
  Handle file = checked(H5Iget_file_id(set.get()), "find the dataset's file");
  hsize_t fileSize = 0;
  check(H5Fget_filesize(file.get(), &fileSize), "read the file's size");
  Handle dcpl = checked(H5Dget_create_plist(set.get()), "read the layout of '" + name + "'");
  const H5D_layout_t layout = H5Pget_layout(dcpl.get());
  // Deflate packs at most 1032 bytes into one (zlib's limit): no chunk of a file holds more.
  constexpr long double kMostInflation = 1032;
  if (layout == H5D_CONTIGUOUS) {
    const haddr_t at = H5Dget_offset(set.get());
    if (at == HADDR_UNDEF || static_cast<long double>(at) + bytes > fileSize)
      throw damaged("its " + std::to_string(static_cast<unsigned long long>(bytes)) +
                    " bytes are not in the file");
  } else if (layout == H5D_CHUNKED) {
    hsize_t chunk[8] = {0};
    if (H5Pget_chunk(dcpl.get(), rank, chunk) != rank) throw damaged("its chunk has another shape");
    long double chunkBytes = static_cast<long double>(H5Tget_size(type.get()));
    for (int d = 0; d < rank; ++d) {
      if (chunk[d] == 0 || chunk[d] > dims[d]) throw damaged("a chunk larger than the dataset");
      chunkBytes *= static_cast<long double>(chunk[d]);
    }
    // The filters this project's caches use; without deflate a chunk is stored at its size.
    bool inflates = false;
    std::uint64_t checksumBytes = 0;
    const int filters = H5Pget_nfilters(dcpl.get());
    for (int f = 0; f < filters; ++f) {
      unsigned flags = 0, config = 0;
      std::size_t values = 0;
      const H5Z_filter_t id = H5Pget_filter2(dcpl.get(), static_cast<unsigned>(f), &flags,
                                             &values, nullptr, 0, nullptr, &config);
      if (id == H5Z_FILTER_DEFLATE)
        inflates = true;
      else if (id == H5Z_FILTER_FLETCHER32)
        checksumBytes = 4;
      else if (id != H5Z_FILTER_SHUFFLE)
        throw damaged("a filter no cache uses (" + std::to_string(id) + ")");
    }
    hsize_t chunks = 0;
    check(H5Dget_num_chunks(set.get(), space.get(), &chunks), "count the chunks of '" + name + "'");
    long double stored = 0;
    for (hsize_t i = 0; i < chunks; ++i) {
      hsize_t offset[8] = {0}, size = 0;
      haddr_t at = HADDR_UNDEF;
      unsigned mask = 0;
      check(H5Dget_chunk_info(set.get(), space.get(), i, offset, &mask, &at, &size),
            "read chunk " + std::to_string(i) + " of '" + name + "'");
      if (at == HADDR_UNDEF || at > fileSize || size > fileSize - at ||
          chunkBytes > kMostInflation * static_cast<long double>(size) + 64)
        throw damaged("chunk " + std::to_string(i) + " is not in the file");
      // Every filter applied (a skipped one leaves data HDF5 would read as filtered), and an
      // uncompressed chunk exactly its size (HDF5 copies the chunk's size out of what it read).
      if (mask != 0 || (!inflates && static_cast<long double>(size) != chunkBytes + checksumBytes))
        throw damaged("chunk " + std::to_string(i) + " is not stored as its filters say");
      stored += static_cast<long double>(size);
    }
    if (bytes > kMostInflation * stored + 64)
      throw damaged("its " + std::to_string(static_cast<unsigned long long>(bytes)) +
                    " bytes cannot come from the " +
                    std::to_string(static_cast<unsigned long long>(stored)) + " it stores");
  } else if (layout != H5D_COMPACT) {
    throw damaged("a layout the cache does not use");
  }
  return set;
}

}  // namespace sph::io::cache::h5
