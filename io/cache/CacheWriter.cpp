#include "io/cache/CacheWriter.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <numeric>

#include "io/cache/CacheJournal.h"
#include "sim/InputError.h"

namespace sph::io::cache {
namespace {

using Clock = std::chrono::steady_clock;
using h5::check;
using h5::checked;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string isoTimeNow() {
  const std::time_t t = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&t, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += (out.empty() ? "" : "\n") + l;
  return out;
}

// Links the root's object header is sized for: per frame its Step, Restart (if written) and
// Vectors groups and its rendered images (if the scene stores them), four times over so that
// resumed runs can extend the cache well past its planned end, plus room for the root attributes
// (they share the header with the links and HDF5 puts them into the space reserved for links, so
// it is reserved for them too, in link-sized units). A link costs about 30 bytes and the header
// is rewritten at each commit, so this stays cheap: 30 kB for a 60-frame run. Past it HDF5
// chains a second header block, and the moment it does so is the one commit that is not a
// single write (docs/cache-format.md, "Crash safety").
unsigned rootLinkEstimate(std::size_t expectedFrames, std::size_t linksPerFrame,
                          std::size_t attributeBytes) {
  const std::size_t links = 4 * linksPerFrame * expectedFrames + 256 + attributeBytes / 16;
  return static_cast<unsigned>(std::min<std::size_t>(links, h5::kMaxCompactLinks));
}

// Root links a frame adds: Step#N, Vectors#N, Restart#N, Render#<renderer>#N, Rain#N.
std::size_t linksPerFrame(const sph::scene::Scene& scene) {
  std::size_t links = 2 + (scene.output.restart ? 1 : 0);
  if (scene.render && scene.render->toCache) {
    const std::size_t renderers =
        scene.render->splat == sph::scene::RenderDesc::Splat::Both ? 2 : 1;
    links += (renderers + static_cast<std::size_t>(scene.render->every) - 1) /
             static_cast<std::size_t>(scene.render->every);
  }
  if (scene.rain && scene.camera) ++links;  // the drops (io/cache/RainCache.h)
  return links;
}

// User block for the journal: room for the root header (about 32 bytes a link), a power of two
// as HDF5 requires.
std::uint64_t userBlockBytes(unsigned rootLinks, std::size_t attributeBytes) {
  const std::uint64_t need = 32ull * rootLinks + attributeBytes + 8192;
  std::uint64_t size = 512;
  while (size < need) size *= 2;
  return size;
}

}  // namespace

CacheWriter::CacheWriter(std::string path, h5::Handle file, int lockFd)
    : path_(std::move(path)), file_(std::move(file)), fd_(lockFd) {}

CacheWriter::~CacheWriter() {
  file_.reset();
  if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<CacheWriter> CacheWriter::create(const std::string& path,
                                                 const sph::scene::Scene& scene,
                                                 const solver::DerivedParams& derived,
                                                 const solver::BoundaryParticles& boundary,
                                                 const CacheProvenance& provenance,
                                                 std::size_t expectedFrames) {
  h5::silence();
  const std::vector<cache::Parameter> parameters = cache::solverParameters(scene, derived);
  // The root header holds the status string and, for every other attribute, its name, type and
  // (numbers) value; the text of the strings lives in the global heap.
  const std::size_t attributeBytes = cache::kStatusWidth + 64 * (parameters.size() + 24);
  const unsigned rootLinks = rootLinkEstimate(expectedFrames, linksPerFrame(scene), attributeBytes);
  h5::Handle fcpl = h5::fileCreateProps(rootLinks);
  const std::uint64_t userBlock = userBlockBytes(rootLinks, attributeBytes);
  h5::check(H5Pset_userblock(fcpl.get(), userBlock), "reserve the journal");
  h5::Handle fapl = h5::fileAccessProps();
  // Our own open() first, for a plain message (HDF5's for a missing directory is a paragraph).
  const int probe = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (probe < 0)
    throw InputError(path + ": cannot create the cache (" + std::strerror(errno) + ")");
  ::close(probe);
  h5::Handle file;
  try {
    file =
        checked(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), "create the cache");
  } catch (const h5::Error& e) {
    throw InputError(path + ": cannot create the cache (" + e.detail() + ")");
  }
  std::unique_ptr<CacheWriter> w(new CacheWriter(path, std::move(file), lockCacheFile(path)));
  w->userBlock_ = userBlock;
  const sph::scene::OutputDesc& out = scene.output;
  std::string error;
  w->fields_ = cache::parseFields(out.fields, error);
  if (!error.empty()) throw InputError(path + ": output.fields: " + error);
  w->restart_ = out.restart;
  w->doublePositions_ = out.doublePositions;
  w->storage_.deflateLevel = out.compression;

  try {
    const hid_t root = w->file_.get();
    h5::writeAttribute(root, cache::kFormatAttr, std::string(cache::kFormatName));
    h5::writeAttribute(root, cache::kFormatVersionAttr, cache::kFormatVersion);
    h5::writeAttribute(root, "sphsplat_version", provenance.programVersion);
    h5::writeAttribute(root, "created", isoTimeNow());
    h5::writeAttribute(root, "scene_name", scene.name);
    h5::writeAttribute(root, "scene_path", scene.sourcePath);
    h5::writeAttribute(root, "scene_text", scene.sourceText);
    h5::writeAttribute(root, "scene_overrides", joined(provenance.overrides));
    h5::writeAttribute(root, "scene_fingerprint", cache::dynamicsFingerprint(scene));
    h5::writeAttribute(root, "threads", static_cast<std::int64_t>(provenance.threads));
    for (const cache::Parameter& p : parameters) {
      if (p.isText)
        h5::writeAttribute(root, p.name, p.text);
      else
        h5::writeAttribute(root, p.name, p.number);
    }
    h5::writeAttribute(root, "output.fps", out.fps);
    h5::writeAttribute(root, "output.fields", cache::describeFields(w->fields_));
    h5::writeAttribute(root, "output.compression", static_cast<std::int64_t>(out.compression));
    h5::writeAttribute(root, "output.restart", static_cast<std::int64_t>(out.restart));
    h5::writeAttribute(root, "output.double_positions",
                       static_cast<std::int64_t>(out.doublePositions));
    // Fixed-length, in the root header: rewritten in place by every status change (setStatus),
    // which a variable-length string, kept in the global heap, could not be crash-safely.
    h5::writeFixedAttribute(root, cache::kStatusAttr, "running", cache::kStatusWidth);

    // The boundary particles never move: once, in a group H5Part readers do not count as a step.
    h5::Handle b = checked(H5Gcreate2(root, cache::kBoundaryGroup, H5P_DEFAULT,
                                      h5::groupCreateProps(4).get(), H5P_DEFAULT),
                           "create /Boundary");
    const std::vector<float>* xyz[3] = {&boundary.x, &boundary.y, &boundary.z};
    const char* names[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      h5::writeDataset(b.get(), names[a], H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, xyz[a]->data(),
                       xyz[a]->size(), w->storage_);
    }
    if (boundary.size() > 0) {
      h5::createColumnView(b.get(), cache::kVectorViews[0].name, H5T_IEEE_F32LE, boundary.size(),
                           {"/Boundary/x", "/Boundary/y", "/Boundary/z"});
    }
    h5::writeAttribute(b.get(), "particles", static_cast<std::uint64_t>(boundary.size()));
    h5::writeAttribute(b.get(), "particle_mass", static_cast<double>(derived.mass));
    b.reset();
    w->commitObjects();
  } catch (const h5::Error& e) {
    throw InputError(path + ": cannot write the cache header (" + e.what() + ")");
  }
  w->writePointIndex(boundary.size());
  return w;
}

std::unique_ptr<CacheWriter> CacheWriter::append(const std::string& path, std::size_t frames) {
  h5::silence();
  const int fd = lockCacheFile(path);
  h5::Handle fapl = h5::fileAccessProps();
  h5::Handle file;
  try {
    file = checked(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()), "open the cache");
  } catch (const h5::Error& e) {
    ::close(fd);
    throw InputError(path + ": cannot open the cache for writing (" + e.detail() + ")");
  }
  std::unique_ptr<CacheWriter> w(new CacheWriter(path, std::move(file), fd));
  w->frames_ = frames;
  w->readSettings();
  h5::Handle fcpl =
      checked(H5Fget_create_plist(w->file_.get()), "read the file creation properties");
  hsize_t userBlock = 0;
  h5::check(H5Pget_userblock(fcpl.get(), &userBlock), "read the user block size");
  w->userBlock_ = userBlock;
  fcpl.reset();
  w->addMissingVectorViews();
  return w;
}

// Caches written before the views existed get them for their frames, so that the sidecar a
// resume writes can point every frame at its views. All in one commit, linked from the root.
void CacheWriter::addMissingVectorViews() {
  std::vector<std::pair<std::size_t, std::size_t>> missing;  // frame, particles
  try {
    for (std::size_t k = 0; k < frames_; ++k) {
      if (h5::hasLink(file_.get(), cache::vectorsName(k))) continue;
      h5::Handle step = checked(H5Gopen2(file_.get(), cache::stepName(k).c_str(), H5P_DEFAULT),
                                "open " + cache::stepName(k));
      const std::size_t n = h5::datasetLength(step.get(), "x");
      if (n > 0) missing.emplace_back(k, n);
    }
    if (missing.empty()) return;
    reopen();
    std::vector<h5::Handle> groups;
    for (const auto& [frame, particles] : missing)
      groups.push_back(writeVectorViews(frame, particles));
    commitObjects();
    for (std::size_t i = 0; i < missing.size(); ++i) {
      const std::string name = cache::vectorsName(missing[i].first);
      check(H5Olink(groups[i].get(), file_.get(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
            "link " + name);
    }
    groups.clear();
    commitObjects(file_.get());
  } catch (const h5::Error& e) {
    throw InputError(path_ + ": cannot add the frames' vector views (" + e.what() + ")");
  }
}

void CacheWriter::readSettings() {
  try {
    const hid_t root = file_.get();
    std::string error;
    std::vector<std::string> names;
    const std::string list = h5::readStringAttribute(root, "output.fields");
    for (std::size_t pos = 0; pos < list.size();) {
      const std::size_t end = std::min(list.find(' ', pos), list.size());
      if (end > pos) names.push_back(list.substr(pos, end - pos));
      pos = end + 1;
    }
    fields_ = cache::parseFields(names, error);
    if (!error.empty()) throw InputError(path_ + ": root attribute output.fields: " + error);
    restart_ = h5::readIntAttribute(root, "output.restart") != 0;
    doublePositions_ = h5::readIntAttribute(root, "output.double_positions") != 0;
    storage_.deflateLevel = static_cast<int>(h5::readIntAttribute(root, "output.compression"));
  } catch (const h5::Error& e) {
    throw InputError(path_ + ": cannot read the cache's output settings (" + e.what() + ")");
  }
}

void CacheWriter::reopen() {
  // The views' mappings (and the root's strings) live in HDF5's global heap, whose blocks are
  // rewritten in place when a new entry fits into one. HDF5 puts a new entry into a block it
  // knows to have room, which after a commit would be a block committed frames use. A file
  // opened afresh knows no block until it reads one, and the writer reads none: each frame's
  // entries go to a block of their own, written once (the crash and reader-view tests check it).
  const ssize_t open = H5Fget_obj_count(file_.get(), H5F_OBJ_ALL);
  if (open != 1) {
    throw h5::Error("reopen the cache",
                    std::to_string(open - 1) + " of its objects are still open in this process");
  }
  file_.close("close the cache");
  file_ = checked(H5Fopen(path_.c_str(), H5F_ACC_RDWR, h5::fileAccessProps().get()),
                  "reopen the cache");
  growFile();  // closing cut the file to HDF5's end of allocation
}

void CacheWriter::writeFrameGroup(
    const std::string& name, std::size_t frame,
    const std::function<void(hid_t group, const h5::Storage& storage)>& fill) {
  if (frame >= frames_) {
    throw InputError(path_ + ": cannot store /" + name + ": the cache has " +
                     std::to_string(frames_) + " frames");
  }
  const auto start = Clock::now();
  try {
    const hid_t root = file_.get();
    if (h5::hasLink(root, name)) throw InputError(path_ + ": /" + name + " is already written");
    // Same two-phase commit as a frame: the group is written, then linked into the root.
    h5::Handle group =
        checked(H5Gcreate_anon(root, h5::groupCreateProps(8).get(), H5P_DEFAULT), "create " + name);
    fill(group.get(), storage_);
    commitObjects();
    check(H5Olink(group.get(), root, name.c_str(), H5P_DEFAULT, H5P_DEFAULT), "link /" + name);
    group.reset();
    commitObjects(root);
  } catch (const h5::Error& e) {
    throw InputError(path_ + ": cannot write /" + name + " (" + e.what() + ")");
  }
  secondsWriting_ += since(start);
}

void CacheWriter::writePointIndex(std::size_t points) {
  const std::size_t length = cache::pointIndexLength(points);
  if (points == 0 || pointIndexes_.count(length)) return;
  const auto start = Clock::now();
  const std::string name = cache::pointIndexName(points);
  try {
    const hid_t root = file_.get();
    if (!h5::hasLink(root, name)) {
      // Same two-phase commit as a frame: the index is written and placed, then linked.
      std::vector<std::uint32_t> numbers(length);
      std::iota(numbers.begin(), numbers.end(), 0u);
      h5::Handle index =
          h5::createDataset(root, "", H5T_STD_U32LE, {static_cast<hsize_t>(length)}, storage_);
      check(H5Dwrite(index.get(), H5T_NATIVE_UINT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, numbers.data()),
            "write " + name);
      // Its chunks placed now, before commitObjects() grows the file (point 4 there).
      check(H5Dflush(index.get()), "write " + name);
      commitObjects();
      check(H5Olink(index.get(), root, name.c_str(), H5P_DEFAULT, H5P_DEFAULT), "link /" + name);
      index.reset();
      commitObjects(root);
    }
  } catch (const h5::Error& e) {
    throw InputError(path_ + ": cannot write /" + name + " (" + e.what() + ")");
  }
  pointIndexes_.insert(length);
  secondsWriting_ += since(start);
}

void CacheWriter::dropFramesFrom(std::size_t first) {
  const auto start = Clock::now();
  try {
    std::vector<std::string> names, dropped;
    hsize_t index = 0;
    check(H5Literate(
              file_.get(), H5_INDEX_NAME, H5_ITER_NATIVE, &index,
              [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
                static_cast<std::vector<std::string>*>(data)->emplace_back(name);
                return 0;
              },
              &names),
          "list the root's links");
    for (const std::string& name : names) {
      const std::optional<std::size_t> frame = cache::frameOfRootLink(name);
      if (frame && *frame >= first) dropped.push_back(name);
    }
    // Only the root's header changes, in the one commit that every frame's link takes (the
    // journal guards it): a kill leaves the frames before or after, never part of them.
    if (!dropped.empty()) {
      removeRootLinks(dropped);
      commitObjects(file_.get());
    }
  } catch (const h5::Error& e) {
    throw InputError(path_ + ": cannot remove frames from " + std::to_string(first) + " on (" +
                     e.what() + ")");
  }
  frames_ = std::min(frames_, first);
  secondsWriting_ += since(start);
}

void CacheWriter::removeRootLinks(const std::vector<std::string>& names) {
  haddr_t end = 0, lowered = 0;
  check(H5Fget_eoa(file_.get(), &end), "read the end of allocation");
  for (const std::string& name : names)
    check(H5Ldelete(file_.get(), name.c_str(), H5P_DEFAULT), "remove /" + name);
  // Objects written last lie at the end of the file: freeing them makes HDF5 lower its end of
  // allocation, and its next flush would cut the file below the end the committed superblock
  // records before writing the new one (a kill in between leaves a file every reader refuses as
  // truncated). The end is raised back first; the freed space stays unused.
  check(H5Fget_eoa(file_.get(), &lowered), "read the end of allocation");
  if (lowered < end) {
    check(H5Fincrement_filesize(file_.get(), 0), "keep the end of allocation");
    check(H5Fget_eoa(file_.get(), &lowered), "read the end of allocation");
    if (lowered < end)
      check(H5Fincrement_filesize(file_.get(), end - lowered), "keep the end of allocation");
  }
}

void CacheWriter::setStatus(const std::string& status) {
  const auto start = Clock::now();
  try {
    // A frame that failed between closing the file and opening it again (reopen(), a full disk)
    // left it closed: the status, which says so, still goes in.
    if (!file_) {
      file_ = checked(H5Fopen(path_.c_str(), H5F_ACC_RDWR, h5::fileAccessProps().get()),
                      "open the cache again");
      growFile();
    }
    h5::rewriteAttribute(file_.get(), cache::kStatusAttr, status.substr(0, cache::kStatusWidth));
    commitObjects(file_.get());
  } catch (const h5::Error& e) {
    throw InputError(path_ + ": cannot record the run status (" + e.what() + ")");
  }
  secondsWriting_ += since(start);
}

void CacheWriter::publishAs(const std::string& finalPath) {
  if (std::rename(path_.c_str(), finalPath.c_str()) != 0) {
    throw InputError(finalPath + ": cannot move the new cache into place from " + path_ + " (" +
                     std::strerror(errno) + ")");
  }
  path_ = finalPath;
}

std::uint64_t CacheWriter::fileBytes() const {
  // What the file will keep (HDF5's end of allocation), without the margin it grows by.
  haddr_t eoa = 0;
  if (file_ && H5Fget_eoa(file_.get(), &eoa) >= 0) return static_cast<std::uint64_t>(eoa);
  struct stat st {};
  return fstat(fd_, &st) == 0 ? static_cast<std::uint64_t>(st.st_size) : 0;
}

void CacheWriter::close() {
  try {
    file_.close("close the cache");
  } catch (const h5::Error& e) {
    throw InputError(path_ + ": " + e.what());
  }
  if (fd_ < 0) return;
  // Cut off the growth margin (commitObjects, point 4): the file ends where its superblock says,
  // read back from the file itself now that HDF5 has written its last.
  // (Superblock version 2: signature, version, sizes, flags, base address, extension address,
  // then the end-of-file address, 8 bytes little-endian.)
  unsigned char field[8] = {0};
  std::uint64_t end = 0;
  const bool read = pread(fd_, field, sizeof field, static_cast<off_t>(userBlock_ + 28)) ==
                    static_cast<ssize_t>(sizeof field);
  for (int i = 7; i >= 0; --i) end = (end << 8) | field[i];
  if (read && end > userBlock_) {
    struct stat st {};
    if (fstat(fd_, &st) == 0 && static_cast<std::uint64_t>(st.st_size) > end &&
        ftruncate(fd_, static_cast<off_t>(end)) != 0) {
      const int error = errno;
      ::close(fd_), fd_ = -1;
      throw InputError(path_ + ": cannot trim the cache file (" + std::strerror(error) + ")");
    }
  }
  ::close(fd_), fd_ = -1;
}

}  // namespace sph::io::cache
