// CacheWriter's frames: the Step#N group, its resume record and vector views, written by one
// process or by all ranks of an MPI run together (parallel HDF5; docs/scaling.md, "The cache is
// written by all ranks"). Either way the commit is the one of io/cache/CacheCommit.cpp.
#include <algorithm>
#include <chrono>
#include <cstring>

#include "io/cache/CacheWriter.h"
#include "sim/InputError.h"

namespace sph::io::cache {

using h5::check;
using h5::checked;

namespace {
// Bytes a frame written together may allocate (see writeFrame): 2 x 8 bytes x the arrays a frame
// can hold (the fields, the resume record's and DFSPH's warm start: at most 16), plus metadata.
constexpr std::uint64_t kFrameBoundPerParticle = 2 * 8 * 16;
constexpr std::uint64_t kFrameBoundMetadata = 4 << 20;
}  // namespace

std::size_t CacheWriter::frameParticles(const Particles& fluid) const {
  return slice_ ? static_cast<std::size_t>(slice_->part.total) : fluid.size();
}

// True on every rank if `mine` is true on every rank (one process: `mine`).
bool CacheWriter::onAllRanks(bool mine) const {
  if (!slice_) return mine;
  const std::vector<ranks::Bytes> all = slice_->ranks->allGather(ranks::Bytes(1, mine ? 1 : 0));
  return std::all_of(all.begin(), all.end(), [](const ranks::Bytes& b) { return b.at(0) == 1; });
}

// Whether every value of `v` over all ranks has the bits of the first one, which goes to `first`.
bool CacheWriter::constantEverywhere(const std::vector<float>& v, float& first) const {
  if (!v.empty()) first = v[0];
  if (slice_) {
    // The first value of the first rank that holds any.
    ranks::Bytes mine(v.empty() ? 0 : sizeof first);
    if (!v.empty()) std::memcpy(mine.data(), &first, sizeof first);
    for (const ranks::Bytes& b : slice_->ranks->allGather(mine)) {
      if (b.empty()) continue;
      std::memcpy(&first, b.data(), sizeof first);
      break;
    }
  }
  return onAllRanks(std::all_of(v.begin(), v.end(),
                                [&](float x) { return std::memcmp(&x, &first, sizeof x) == 0; }));
}

std::uint64_t CacheWriter::writeValues(hid_t group, const char* name, hid_t memType, hid_t fileType,
                                       const void* data, std::size_t count) {
  if (slice_)
    return h5::writeDatasetPart(group, name, memType, fileType, data, slice_->part, storage_);
  return h5::writeDataset(group, name, memType, fileType, data, count, storage_);
}

void CacheWriter::writeField(hid_t group, cache::Field field, const Particles& fluid) {
  const char* name = cache::fieldName(field);
  const std::size_t n = fluid.size();
  if (field == cache::Field::Id) {
    frameDataBytes_ +=
        writeValues(group, name, H5T_NATIVE_UINT32, H5T_STD_U32LE, fluid.id.data(), n);
    return;
  }
  const std::vector<float>& values = fluid.*cache::floatMember(field);
  const bool position =
      field == cache::Field::X || field == cache::Field::Y || field == cache::Field::Z;
  if (position && doublePositions_) {
    const std::vector<double> wide(values.begin(), values.end());
    frameDataBytes_ += writeValues(group, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, wide.data(), n);
  } else {
    frameDataBytes_ += writeValues(group, name, H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, values.data(), n);
  }
}

void CacheWriter::writeFrame(const Particles& fluid, const run::RunState& state,
                             const FrameSlice* slice) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t frame = frames_;
  try {
    if (slice) {
      // For this frame the file is every rank's: opened through MPI-IO (afresh, which is what
      // reopen() does for the global heap's sake), written, committed and closed together.
      // Over MPI-IO HDF5 does not tell the end of allocation (H5Fget_eoa needs a SWMR-capable
      // driver), and it cuts the file to it after each flush, so the file is grown before each
      // flush past a bound of what the frame can allocate (CacheCommit.cpp, point 4): its
      // arrays twice over (parallel HDF5 allocates a filtered chunk at creation, then again at
      // its compressed size) in 8-byte values, and room for the metadata.
      haddr_t eoa = 0;
      check(H5Fget_eoa(file_.get(), &eoa), "read the end of allocation");
      frameEnd_ = static_cast<std::uint64_t>(eoa) + kFrameBoundPerParticle * slice->part.total +
                  kFrameBoundMetadata;
      file_.close("close the cache");
      file_ = checked(H5Fopen(path_.c_str(), H5F_ACC_RDWR, h5::parallelFileAccessProps().get()),
                      "open the cache on every rank");
      slice_ = slice;
      // Every HDF5 call the same on every rank, reads too (joinFrame reads the settings): the
      // ranks' metadata caches must stay alike, or a collective read waits for a rank that has
      // the object cached (a broadcast only some ranks make).
      readSettings();
      writeFrameObjects(fluid, state);
      slice_ = nullptr;
      file_.close("close the cache on every rank");
      file_ = checked(H5Fopen(path_.c_str(), H5F_ACC_RDWR, h5::fileAccessProps().get()),
                      "reopen the cache");
      growFile();
      linkVectorViews(frame, static_cast<std::size_t>(slice->part.total));
      writePointIndex(static_cast<std::size_t>(slice->part.total));
    } else {
      reopen();
      writeFrameObjects(fluid, state);
      writePointIndex(fluid.size());
    }
  } catch (const h5::Error& e) {
    // Failed on this rank alone, mid-frame: closing would be collective and wait forever for the
    // others; the run stops (every rank, job/distributed/DistributedRun.h) with what is committed.
    if (slice_) file_.release();
    slice_ = nullptr;
    throw InputError(path_ + ": cannot write frame " + std::to_string(frame) + " (" + e.what() +
                     ")");
  } catch (...) {
    // The same for any other failure (a setting that does not read back, memory): slice_ points
    // into the caller's frame and must not outlive it.
    if (slice_) file_.release();
    slice_ = nullptr;
    throw;
  }
  frames_ = frame + 1;
  secondsWriting_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void CacheWriter::joinFrame(const std::string& path, std::size_t frame, const Particles& fluid,
                            const run::RunState& state, const FrameSlice& slice) {
  h5::silence();  // one line on failure (below), not HDF5's stack: this rank never created a cache
  try {
    h5::Handle file =
        checked(H5Fopen(path.c_str(), H5F_ACC_RDWR, h5::parallelFileAccessProps().get()),
                "open the cache on every rank");
    // No lock and no file descriptor: growing the file and the journal are rank 0's.
    CacheWriter w(path, std::move(file), -1);
    try {
      w.frames_ = frame;
      w.readSettings();
      w.slice_ = &slice;
      w.writeFrameObjects(fluid, state);
    } catch (...) {
      // Failed on this rank alone: closing the MPI-IO file is collective and would wait forever
      // for the other ranks, which are in another collective call; the run stops every rank
      // (job/distributed/DistributedRun.h) with what is committed.
      w.file_.release();
      w.slice_ = nullptr;
      throw;
    }
    w.file_.close("close the cache on every rank");
  } catch (const h5::Error& e) {
    throw InputError(path + ": cannot write frame " + std::to_string(frame) + " (" + e.what() +
                     ")");
  }
}

void CacheWriter::writeFrameObjects(const Particles& fluid, const run::RunState& state) {
  const std::size_t frame = frames_;
  const std::string step = cache::stepName(frame);
  const hid_t root = file_.get();
  h5::Handle group =
      checked(H5Gcreate_anon(root, h5::groupCreateProps(16).get(), H5P_DEFAULT), "create " + step);
  h5::writeAttribute(group.get(), cache::kTimeAttr, state.time);
  h5::writeAttribute(group.get(), "step", static_cast<std::uint64_t>(state.step));
  for (std::size_t f = 0; f < cache::kFieldCount; ++f) {
    if (fields_[f]) writeField(group.get(), static_cast<cache::Field>(f), fluid);
  }
  h5::Handle restart;
  if (restart_) {
    restart = checked(H5Gcreate_anon(root, h5::groupCreateProps(16).get(), H5P_DEFAULT),
                      "create the resume record");
    writeRestart(restart.get(), fluid, state);
  }
  // Together, parallel HDF5 1.10.8 hangs creating a virtual dataset (one rank waits in a global
  // heap read's broadcast that another never makes): rank 0 adds the views after the frame.
  h5::Handle vectors = slice_ ? h5::Handle() : writeVectorViews(frame, frameParticles(fluid));
  commitObjects();
  std::vector<std::string> linked;
  auto link = [&](const h5::Handle& object, const std::string& name) {
    check(H5Olink(object.get(), root, name.c_str(), H5P_DEFAULT, H5P_DEFAULT), "link " + name);
    linked.push_back(name);
  };
  try {
    if (restart) link(restart, cache::restartName(frame));
    if (vectors) link(vectors, cache::vectorsName(frame));
    link(group, step);
    group.reset(), restart.reset(), vectors.reset();
    commitObjects(root);
  } catch (const h5::Error&) {
    // Not committed, the links stay in HDF5's memory, and the next commit (the status that says
    // why the run stopped) would write them: the frame is taken back, so that the file holds the
    // frames the run reports. Together, a failure may be this rank's alone, and a removal
    // would wait for the others: the run stops with the file released (writeFrame).
    if (!slice_) {
      try {
        removeRootLinks(linked);
      } catch (const h5::Error&) {
        // Reported by the failure being handled.
      }
    }
    throw;
  }
}

void CacheWriter::writeRestart(hid_t r, const Particles& fluid, const run::RunState& state) {
  h5::writeAttribute(r, "time", state.time);
  h5::writeAttribute(r, "step", static_cast<std::uint64_t>(state.step));
  h5::writeAttribute(r, "last_dt", state.lastDt);
  h5::writeAttribute(r, "max_speed", state.maxSpeed);
  h5::writeAttribute(r, "max_acceleration", state.maxAcceleration);
  h5::writeAttribute(r, "next_id", static_cast<std::uint64_t>(state.nextId));
  h5::writeAttribute(r, "particles", static_cast<std::uint64_t>(frameParticles(fluid)));
  h5::writeAttribute(r, "lost_particles", static_cast<std::uint64_t>(state.lostParticles));
  // rain.feed_fluid's ledger (sim/rain/RainFeed.h), only once rain has landed: absent = 0.
  if (state.rain.landedDrops > 0) {
    h5::writeAttribute(r, "rain_landed_drops", state.rain.landedDrops);
    h5::writeAttribute(r, "rain_particles", state.rain.particles);
    h5::writeAttribute(r, "rain_pending_volume", state.rain.pending);
  }
  std::vector<double> travelled;
  std::vector<std::uint64_t> emitted, started;
  for (const run::EmitterState& e : state.emitters) {
    travelled.push_back(e.travelled), emitted.push_back(e.emitted),
        started.push_back(e.started ? 1 : 0);
  }
  h5::writeAttribute(r, "emitter_travelled", travelled);
  h5::writeAttribute(r, "emitter_emitted", emitted);
  h5::writeAttribute(r, "emitter_started", started);
  // Arrays the Step group already holds are not repeated (fields are stored exactly), and an
  // array holding one value throughout (collide_time without a collision pass) is that value.
  const cache::FieldSet missing = cache::restartFields() & ~fields_;
  for (std::size_t f = 0; f < cache::kFieldCount; ++f) {
    if (!missing[f]) continue;
    const auto field = static_cast<cache::Field>(f);
    if (field != cache::Field::Id && frameParticles(fluid) > 0) {
      const std::vector<float>& v = fluid.*cache::floatMember(field);
      float first = 0;
      const bool constant = constantEverywhere(v, first);
      if (constant) {
        h5::writeAttribute(r, std::string(cache::fieldName(field)) + "_constant", first);
        continue;
      }
    }
    writeField(r, field, fluid);
  }
  // The pressure solver's per-particle state (sim/solver/StepContext.h), in the frame's particle
  // order: a resume without it would not continue bit-exactly.
  const std::pair<const char*, const std::vector<float>*> warm[] = {
      {cache::kWarmDensityName, &state.warmStart.density},
      {cache::kWarmDivergenceName, &state.warmStart.divergence},
      {cache::kWallShareName, &state.warmStart.wallShare}};
  for (const auto& [name, values] : warm) {
    // Together, every rank holds its part of it (or no particles at all).
    const bool mine = values->size() == fluid.size() && (!values->empty() || slice_);
    if (!onAllRanks(mine) || frameParticles(fluid) == 0) continue;
    frameDataBytes_ +=
        writeValues(r, name, H5T_NATIVE_FLOAT, H5T_IEEE_F32LE, values->data(), values->size());
  }
}

// The views of a frame just committed without them, in a commit of their own. A kill between
// the two commits leaves a frame without views, which every reader reads (the views are only for
// ParaView, whose sidecar lists the frame after this) and a resume adds (addMissingVectorViews).
void CacheWriter::linkVectorViews(std::size_t frame, std::size_t particles) {
  h5::Handle vectors = writeVectorViews(frame, particles);
  if (!vectors) return;
  commitObjects();
  check(H5Olink(vectors.get(), file_.get(), cache::vectorsName(frame).c_str(), H5P_DEFAULT,
                H5P_DEFAULT),
        "link " + cache::vectorsName(frame));
  vectors.reset();
  commitObjects(file_.get());
}

h5::Handle CacheWriter::writeVectorViews(std::size_t frame, std::size_t particles) {
  // Zero-length views are of no use: the sidecar lists an empty frame without geometry.
  if (particles == 0) return h5::Handle();
  h5::Handle group =
      checked(H5Gcreate_anon(file_.get(), h5::groupCreateProps(4).get(), H5P_DEFAULT),
              "create " + cache::vectorsName(frame));
  const std::string step = "/" + cache::stepName(frame) + "/";
  for (const cache::VectorView& view : cache::kVectorViews) {
    if (!cache::hasAll(fields_, view)) continue;
    std::vector<std::string> columns;
    for (cache::Field c : view.components) columns.push_back(step + cache::fieldName(c));
    const bool wide = doublePositions_ && view.components[0] == cache::Field::X;
    h5::createColumnView(group.get(), view.name, wide ? H5T_IEEE_F64LE : H5T_IEEE_F32LE, particles,
                         columns);
  }
  return group;
}

}  // namespace sph::io::cache
