#include "io/cache/CacheSession.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "io/OutputLock.h"
#include "io/cache/RainCache.h"
#include "io/UserFiles.h"
#include "sim/HumanText.h"
#include "sim/InputError.h"
#include "sim/rain/RainFeed.h"

namespace sph::io::cache {
namespace {

bool exists(const std::string& path) {
  struct stat st {};
  return lstat(path.c_str(), &st) == 0;
}

bool isDirectory(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string baseName(const std::string& path) {
  return path.substr(path.find_last_of('/') + 1);
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// run_status of a run that stopped early.
std::string stoppedStatus(const std::string& reason, std::size_t lastFrame, double lastTime) {
  return "stopped: " + reason + "; last good frame " + std::to_string(lastFrame) +
         " (t = " + number(lastTime) + " s)";
}

std::string megabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g MB", bytes / 1e6);
  return text;
}

}  // namespace

std::unique_ptr<CacheSession> CacheSession::prepare(const CacheSessionOptions& flags,
                                                    sph::scene::Scene& scene) {
  if (flags.noCompress) scene.output.compression = 0;
  auto out = std::unique_ptr<CacheSession>(new CacheSession);
  out->overwrite_ = flags.overwrite;
  if (!flags.resume.empty()) {
    if (!flags.output.empty() && flags.output != flags.resume) {
      throw InputError("--resume " + flags.resume + " appends to that cache; leave out --output " +
                       flags.output);
    }
    if (flags.overwrite)
      throw InputError("--resume and --overwrite exclude each other (resume appends to the cache)");
    out->path_ = flags.resume;
    out->resume_ = true;
    // Before reading: a run that writes it now may be mid-commit.
    out->lock_ = OutputLock::acquire(out->path_, "cache");
    out->reader_ = std::make_unique<CacheReader>(flags.resume);
    const CacheSummary& s = out->reader_->summary();
    if (s.frames.empty())
      throw InputError(flags.resume + ": the cache has no complete frame to resume from");
    if (!s.damagedFrame.empty()) {
      throw InputError(flags.resume + ": cannot resume past a damaged frame (" + s.damagedFrame +
                       ")");
    }
    // A resume needs the last frame's resume record: say so before anything runs.
    if (!s.frames.back().hasRestart) out->reader_->readRestart(s.frames.size() - 1);
    if (cacheIsLocked(flags.resume)) {
      throw InputError(
          flags.resume +
          ": another sphsplat run is writing this cache; wait for it or stop it first");
    }
    // Frames stay evenly spaced: the cache's rate wins over the scene's.
    scene.output.fps = s.fps;
    out->xdmfPath_ = XdmfWriter::sidecarPath(out->path_);
    // The resume rewrites the sidecar: as a new run would, never over the scene being run or
    // anything but a regular file.
    if (sameFile(out->xdmfPath_, scene.sourcePath)) {
      throw InputError(out->xdmfPath_ + ": is the scene file being run (" + scene.sourcePath +
                       "), and the resume would write the cache's sidecar over it; rename "
                       "the scene");
    }
    const std::string kind = nonRegularKind(out->xdmfPath_);
    if (!kind.empty() || isDirectory(out->xdmfPath_)) {
      throw InputError(out->xdmfPath_ + ": is " + (kind.empty() ? "a directory" : kind) +
                       ", not the cache's sidecar; refusing to replace it");
    }
    return out;
  }
  out->path_ = flags.output.empty() ? scene.output.path : flags.output;
  if (out->path_.empty()) return nullptr;
  const std::size_t slash = out->path_.find_last_of('/');
  const std::string dir =
      slash == std::string::npos ? "." : out->path_.substr(0, std::max<std::size_t>(slash, 1));
  if (access(dir.c_str(), W_OK) != 0) {
    throw InputError(out->path_ + ": cannot create the cache in " + dir + " (" +
                     std::strerror(errno) + ")");
  }
  // Before looking at what is there: of two runs started together on this path, one gets here.
  out->lock_ = OutputLock::acquire(out->path_, "cache");
  out->xdmfPath_ = XdmfWriter::sidecarPath(out->path_);
  if (out->xdmfPath_ == out->path_) out->xdmfPath_ += ".xdmf";
  for (const std::string& p : {out->path_, out->xdmfPath_}) {
    if (isDirectory(p)) throw InputError(p + ": is a directory; expected a cache file name");
    // Compared by device and inode: ./x.json, /abs/x.json, a symlink or a hard link alike.
    if (sameFile(p, scene.sourcePath)) {
      throw InputError(p + ": is the scene file being run (" + scene.sourcePath +
                       "); refusing to write the cache over it, even with --overwrite");
    }
    // --overwrite replaces files, never a device node, a FIFO or a socket.
    const std::string kind = nonRegularKind(p);
    if (!kind.empty()) {
      throw InputError(p + ": is " + kind +
                       ", not a regular file; refusing to replace it (choose a cache file name)");
    }
    if (exists(p) && !flags.overwrite) {
      throw InputError(
          p + ": " + whatExists(p) + "; pass --overwrite to replace it" +
          (p == out->path_ ? ", or --resume " + p + " to continue that run" : std::string("")));
    }
  }
  if (cacheIsLocked(out->path_)) {
    throw InputError(out->path_ +
                     ": another sphsplat run is writing this cache; wait for it or stop it first");
  }
  return out;
}

std::size_t CacheSession::restore(run::Simulation& sim, const CacheProvenance& provenance) {
  const std::size_t last = checkResume(sim, provenance);
  auto [state, fluid] = reader_->readRestart(last);
  checkRecord(path_, state, sim);
  sim.restore(state, std::move(fluid));
  finishRestore(sim);
  return last;
}

void CacheSession::checkRecord(const std::string& path, const run::RunState& state,
                               const run::Simulation& sim) {
  if (state.emitters.size() != sim.emitters().size()) {
    throw InputError(path + ": the resume record has " + std::to_string(state.emitters.size()) +
                     " emitters, the scene " + std::to_string(sim.emitters().size()));
  }
}

std::size_t CacheSession::checkResume(const run::Simulation& sim,
                                      const CacheProvenance& provenance) {
  const CacheSummary& s = reader_->summary();
  const sph::scene::Scene& scene = sim.scene();
  if (cache::dynamicsFingerprint(scene) != s.sceneFingerprint) {
    // Name the first parameter set by the scene that differs, if one does; the automatic ones
    // (the speed of sound follows the fluid's height) only when no set one does, so that a
    // changed fluid box is not reported as another speed of sound.
    std::string what, derived;
    for (const cache::Parameter& mine : cache::solverParameters(scene, sim.params())) {
      for (const cache::Parameter& theirs : s.parameters) {
        if (mine.name != theirs.name) continue;
        std::string differs;
        if (mine.isText && mine.text != theirs.text) {
          differs =
              mine.name + " is \"" + mine.text + "\" here but \"" + theirs.text + "\" in the cache";
        } else if (!mine.isText && mine.number != theirs.number) {
          differs = mine.name + " is " + number(mine.number) + " here but " +
                    number(theirs.number) + " in the cache";
        }
        std::string& into = cache::isAutomaticParameter(scene, mine.name) ? derived : what;
        if (into.empty()) into = differs;
      }
    }
    if (what.empty()) {
      what = "its fluids, boundaries, emitters or domain differ";
      if (sim.rainFeed()) what += ", or its rain that feeds the fluid (rain, camera, render size)";
      if (!derived.empty()) what += "; derived from them, " + derived;
    }
    throw InputError(
        scene.sourcePath + ": not the scene the cache " + path_ + " was written with (" + what +
        "); resume with the same scene and --set edits (the cache keeps them: sphsplat info " +
        path_ + ")");
  }
  if (provenance.threads != s.threads) {
    std::fprintf(stderr,
                 "sphsplat: note: %s was written with %lld threads, this run uses %d; a resumed "
                 "run matches an "
                 "uninterrupted one bit for bit only with the same thread count\n",
                 path_.c_str(), static_cast<long long>(s.threads), provenance.threads);
  }
  return resumeFrame();
}

std::size_t CacheSession::resumeFrame() const {
  const std::vector<CacheFrame>& frames = reader_->summary().frames;
  const std::size_t last = frames.size() - 1;
  // The run loop's frame times (sim/run/RunLoop.cpp); a run lands on them up to rounding.
  const double interval = 1.0 / reader_->summary().fps;
  const bool offGrid = frames[last].time < static_cast<double>(last) * interval - 1e-9 * interval;
  return offGrid && last > 0 ? last - 1 : last;
}

void CacheSession::finishRestore(run::Simulation& sim) {
  const CacheSummary& s = reader_->summary();
  const std::size_t last = resumeFrame();
  followRain(sim);
  // The drops as the run left them: the resumed run continues them exactly. A feeding rain's are
  // part of the run's state (sim/rain/RainFeed.h): a cache without them cannot be resumed.
  if (sim.rainFeed() || (rain_ && s.frames[last].rainDrops > 0)) {
    RainFrame drops = readRainFrame(*reader_, last);
    if (drops.positions.size() != sim.scene().rain->count) {
      throw InputError(path_ + ": the cache holds " + std::to_string(drops.positions.size()) +
                       " rain drops a frame, the scene's rain.count is " +
                       std::to_string(sim.scene().rain->count));
    }
    if (rain_)
      rain_->restore(drops.time, drops.positions, drops.generations);
    else
      sim.restoreRain(drops.time, drops.positions, drops.generations);
  }

  fields_ = s.fields;
  doublePositions_ = s.doublePositions;
  // The sidecar shows the boundary from its [n][3] view, which caches written before it lack.
  boundaryParticles_ = s.boundaryView ? s.boundaryParticles : 0;
  frames_.assign(s.frames.begin(), s.frames.begin() + static_cast<std::ptrdiff_t>(last + 1));
  const std::size_t held = s.frames.size();
  if (held > frames_.size()) {
    resumeNote_ = "; its frame " + std::to_string(last + 1) + " (t = " +
                  number(s.frames[last + 1].time) +
                  " s, where the run ended between two frame times) is written again at t = " +
                  number(static_cast<double>(last + 1) / s.fps) + " s";
  }
  for (const CacheFrame& f : frames_) particleFrames_ += static_cast<double>(f.particles);
  reader_.reset();  // HDF5 opens a file once per process: read-only first, now for writing
  writer_ = CacheWriter::append(path_, held);
  // A cache written before the point indexes gets those its sidecar needs.
  writer_->writePointIndex(boundaryParticles_);
  for (const CacheFrame& f : frames_)
    writer_->writePointIndex(f.particles), writer_->writePointIndex(f.rainDrops);
  // The sidecar first: it never lists a frame the cache has ceased to hold.
  xdmf_ = std::make_unique<XdmfWriter>(xdmfPath_, baseName(path_), fields_, doublePositions_,
                                       boundaryParticles_, frames_);
  writer_->dropFramesFrom(frames_.size());
  writer_->setStatus("running (resumed from frame " + std::to_string(last) + ")");
}

void CacheSession::followRain(const run::Simulation& sim) {
  // A feeding rain is stepped by the simulation itself (its landings change the fluid); any
  // other rain is stepped here, at every frame.
  if (sim.rainFeed()) {
    rainShown_ = &sim.rainFeed()->stepper();
    return;
  }
  rain_ = rain::RainStepper::create(sim.scene(), rain::RainStepper::sceneAspect(sim.scene()));
  rainShown_ = rain_.get();
}

double CacheSession::lastFrameTime() const {
  const std::vector<CacheFrame>& frames = reader_ ? reader_->summary().frames : frames_;
  return frames.empty() ? 0.0 : frames.back().time;
}

void CacheSession::create(const run::Simulation& sim, const CacheProvenance& provenance,
                          std::size_t expectedFrames) {
  const sph::scene::Scene& scene = sim.scene();
  std::string error;
  fields_ = cache::parseFields(scene.output.fields, error);
  doublePositions_ = scene.output.doublePositions;
  boundaryParticles_ = sim.boundary().particles().size();
  followRain(sim);
  const std::string partial = siblingPath(path_, "", ".partial");
  try {
    writer_ = CacheWriter::create(partial, scene, sim.params(), sim.boundary().particles(),
                                  provenance, expectedFrames);
    writingPartial_ = true;
  } catch (...) {
    ::unlink(partial.c_str());  // no first frame, no cache: nothing left behind
    throw;
  }
}

void CacheSession::writeFrame(const run::Simulation& sim) {
  writer_->writeFrame(sim.fluid(), sim.runState());
  recordFrame(sim, sim.fluid().size());
}

void CacheSession::writeFrameTogether(const run::Simulation& sim, const Particles& mine,
                                      const run::RunState& state, const FrameSlice& slice,
                                      const rain::WaterCells* water) {
  // Rank 0 holds part of the fluid only: its drops must meet the cells of all of it, and a rain
  // that feeds the fluid is not shared out (refused on K processes before the run; failing here,
  // on rank 0 alone, ends every rank: job/distributed/DistributedRun.h, setLockstep).
  if (rainShown_ != rain_.get() || (rain_ && !water))
    throw InputError(path_ +
                     ": its rain needs the whole fluid, which no rank holds (docs/scaling.md)");
  writer_->writeFrame(mine, state, &slice);
  recordFrame(sim, static_cast<std::size_t>(slice.part.total), water);
}

void CacheSession::recordFrame(const run::Simulation& sim, std::size_t particles,
                               const rain::WaterCells* water) {
  CacheFrame f;
  f.index = writer_->frameCount() - 1;
  f.time = sim.time();
  f.particles = particles;
  f.step = sim.stepCount();
  f.hasRestart = true;
  if (rain_ && water)
    rain_->advanceTo(sim.time(), *water);
  else if (rain_)
    rain_->advanceTo(sim.time(), sim.fluid());
  if (rainShown_) {
    // A feeding rain's stepper is at its last tick: the frame's time unless the run ended
    // between two.
    writeRainFrame(*writer_, f.index, rainShown_->time(), rainShown_->system());
    f.rainDrops = rainShown_->system().size();
  }
  frames_.push_back(f);
  particleFrames_ += static_cast<double>(f.particles);
  particleFramesWritten_ += static_cast<double>(f.particles);
  if (!xdmf_) {
    // Frame 0 is in: the new cache replaces PATH (and only now, so a run that fails before this
    // leaves an existing cache untouched), then the sidecar follows.
    if (writingPartial_) {
      writer_->publishAs(path_);
      writingPartial_ = false;
    }
    xdmf_ = std::make_unique<XdmfWriter>(xdmfPath_, baseName(path_), fields_, doublePositions_,
                                         boundaryParticles_, frames_);
  } else {
    xdmf_->append(f);
  }
}

void CacheSession::finish(double time) {
  writer_->setStatus("finished at t = " + number(time) + " s");
  if (xdmf_) xdmf_->flush();
}

std::string CacheSession::stop(const std::string& reason) {
  if (frames_.empty()) {
    close();
    // --overwrite replaces an existing file only once frame 0 is in.
    return exists(path_) ? "no frame was written; " + path_ + " is as it was before the run"
                         : "no frame was written, so there is no cache at " + path_;
  }
  const std::string last = std::to_string(frames_.size() - 1);
  const std::string lastTime = number(frames_.back().time);
  // The status first: the sidecar may fail for the reason the run stopped (a full disk).
  writer_->setStatus(stoppedStatus(reason, frames_.size() - 1, frames_.back().time));
  std::string sidecar;
  try {
    if (xdmf_) xdmf_->flush();
  } catch (const InputError&) {
    sidecar = " (its sidecar " + xdmfPath_ + " lists fewer; a resume writes it whole)";
  }
  if (!xdmf_) sidecar = " (without its sidecar " + xdmfPath_ + "; a resume writes it)";
  const std::string text = "the cache " + path_ + " keeps " + framesText() + sidecar +
                           "; the last good frame is " + last + " (t = " + lastTime + " s)";
  try {
    close();
  } catch (const InputError&) {
    // The status is committed; only the close's own writes failed (the same full disk).
  }
  return text;
}

void CacheSession::recordStop(const std::string& path, const std::string& reason,
                              std::size_t maxFrames) {
  // As a resume takes it: a run started on the cache meanwhile keeps it (and records its own).
  const OutputLock lock = OutputLock::acquire(path, "cache");
  std::size_t frames = 0;
  double lastTime = 0;
  {
    const CacheReader reader(path);
    const CacheSummary& s = reader.summary();
    if (s.frames.empty()) return;
    // A resume that ran in between recorded its own status (or, killed, holds more frames than
    // the stopped run could have written): that is the cache's state now, not this run's.
    if (s.status.rfind("running", 0) != 0 || s.frames.size() > maxFrames) return;
    frames = s.frames.size();
    lastTime = s.frames.back().time;
  }
  const std::unique_ptr<CacheWriter> writer = CacheWriter::append(path, frames);
  writer->setStatus(stoppedStatus(reason, frames - 1, lastTime));
  writer->close();
}

CacheSession::~CacheSession() {
  try {
    close();
  } catch (const std::exception&) {
    // Closing after a failure (a full disk): the failure was reported; keep unwinding.
  }
}

void CacheSession::close() {
  if (!writer_) return;
  const std::string file = writer_->path();
  // A new cache that never got its first frame is no cache: PATH.partial goes, whatever its
  // close says (a full disk fails it). Any other file the writer had is a cache with frames (a
  // resumed one, or a new one moved into place) and stays, whatever failed after it (the
  // sidecar, a full disk).
  if (writingPartial_) {
    writingPartial_ = false;
    writer_.reset();
    ::unlink(file.c_str());
    return;
  }
  writer_->close();
  writer_.reset();
}

std::size_t CacheSession::frameCount() const {
  return frames_.size();
}

std::string CacheSession::framesText() const {
  if (frames_.empty()) return "no frame";
  return "frames 0-" + std::to_string(frames_.size() - 1) +
         " (t = " + number(frames_.front().time) + " - " + number(frames_.back().time) + " s)";
}

std::string CacheSession::summary(double runSeconds) const {
  const double bytes = writer_ ? static_cast<double>(writer_->fileBytes()) : 0.0;
  const double writing = writer_ ? writer_->secondsWriting() : 0.0;
  std::ostringstream s;
  s.precision(3);
  s << "cache: " << path_ << " (+ " << xdmfPath_ << " for ParaView): " << frames_.size()
    << " frames, " << megabytes(bytes);
  if (writer_ && particleFramesWritten_ > 0) {
    s << "; frame datasets "
      << static_cast<double>(writer_->frameDataBytes()) / particleFramesWritten_
      << " bytes per particle per frame";
  }
  s << "; writing took " << humanSeconds(writing) << " = "
    << (runSeconds > 0 ? 100 * writing / runSeconds : 0.0) << "% of the run";
  return s.str();
}

void CacheSession::writeRenderedFrame(const std::string& renderer, std::size_t frame, int width,
                                      int height, const std::uint8_t* rgb) {
  writer_->writeRenderedFrame(renderer, frame, width, height, rgb);
}

}  // namespace sph::io::cache
