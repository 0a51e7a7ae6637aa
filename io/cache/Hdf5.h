// A thin RAII layer over the HDF5 C API (libhdf5 1.10), just what the cache writer and reader
// need: move-only handles that close themselves, checked calls that turn HDF5's error stack into
// one line, attributes and 1-D datasets of plain numbers and strings.
//
// HDF5 prints its error stack to stderr by default; silence() turns that off so a broken cache
// gives the user one line (STYLE.md rule 10), built from the innermost HDF5 message.
#pragma once

#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph::io::cache::h5 {

// A failed HDF5 call: `what` we tried, then HDF5's own innermost description.
class Error : public std::runtime_error {
 public:
  Error(const std::string& what, std::string detail)
      : std::runtime_error(detail.empty() ? what : what + " (" + detail + ")"),
        detail_(std::move(detail)) {}
  // HDF5's description alone, e.g. "truncated file: eof = 4096, ... stored_eof = 81920".
  const std::string& detail() const { return detail_; }

 private:
  std::string detail_;
};

// Before HDF5 reads the variable-length string attribute `name` of `object`: checks, in the file
// itself, that the global heap object it points to lies whole in its collection and has the
// string's length (io/cache/Hdf5HeapCheck.cpp), and throws Error(what is damaged) if not.
void checkHeapString(hid_t object, const std::string& name);

// Turns off HDF5's automatic error printing for this process (idempotent).
void silence();
// Starts the library without its clean-up at exit (or at MPI_Finalize, when MPI starts after
// it): call first in main, before MPI and before any other HDF5 call. A file whose close failed
// (a full disk) stays registered in HDF5 1.10 with its memory already freed, and that clean-up
// would close it again and crash; every file is closed explicitly before the program ends.
void startWithoutExitCleanup();
// The innermost message of the current thread's HDF5 error stack ("" if empty).
std::string errorText();

// Owns one HDF5 identifier of any kind and closes it with the matching H5?close.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(o.id_) { o.id_ = -1; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) reset(), id_ = o.id_, o.id_ = -1;
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  hid_t get() const { return id_; }
  explicit operator bool() const { return id_ >= 0; }
  void reset();
  // Forgets the identifier without closing it (a file whose close would be a collective call
  // the other processes will not make).
  void release() { id_ = -1; }
  // Closes now and reports a failure (a file's close writes what is left).
  void close(const std::string& what);

 private:
  hid_t id_ = -1;
};

// Wraps an identifier returned by the C API; throws Error(what) if it is negative.
Handle checked(hid_t id, const std::string& what);
// Throws Error(what) if an herr_t/htri_t status is negative.
void check(long long status, const std::string& what);

// Most links a group keeps in its object header (HDF5's limit for compact link storage).
inline constexpr unsigned kMaxCompactLinks = 65535;

// Property lists.
Handle fileCreateProps(unsigned expectedRootLinks);
Handle fileAccessProps();
Handle groupCreateProps(unsigned expectedLinks);

// Does `name` (one path component) exist as a link in `loc`?
bool hasLink(hid_t loc, const std::string& name);
// Does the relative path "a/b/c" exist in `loc` (every component, checked in turn)?
bool hasPath(hid_t loc, const std::string& path);
bool hasAttribute(hid_t obj, const std::string& name);
// H5O_TYPE_GROUP, H5O_TYPE_DATASET... of the object `name` in `loc`, or H5O_TYPE_UNKNOWN.
H5O_type_t objectType(hid_t loc, const std::string& name);

// Attributes. A string is written as a variable-length UTF-8 string, which h5py reads as `str`
// (a fixed-length one comes back as `bytes`). Its characters go to HDF5's global heap, whose
// blocks a later string can extend in place: CacheWriter writes such strings only where no
// committed block can be touched (before the first commit, or right after reopening the file).
void writeAttribute(hid_t obj, const std::string& name, const std::string& value);
// A fixed-length UTF-8 string of `width` characters (at least the value's), stored in the object
// header itself: for a value rewritten in place later (rewriteAttribute), and where a
// specification asks for fixed-length strings (the HDF5 Image attributes).
void writeFixedAttribute(hid_t obj, const std::string& name, const std::string& value,
                         std::size_t width = 0);
void writeAttribute(hid_t obj, const std::string& name, double value);
void writeAttribute(hid_t obj, const std::string& name, float value);
void writeAttribute(hid_t obj, const std::string& name, std::int64_t value);
void writeAttribute(hid_t obj, const std::string& name, std::uint64_t value);
void writeAttribute(hid_t obj, const std::string& name, const std::vector<double>& values);
void writeAttribute(hid_t obj, const std::string& name, const std::vector<std::uint64_t>& values);
// Overwrites an existing fixed-length string attribute in place (truncated to its width).
void rewriteAttribute(hid_t obj, const std::string& name, const std::string& value);

// Either kind of string: variable-length (caches since the change to h5py-friendly strings) or
// fixed-length, UTF-8 or ASCII (older caches, run_status, image attributes).
std::string readStringAttribute(hid_t obj, const std::string& name);
double readDoubleAttribute(hid_t obj, const std::string& name);
float readFloatAttribute(hid_t obj, const std::string& name);
std::int64_t readIntAttribute(hid_t obj, const std::string& name);
std::uint64_t readUintAttribute(hid_t obj, const std::string& name);
std::vector<double> readDoubleArrayAttribute(hid_t obj, const std::string& name);
std::vector<std::uint64_t> readUintArrayAttribute(hid_t obj, const std::string& name);
std::vector<std::string> attributeNames(hid_t obj);

// The deflate level written with zlib's run-length strategy (Storage::deflateLevel).
constexpr int kRunLengthLevel = 1;

// How a dataset is stored. Chunked datasets get the byte shuffle before deflate (it groups the
// bytes of equal significance, which is what makes float arrays compress).
struct Storage {
  // 0 = no compression; 2-9 zlib's levels; 1 (kRunLengthLevel) zlib's run-length strategy where
  // writeDataset deflates the chunks itself (the 1-D datasets one process writes, every frame
  // field; HDF5's own filter, which writes the others, takes 1 as zlib's level 1).
  // After the byte shuffle most of a float field's bytes are mantissa noise, in which deflate's
  // search for matches finds nothing: the run-length strategy spends no time on it and keeps the
  // runs of the exponent bytes: the peer's dam break's frames 2.2x faster than level 4 for 8%
  // more bytes (docs/benchmarks.md, "HDF5 cache"). Every zlib reader decodes either.
  int deflateLevel = 0;
  // Upper bound of one chunk (bytes). 128 KiB: a frame's field of 117,649 floats is 4 chunks,
  // which writeDataset deflates on 4 threads at once; 0.9% larger than one chunk of it.
  std::size_t chunkBytes = 128 << 10;
  // Written by all ranks together (writeDatasetPart): no fill values, which parallel HDF5 would
  // write into the space it allocates at creation before the ranks write their parts.
  bool collective = false;
};

// Creates a dataset of shape `dims` in `loc` named `name`, or an anonymous one (linked later with
// H5Olink) if `name` is empty. Chunk shape: the whole extent, cut along the first axis to at most
// storage.chunkBytes.
Handle createDataset(hid_t loc, const std::string& name, hid_t fileType,
                     const std::vector<hsize_t>& dims, const Storage& storage);

// Writes a 1-D dataset `name` in `loc` from `count` values of `memType` (a native type),
// stored as `fileType` (e.g. H5T_IEEE_F32LE). Returns the bytes it takes in the file.
std::uint64_t writeDataset(hid_t loc, const std::string& name, hid_t memType, hid_t fileType,
                           const void* data, std::size_t count, const Storage& storage);

// Parallel HDF5 (Hdf5Parallel.cpp): whether this build has it, so that the ranks of an MPI run
// write the cache together (docs/scaling.md, "The cache is written by all ranks").
bool haveParallel();
// File access through MPI-IO on all processes of MPI_COMM_WORLD: each call on the file is then
// collective. Only where haveParallel().
Handle parallelFileAccessProps();

// This process's part of a 1-D dataset written by all processes together: the dataset holds
// `total` values; this process's values, in order, go to `runs` (first index, count).
struct Part {
  std::uint64_t total = 0;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> runs;
  std::size_t count() const;  // this process's values
};
// Like writeDataset, collectively (every process calls it, each with its part; collective
// transfers, which parallel HDF5 needs for filters): the values this process holds.
std::uint64_t writeDatasetPart(hid_t loc, const std::string& name, hid_t memType, hid_t fileType,
                               const void* data, const Part& part, const Storage& storage);

// Creates `name` in `loc`: a virtual dataset of shape [count][3] whose columns are the 1-D
// datasets `columns` (paths in the same file, `count` values each), stored as `fileType`. No data
// is copied; readers of HDF5 1.10 and later read it like any dataset. Its mapping goes to the
// global heap (see writeAttribute on strings).
void createColumnView(hid_t loc, const std::string& name, hid_t fileType, std::size_t count,
                      const std::vector<std::string>& columns);

// Opens the dataset `name` of `loc` for reading once its headers (checkHeaders) and its
// storage have been checked against the file (io/cache/Hdf5StorageCheck.cpp): every chunk
// within the file, no chunk larger than the dataset, and no more bytes than its stored ones can
// inflate to (a damaged shape or layout would otherwise make the reader, or HDF5, allocate what
// the file never held). Throws Error if not.
Handle openCheckedDataset(hid_t loc, const std::string& name);

// Checks, from the file's bytes, the object headers on the way to `name` (a path in `loc`) and
// its own, before HDF5 decodes them (io/cache/Hdf5Checks.cpp): addresses at blocks of the kind they
// name, links and attributes whole within their messages, a dataset's shape, type and layout
// consistent with each other and with the file's size. HDF5 1.10 reads past its buffers or
// allocates without bound at such damage when a header's checksum still matches. Throws Error.
void checkHeaders(hid_t loc, const std::string& name);
// Opens the group `name` of `loc` once checkHeaders() has passed.
Handle openCheckedGroup(hid_t loc, const std::string& name);
// The same check of the root group's header, from the file at `path`, before HDF5 opens it.
void checkRootHeader(const std::string& path);

// A 1-D dataset's element count; throws Error if it is not a 1-D numeric dataset.
std::size_t datasetLength(hid_t loc, const std::string& name);
// Reads a whole 1-D dataset converted to `memType`; `out` must hold datasetLength() values.
void readDataset(hid_t loc, const std::string& name, hid_t memType, void* out);
// Index runs (first, count) of a 1-D dataset, ascending and disjoint.
using Runs = std::vector<std::pair<std::uint64_t, std::uint64_t>>;
// Reads the values of `runs`, in order, converted to `memType`; `out` holds their total count
// (a resume on K processes: each rank reads its slab, job/distributed/DistributedResume.h).
void readDatasetRuns(hid_t loc, const std::string& name, hid_t memType, const Runs& runs,
                     void* out);

template <class T>
hid_t nativeType();
template <>
inline hid_t nativeType<float>() {
  return H5T_NATIVE_FLOAT;
}
template <>
inline hid_t nativeType<double>() {
  return H5T_NATIVE_DOUBLE;
}
template <>
inline hid_t nativeType<std::uint32_t>() {
  return H5T_NATIVE_UINT32;
}
template <>
inline hid_t nativeType<std::uint8_t>() {
  return H5T_NATIVE_UINT8;
}

// Reads a whole 1-D dataset converted to `memType`, opened and checked once: `place(n)` is given
// its length and returns where its n values go.
void readDatasetInto(hid_t loc, const std::string& name, hid_t memType,
                     const std::function<void*(std::size_t)>& place);

template <class T>
std::vector<T> readDataset(hid_t loc, const std::string& name) {
  std::vector<T> out;
  readDatasetInto(loc, name, nativeType<T>(), [&](std::size_t n) {
    out.resize(n);
    return static_cast<void*>(out.data());
  });
  return out;
}

// The whole dataset, or with `runs` only their values.
template <class T>
std::vector<T> readDataset(hid_t loc, const std::string& name, const Runs* runs) {
  if (!runs) return readDataset<T>(loc, name);
  std::size_t n = 0;
  for (const auto& run : *runs) n += run.second;
  std::vector<T> out(n);
  if (n > 0) readDatasetRuns(loc, name, nativeType<T>(), *runs, out.data());
  return out;
}

}  // namespace sph::io::cache::h5
