// The HDF5 layer's base (Hdf5.h): its errors as one line, handles that close themselves, the
// property lists every cache file and group is made with, and link and object lookups.
#include "io/cache/Hdf5.h"

#include <algorithm>
#include <cstdlib>

namespace sph::io::cache::h5 {

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

}  // namespace sph::io::cache::h5
