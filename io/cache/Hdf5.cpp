#include "io/cache/Hdf5.h"

#include <algorithm>
#include <cstdlib>

namespace sph::io::h5 {

void silence() {
  static const bool done = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

void startWithoutExitCleanup() {
  H5dont_atexit();
  H5open();
}

namespace {

// The serial driver's failed read or write says "file write failed: time = <ctime, with its
// newline>, filename = ..., errno = 28, error message = 'No space left on device', buf = ...":
// "file write failed: No space left on device" keeps a message on one line.
std::string withoutSystemDetail(const std::string& text) {
  const std::string key = "error message = '";
  const std::size_t time = text.find(": time = "), at = text.find(key);
  if (time == std::string::npos || at == std::string::npos) return text;
  const std::size_t from = at + key.size(), to = text.find('\'', from);
  if (to == std::string::npos) return text;
  return text.substr(0, time) + ": " + text.substr(from, to - from);
}

// H5Ewalk2 visits the stack from the innermost call outwards with H5E_WALK_UPWARD; the first
// entry says what actually went wrong ("truncated file", "bad object header version").
herr_t innermost(unsigned n, const H5E_error2_t* e, void* data) {
  if (n != 0) return 0;
  auto* out = static_cast<std::string*>(data);
  if (e->desc && *e->desc) {
    *out = withoutSystemDetail(e->desc);
  } else {
    char msg[256] = {0};
    H5E_type_t type;
    if (H5Eget_msg(e->min_num, &type, msg, sizeof msg) > 0) *out = msg;
  }
  return 0;
}

}  // namespace

std::string errorText() {
  std::string text;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost, &text);
  return text;
}

void Handle::reset() {
  if (id_ < 0) return;
  switch (H5Iget_type(id_)) {
    case H5I_FILE:
      H5Fclose(id_);
      break;
    case H5I_GROUP:
      H5Gclose(id_);
      break;
    case H5I_DATASET:
      H5Dclose(id_);
      break;
    case H5I_DATASPACE:
      H5Sclose(id_);
      break;
    case H5I_DATATYPE:
      H5Tclose(id_);
      break;
    case H5I_ATTR:
      H5Aclose(id_);
      break;
    case H5I_GENPROP_LST:
      H5Pclose(id_);
      break;
    default:
      H5Idec_ref(id_);
      break;
  }
  id_ = -1;
}

void Handle::close(const std::string& what) {
  if (id_ < 0) return;
  const hid_t id = id_;
  id_ = -1;
  herr_t status = 0;
  switch (H5Iget_type(id)) {
    case H5I_FILE:
      status = H5Fclose(id);
      break;
    case H5I_GROUP:
      status = H5Gclose(id);
      break;
    case H5I_DATASET:
      status = H5Dclose(id);
      break;
    default:
      status = H5Idec_ref(id) < 0 ? -1 : 0;
      break;
  }
  check(status, what);
}

namespace {

void setLinkStorage(hid_t plist, unsigned expectedLinks) {
  // Links stay in the group's object header ("compact" storage) up to kMaxCompactLinks, and the
  // header is allocated for the expected count up front, so adding a link rewrites one block of
  // the header in place instead of growing it or converting it to a B-tree (io/cache/CacheWriter.cpp,
  // rootLinkEstimate).
  check(H5Pset_link_phase_change(plist, kMaxCompactLinks, kMaxCompactLinks),
        "set the compact link limit");
  check(H5Pset_est_link_info(plist, std::min(std::max(expectedLinks, 1u), kMaxCompactLinks), 12),
        "set the expected link count");
  // Attributes in the object header too (the root has ~35, a resume record 10): past HDF5's
  // default of 8 they would move to a heap and a B-tree of their own, 2 kB per group.
  check(H5Pset_attr_phase_change(plist, 64, 48), "set the compact attribute limit");
}

}  // namespace

Handle checked(hid_t id, const std::string& what) {
  if (id < 0) throw Error(what, errorText());
  return Handle(id);
}

void check(long long status, const std::string& what) {
  if (status < 0) throw Error(what, errorText());
}

Handle fileCreateProps(unsigned expectedRootLinks) {
  Handle fcpl = checked(H5Pcreate(H5P_FILE_CREATE), "create a file creation property list");
  // Space is only ever taken at the end of the file, never from freed blocks: a block that the
  // last flushed state still points to can then never be overwritten by newer data.
  check(H5Pset_file_space_strategy(fcpl.get(), H5F_FSPACE_STRATEGY_NONE, false, 1),
        "set the file space strategy");
  // The root group's links (a file creation property list carries the root group's settings).
  setLinkStorage(fcpl.get(), expectedRootLinks);
  // Chunk index B-tree nodes for 8 chunks instead of 64: most frame datasets have one chunk, and
  // the default node (2 kB) would weigh more than a small frame's compressed data.
  check(H5Pset_istore_k(fcpl.get(), 4), "set the chunk index node size");
  return fcpl;
}

Handle fileAccessProps() {
  Handle fapl = checked(H5Pcreate(H5P_FILE_ACCESS), "create a file access property list");
  // Objects in the 1.8 formats: checksummed object headers and compact link storage (what the
  // crash safety of the cache relies on, see io/cache/CacheCommit.cpp) and superblock version 2, which
  // unlike version 3 carries no "file open for writing" flag: a killed writer leaves no flag that
  // would make readers refuse the file. The upper bound 1.10 is only for the one 1.10 message,
  // the file space strategy (fileCreateProps); so HDF5 >= 1.10 reads the caches (ParaView, h5py).
  check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V110),
        "set the HDF5 format version");
  // No flock(): a cache being written can be inspected (sphsplat info, h5dump with
  // HDF5_USE_FILE_LOCKING=FALSE, ParaView) while the run goes on. The writer takes a lock of its
  // own against a second writer (CacheWriter).
  check(H5Pset_file_locking(fapl.get(), false, true), "disable HDF5 file locking");
  return fapl;
}

Handle groupCreateProps(unsigned expectedLinks) {
  Handle gcpl = checked(H5Pcreate(H5P_GROUP_CREATE), "create a group creation property list");
  setLinkStorage(gcpl.get(), expectedLinks);
  return gcpl;
}

bool hasLink(hid_t loc, const std::string& name) {
  return H5Lexists(loc, name.c_str(), H5P_DEFAULT) > 0;
}

bool hasPath(hid_t loc, const std::string& path) {
  // H5Lexists fails, rather than saying no, when a component before the last is missing.
  for (std::size_t end = path.find('/');; end = path.find('/', end + 1)) {
    if (!hasLink(loc, path.substr(0, end))) return false;
    if (end == std::string::npos) return true;
  }
}

bool hasAttribute(hid_t obj, const std::string& name) {
  return H5Aexists(obj, name.c_str()) > 0;
}

H5O_type_t objectType(hid_t loc, const std::string& name) {
  if (!hasLink(loc, name)) return H5O_TYPE_UNKNOWN;
  checkHeaders(loc, name);  // HDF5 reads the whole header, continuations too
  H5O_info_t info;
  if (H5Oget_info_by_name2(loc, name.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0)
    return H5O_TYPE_UNKNOWN;
  return info.type;
}

namespace {

void writeScalar(hid_t obj, const std::string& name, hid_t fileType, hid_t memType,
                 const void* value) {
  Handle space = checked(H5Screate(H5S_SCALAR), "create a dataspace");
  Handle attr =
      checked(H5Acreate2(obj, name.c_str(), fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              "create attribute '" + name + "'");
  check(H5Awrite(attr.get(), memType, value), "write attribute '" + name + "'");
}

void writeArray(hid_t obj, const std::string& name, hid_t fileType, hid_t memType,
                const void* values, std::size_t n) {
  const hsize_t dims[1] = {n};
  Handle space =
      checked(n ? H5Screate_simple(1, dims, nullptr) : H5Screate(H5S_NULL), "create a dataspace");
  Handle attr =
      checked(H5Acreate2(obj, name.c_str(), fileType, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              "create attribute '" + name + "'");
  if (n) check(H5Awrite(attr.get(), memType, values), "write attribute '" + name + "'");
}

// A fixed-length, NUL-terminated UTF-8 string type holding `length` characters.
Handle stringType(std::size_t length) {
  Handle type = checked(H5Tcopy(H5T_C_S1), "copy the string type");
  check(H5Tset_size(type.get(), length + 1), "size a string type");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), "terminate a string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set UTF-8");
  return type;
}

Handle openAttribute(hid_t obj, const std::string& name) {
  return checked(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "open attribute '" + name + "'");
}

// Element count of an attribute that must hold numbers of class `cls` (integer or float).
std::size_t numericAttribute(hid_t attr, const std::string& name, bool allowFloat, bool allowInt) {
  Handle type = checked(H5Aget_type(attr), "read the type of attribute '" + name + "'");
  const H5T_class_t cls = H5Tget_class(type.get());
  if (!((allowFloat && cls == H5T_FLOAT) || (allowInt && cls == H5T_INTEGER))) {
    throw Error("attribute '" + name + "' is not " + (allowFloat ? "a number" : "an integer"), "");
  }
  Handle space = checked(H5Aget_space(attr), "read the shape of attribute '" + name + "'");
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  check(n, "count attribute '" + name + "'");
  return static_cast<std::size_t>(n);
}

template <class T>
T readNumber(hid_t obj, const std::string& name, hid_t memType, bool allowFloat) {
  Handle attr = openAttribute(obj, name);
  if (numericAttribute(attr.get(), name, allowFloat, true) != 1) {
    throw Error("attribute '" + name + "' is not a single number", "");
  }
  T value{};
  check(H5Aread(attr.get(), memType, &value), "read attribute '" + name + "'");
  return value;
}

template <class T>
std::vector<T> readNumbers(hid_t obj, const std::string& name, hid_t memType, bool allowFloat) {
  Handle attr = openAttribute(obj, name);
  std::vector<T> values(numericAttribute(attr.get(), name, allowFloat, true));
  if (!values.empty())
    check(H5Aread(attr.get(), memType, values.data()), "read attribute '" + name + "'");
  return values;
}

}  // namespace

void writeAttribute(hid_t obj, const std::string& name, const std::string& value) {
  Handle type = checked(H5Tcopy(H5T_C_S1), "copy the string type");
  check(H5Tset_size(type.get(), H5T_VARIABLE), "make a variable-length string type");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "set UTF-8");
  const char* text = value.c_str();
  writeScalar(obj, name, type.get(), type.get(), &text);
}

void writeFixedAttribute(hid_t obj, const std::string& name, const std::string& value,
                         std::size_t width) {
  const std::size_t length = std::max(width, value.size());
  Handle type = stringType(length);
  std::string padded = value;
  padded.resize(length + 1, '\0');
  writeScalar(obj, name, type.get(), type.get(), padded.data());
}

void writeAttribute(hid_t obj, const std::string& name, double value) {
  writeScalar(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}
void writeAttribute(hid_t obj, const std::string& name, float value) {
  writeScalar(obj, name, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, &value);
}
void writeAttribute(hid_t obj, const std::string& name, std::int64_t value) {
  writeScalar(obj, name, H5T_STD_I64LE, H5T_NATIVE_INT64, &value);
}
void writeAttribute(hid_t obj, const std::string& name, std::uint64_t value) {
  writeScalar(obj, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, &value);
}
void writeAttribute(hid_t obj, const std::string& name, const std::vector<double>& values) {
  writeArray(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, values.data(), values.size());
}
void writeAttribute(hid_t obj, const std::string& name, const std::vector<std::uint64_t>& values) {
  writeArray(obj, name, H5T_STD_U64LE, H5T_NATIVE_UINT64, values.data(), values.size());
}

void rewriteAttribute(hid_t obj, const std::string& name, const std::string& value) {
  Handle attr = openAttribute(obj, name);
  Handle type = checked(H5Aget_type(attr.get()), "read the type of attribute '" + name + "'");
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
    throw Error("attribute '" + name + "' is not a fixed-length string", "");
  }
  const std::size_t size = H5Tget_size(type.get());
  std::string padded = value.substr(0, size > 0 ? size - 1 : 0);
  padded.resize(size, '\0');
  check(H5Awrite(attr.get(), type.get(), padded.data()), "write attribute '" + name + "'");
}

std::string readStringAttribute(hid_t obj, const std::string& name) {
  Handle attr = openAttribute(obj, name);
  Handle type = checked(H5Aget_type(attr.get()), "read the type of attribute '" + name + "'");
  if (H5Tget_class(type.get()) != H5T_STRING)
    throw Error("attribute '" + name + "' is not a string", "");
  Handle space = checked(H5Aget_space(attr.get()), "read the shape of attribute '" + name + "'");
  if (H5Sget_simple_extent_npoints(space.get()) != 1)
    throw Error("attribute '" + name + "' is not one string", "");
  if (H5Tis_variable_str(type.get()) > 0) {
    checkHeapString(obj, name);
    // Read with the attribute's own type: its character set (UTF-8 or ASCII) is kept as it is.
    char* text = nullptr;
    check(H5Aread(attr.get(), type.get(), &text), "read attribute '" + name + "'");
    std::string value = text ? text : "";
    H5free_memory(text);
    return value;
  }
  std::string value(H5Tget_size(type.get()), '\0');
  check(H5Aread(attr.get(), type.get(), value.data()), "read attribute '" + name + "'");
  value.resize(value.find('\0') == std::string::npos ? value.size() : value.find('\0'));
  return value;
}

double readDoubleAttribute(hid_t obj, const std::string& name) {
  return readNumber<double>(obj, name, H5T_NATIVE_DOUBLE, true);
}
float readFloatAttribute(hid_t obj, const std::string& name) {
  return readNumber<float>(obj, name, H5T_NATIVE_FLOAT, true);
}
std::int64_t readIntAttribute(hid_t obj, const std::string& name) {
  return readNumber<std::int64_t>(obj, name, H5T_NATIVE_INT64, false);
}
std::uint64_t readUintAttribute(hid_t obj, const std::string& name) {
  return readNumber<std::uint64_t>(obj, name, H5T_NATIVE_UINT64, false);
}
std::vector<double> readDoubleArrayAttribute(hid_t obj, const std::string& name) {
  return readNumbers<double>(obj, name, H5T_NATIVE_DOUBLE, true);
}
std::vector<std::uint64_t> readUintArrayAttribute(hid_t obj, const std::string& name) {
  return readNumbers<std::uint64_t>(obj, name, H5T_NATIVE_UINT64, false);
}

std::vector<std::string> attributeNames(hid_t obj) {
  std::vector<std::string> names;
  H5O_info_t info;
  check(H5Oget_info2(obj, &info, H5O_INFO_NUM_ATTRS), "count attributes");
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const ssize_t len =
        H5Aget_name_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    check(len, "read an attribute name");
    std::string name(static_cast<std::size_t>(len) + 1, '\0');
    check(H5Aget_name_by_idx(obj, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                             H5P_DEFAULT),
          "read an attribute name");
    name.resize(static_cast<std::size_t>(len));
    names.push_back(name);
  }
  return names;
}

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

}  // namespace sph::io::h5
