// CacheReader's opening of a cache: the file checked to be a readable sphsplat cache (retried
// while a run commits to it, repaired from the journal when a kill tore a header), its header
// read into the summary, its frames and rendered pictures listed, and their size measured.
// Frames and the resume record are read in CacheReaderFrames.cpp and CacheReaderResume.cpp.
#include "io/cache/CacheReader.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <set>
#include <thread>

#include "io/cache/CacheJournal.h"
#include "io/cache/CacheWriter.h"
#include "io/UserFiles.h"
#include "sim/InputError.h"

namespace sph::io::cache {
namespace {

using h5::checked;

struct Links {
  std::set<std::string> names;
  haddr_t highest = 0;  // the highest object address a hard link points to (HDF5 address)
};

herr_t collectLink(hid_t, const char* name, const H5L_info_t* info, void* data) {
  auto* links = static_cast<Links*>(data);
  links->names.insert(name);
  if (info->type == H5L_TYPE_HARD) links->highest = std::max(links->highest, info->u.address);
  return 0;
}

// The links of a group, read in one pass (looking each frame up by name would cost O(frames) per
// lookup in compact link storage).
Links groupLinks(hid_t group) {
  Links links;
  hsize_t index = 0;
  h5::check(H5Literate(group, H5_INDEX_NAME, H5_ITER_NATIVE, &index, collectLink, &links),
            "list links");
  return links;
}

std::set<std::string> linkNames(hid_t group) {
  return groupLinks(group).names;
}

// "stored_eof = 123" out of HDF5's truncation message.
std::string numberAfter(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return "";
  std::size_t pos = at + key.size();
  std::size_t end = pos;
  while (end < text.size() && text[end] >= '0' && text[end] <= '9') ++end;
  return text.substr(pos, end - pos);
}

// "12" -> 12; false for anything but decimal digits.
bool frameNumber(const std::string& text, std::size_t& out) {
  if (text.empty() || text.size() > 18 || text.find_first_not_of("0123456789") != std::string::npos)
    return false;
  out = static_cast<std::size_t>(std::stoull(text));
  return true;
}

}  // namespace

void CacheReader::fail(const std::string& message) const {
  throw InputError(path_ + ": " + message);
}

CacheReader::CacheReader(const std::string& path) : path_(path) {
  h5::silence();
  struct stat st {};
  if (stat(path.c_str(), &st) != 0)
    fail(std::string("cannot open the cache (") + std::strerror(errno) + ")");
  // A directory, a device or a FIFO (opening which would wait for a writer for ever) is no cache.
  if (!S_ISREG(st.st_mode)) fail("is " + nonRegularKind(path) + ", expected an HDF5 cache file");
  const htri_t isHdf5 = H5Fis_hdf5(path.c_str());
  if (isHdf5 < 0) fail("cannot read the file (" + h5::errorText() + ")");
  if (isHdf5 == 0) fail("not an HDF5 file (no HDF5 signature); expected a sphsplat cache");
  // A run may be writing the cache: a reader that opens it in the middle of a commit can meet a
  // header half rewritten (it fails HDF5's checksum) or a superblock older than the root header
  // that links the new frame (the frame then reads past the file's end). Both pass once the
  // commit is over, so while a run holds the cache a failed or partial read is tried again; every
  // complete read is a committed state (docs/cache-format.md, "Reading while a run writes").
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (cacheIsLocked(path)) {
    try {
      load();
      if (summary_.damagedFrame.empty()) return;
    } catch (const InputError&) {
      if (std::chrono::steady_clock::now() > deadline) throw;
    }
    if (std::chrono::steady_clock::now() > deadline) return;  // damagedFrame says what is wrong
    file_.reset();
    summary_ = CacheSummary{};
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  // No run writes the file: what is on disk stays as it is.
  try {
    load();
  } catch (const InputError& original) {
    // A header torn by a kill in the middle of a commit fails HDF5's checksum: put back the copy
    // the writer journaled (CacheJournal.h) and try again; undo that if it did not help. Only
    // here, with no run holding the file: a run's commit in progress looks the same to a reader
    // and must not be undone.
    if (std::string(original.what()).find("checksum") == std::string::npos) throw;
    JournalRepair repair;
    if (!repairFromJournal(path, repair)) throw;
    try {
      file_.reset();
      summary_ = CacheSummary{};
      load();
      summary_.repaired = true;
    } catch (const InputError&) {
      file_.reset();
      undoRepair(repair);
      throw original;
    }
  }
}

void CacheReader::load() {
  struct stat st {};
  stat(path_.c_str(), &st);
  summary_.path = path_;
  summary_.fileBytes = static_cast<std::uint64_t>(st.st_size);
  // No libver bounds for reading: those only govern what a writer may create.
  h5::Handle fapl = checked(H5Pcreate(H5P_FILE_ACCESS), "create a file access property list");
  h5::check(H5Pset_file_locking(fapl.get(), false, true), "disable file locking");
  try {
    h5::checkRootHeader(path_);
  } catch (const h5::Error& e) {
    fail(std::string("damaged HDF5 file: ") + e.what());
  }
  hid_t file = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, fapl.get());
  // HDF5 shares one open file per process and refuses to open it again with other locking
  // settings (when the program already has it open, e.g. through h5py or the C API).
  if (file < 0 &&
      h5::errorText().find("file locking flag values don't match") != std::string::npos) {
    file = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  }
  if (file < 0) {
    const std::string detail = h5::errorText();
    if (detail.find("truncated file") != std::string::npos) {
      // HDF5 stores the end of file as a file offset (the user block included).
      const std::string stored = numberAfter(detail, "stored_eof = ");
      const unsigned long long expected = stored.empty() ? 0ull : std::stoull(stored);
      fail("truncated HDF5 file: " + std::to_string(st.st_size) +
           " bytes, but its superblock says " + std::to_string(expected) +
           " (an interrupted copy or download?)");
    }
    fail("damaged HDF5 file, cannot open it (HDF5: " + detail + ")");
  }
  file_ = h5::Handle(file);
  // Load the root group's header now: a damaged one is reported as such, not as a missing name.
  H5O_info_t root;
  if (H5Oget_info2(file, &root, H5O_INFO_BASIC | H5O_INFO_HDR) < 0) {
    fail("damaged HDF5 file, cannot read its root group (HDF5: " + h5::errorText() + ")");
  }
  readHeader();
  const Links links = groupLinks(file);
  // Opened in the middle of a run's commit, the superblock can come from before it and the root
  // header from after it: the new frame then lies past the end of the file as this reader knows
  // it (every object the root links is allocated before the superblock that covers it is
  // written, and after every older one).
  haddr_t eoa = 0;
  hsize_t userBlock = 0;
  h5::Handle fcpl = checked(H5Fget_create_plist(file), "read the file creation properties");
  const bool known = H5Fget_eoa(file, &eoa) >= 0 && H5Pget_userblock(fcpl.get(), &userBlock) >= 0;
  // A run's file is longer than its data while the run goes on (io/cache/CacheCommit.cpp, point 4).
  if (known) summary_.fileBytes = std::min<std::uint64_t>(summary_.fileBytes, eoa);
  if (known && links.highest + userBlock >= eoa && !links.names.empty()) {
    fail("damaged HDF5 file: the root group links an object at byte " +
         std::to_string(links.highest + userBlock) +
         ", past the end of the file its superblock gives (" + std::to_string(eoa) + ")");
  }
  scanFrames(links.names);
  scanRenderers(links.names);
}

void CacheReader::readHeader() {
  const hid_t root = file_.get();
  if (!h5::hasAttribute(root, cache::kFormatAttr)) {
    fail(std::string("an HDF5 file but not a sphsplat cache (no root attribute '") +
         cache::kFormatAttr + "'; written by another program?)");
  }
  CacheSummary& s = summary_;
  std::string attribute;
  try {
    auto text = [&](const char* name) { return h5::readStringAttribute(root, attribute = name); };
    auto integer = [&](const char* name) { return h5::readIntAttribute(root, attribute = name); };
    const std::string format = text(cache::kFormatAttr);
    if (format != cache::kFormatName) {
      fail(std::string("an HDF5 file but not a sphsplat cache (root attribute '") +
           cache::kFormatAttr + "' is \"" + format + "\")");
    }
    s.formatVersion = integer(cache::kFormatVersionAttr);
    if (s.formatVersion > cache::kFormatVersion || s.formatVersion < 1) {
      fail("cache format version " + std::to_string(s.formatVersion) +
           " is not one this sphsplat reads (" + std::to_string(cache::kFormatVersion) + ")");
    }
    s.programVersion = text("sphsplat_version");
    s.created = text("created");
    s.status = text(cache::kStatusAttr);
    s.sceneName = text("scene_name");
    s.scenePath = text("scene_path");
    s.sceneText = text("scene_text");
    s.sceneOverrides = text("scene_overrides");
    s.sceneFingerprint = text("scene_fingerprint");
    s.threads = integer("threads");
    s.fps = h5::readDoubleAttribute(root, attribute = "output.fps");
    s.compression = static_cast<int>(integer("output.compression"));
    s.restart = integer("output.restart") != 0;
    s.doublePositions = integer("output.double_positions") != 0;
    std::vector<std::string> names;
    const std::string list = text("output.fields");
    for (std::size_t pos = 0; pos < list.size();) {
      const std::size_t end = std::min(list.find(' ', pos), list.size());
      if (end > pos) names.push_back(list.substr(pos, end - pos));
      pos = end + 1;
    }
    std::string error;
    s.fields = cache::parseFields(names, error);
    if (!error.empty()) fail("root attribute output.fields: " + error);
    for (const std::string& name : h5::attributeNames(root)) {
      if (name.rfind("solver.", 0) != 0) continue;
      attribute = name;
      h5::Handle a = checked(H5Aopen(root, name.c_str(), H5P_DEFAULT), "open attribute");
      h5::Handle type = checked(H5Aget_type(a.get()), "read its type");
      cache::Parameter p;
      p.name = name;
      p.isText = H5Tget_class(type.get()) == H5T_STRING;
      if (p.isText)
        p.text = h5::readStringAttribute(root, name);
      else
        p.number = h5::readDoubleAttribute(root, name);
      s.parameters.push_back(p);
    }
    attribute = "/Boundary/x";
    if (h5::objectType(root, cache::kBoundaryGroup) == H5O_TYPE_GROUP) {
      h5::Handle b = h5::openCheckedGroup(root, cache::kBoundaryGroup);
      s.boundaryParticles = h5::datasetLength(b.get(), "x");
      s.boundaryView = h5::hasLink(b.get(), cache::kVectorViews[0].name);
    }
  } catch (const h5::Error& e) {
    fail("cannot read root attribute or dataset '" + attribute + "' (" + e.what() +
         "); damaged cache?");
  }
}

void CacheReader::scanFrames(const std::set<std::string>& links) {
  const hid_t root = file_.get();
  for (std::size_t k = 0;; ++k) {
    const std::string name = cache::stepName(k);
    if (!links.count(name)) break;
    CacheFrame f;
    f.index = k;
    try {
      h5::Handle g = h5::openCheckedGroup(root, name);
      f.time = h5::readDoubleAttribute(g.get(), cache::kTimeAttr);
      f.particles = h5::datasetLength(g.get(), "x");
      if (h5::hasAttribute(g.get(), "step")) f.step = h5::readUintAttribute(g.get(), "step");
    } catch (const h5::Error& e) {
      summary_.damagedFrame = "/" + name + ": " + e.what();
      break;
    }
    f.hasRestart = links.count(cache::restartName(k)) > 0;
    if (links.count(cache::rainName(k))) {
      try {
        h5::Handle g =
            h5::openCheckedGroup(root, cache::rainName(k).c_str());
        f.rainDrops = h5::readUintAttribute(g.get(), cache::kRainDropsAttr);
      } catch (const h5::Error& e) {
        summary_.damagedFrame = "/" + cache::rainName(k) + ": " + e.what();
        break;
      }
    }
    summary_.frames.push_back(f);
  }
}

void CacheReader::scanRenderers(const std::set<std::string>& links) {
  // renderer -> the frames it has an image of
  std::map<std::string, std::set<std::size_t>> images;
  const std::string prefix = cache::kRenderPrefix;
  for (const std::string& name : links) {
    const std::size_t hash = name.rfind('#');
    std::size_t k = 0;
    if (name.rfind(prefix, 0) != 0 || hash <= prefix.size() ||
        !frameNumber(name.substr(hash + 1), k))
      continue;
    images[name.substr(prefix.size(), hash - prefix.size())].insert(k);
  }
  // Caches written before rendered frames moved to the root: /Render/<renderer>/Frame#N.
  const hid_t root = file_.get();
  if (links.count(cache::kLegacyRenderGroup) &&
      h5::objectType(root, cache::kLegacyRenderGroup) == H5O_TYPE_GROUP) {
    try {
      h5::Handle render =
          h5::openCheckedGroup(root, cache::kLegacyRenderGroup);
      for (const std::string& renderer : linkNames(render.get())) {
        h5::Handle g = h5::openCheckedGroup(render.get(), renderer);
        std::set<std::size_t>& frames = images[renderer];
        for (const std::string& name : linkNames(g.get())) {
          std::size_t k = 0;
          if (name.rfind("Frame#", 0) == 0 && frameNumber(name.substr(6), k)) frames.insert(k);
        }
      }
    } catch (const h5::Error& e) {
      fail(std::string("cannot read /Render (") + e.what() + ")");
    }
  }
  // A picture counts with its frame: one linked beside a frame the cache does not hold (written
  // by hand) is not offered.
  for (const auto& [renderer, frames] : images) {
    std::vector<std::size_t> held;
    for (const std::size_t k : frames)
      if (k < summary_.frames.size()) held.push_back(k);
    summary_.renderers.emplace_back(renderer, std::move(held));
  }
}

std::uint64_t CacheReader::frameDataBytes() const {
  std::uint64_t bytes = 0;
  try {
    for (const CacheFrame& f : summary_.frames) {
      for (const std::string& group : {cache::stepName(f.index), cache::restartName(f.index)}) {
        if (h5::objectType(file_.get(), group) != H5O_TYPE_GROUP) continue;
        h5::Handle g = h5::openCheckedGroup(file_.get(), group);
        for (const std::string& name : linkNames(g.get())) {
          h5::checkHeaders(g.get(), name);
          h5::Handle set =
              checked(H5Dopen2(g.get(), name.c_str(), H5P_DEFAULT), "open /" + group + "/" + name);
          bytes += H5Dget_storage_size(set.get());
        }
      }
    }
  } catch (const h5::Error& e) {
    fail(std::string("cannot measure the frames' datasets (") + e.what() + ")");
  }
  return bytes;
}

}  // namespace sph::io::cache
