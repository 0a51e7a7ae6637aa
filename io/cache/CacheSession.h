// The HDF5 cache of one run (DESIGN.md, "HDF5 cache"): where it goes (--output or the scene's
// output.path), what it may replace (nothing without --overwrite), the temporary name a new cache
// has until its first frame is in, resume (--resume), the XDMF sidecar and the summary lines.
// A FrameSink of the run loop (sim/run/RunLoop.h), so `sphsplat run` and tests drive the same
// session; the file format itself is CacheWriter's, CacheReader's and XdmfWriter's.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "io/cache/CacheReader.h"
#include "io/cache/CacheWriter.h"
#include "io/OutputLock.h"
#include "io/cache/XdmfWriter.h"
#include "sim/run/RunLoop.h"
#include "sim/scene/Scene.h"
#include "sim/run/Simulation.h"
#include "sim/rain/RainStepper.h"

namespace sph::io::cache {

struct CacheSessionOptions {
  std::string output;       // --output PATH
  bool overwrite = false;   // --overwrite
  bool noCompress = false;  // --no-compress
  std::string resume;       // --resume CACHE
};

class CacheSession final : public run::FrameSink {
 public:
  // Checks the flags and the files before anything is simulated; nullptr when the run writes no
  // cache. Applies --no-compress to the scene's output section and, when resuming, the cache's
  // own frame rate (its frames must stay evenly spaced).
  static std::unique_ptr<CacheSession> prepare(const CacheSessionOptions& flags,
                                               sph::scene::Scene& scene);

  bool resuming() const { return resume_; }
  // Resume: checks that `sim`'s scene is the cache's, puts `sim` in the state of the cache's last
  // frame and opens the cache for appending. Returns the index of that frame.
  std::size_t restore(run::Simulation& sim, const CacheProvenance& provenance);
  // restore() in three parts, for a resume on K processes (job/distributed/DistributedResume.h): rank 0
  // checks that `sim`'s scene is the cache's and gets the last frame's index; every rank reads
  // its part of that frame (rank 0 through reader()) and checks it (checkRecord); once every
  // rank has closed its reader, rank 0 opens the cache for appending (finishRestore).
  std::size_t checkResume(const run::Simulation& sim, const CacheProvenance& provenance);
  // The frame a resume continues from: the cache's last, unless that one lies between two frame
  // times (a run that ended at an --end off the frame grid, where an uninterrupted run never
  // stops): then the frame before it, and the resume writes the dropped frame's number again at
  // its time on the grid, so that the frames match an uninterrupted run's bit for bit.
  std::size_t resumeFrame() const;
  // After a resume from the frame before the last (resumeFrame()): what the resume line adds,
  // "; frame 4 (t = 0.11 s) ... is written again at t = 0.1333 s"; else empty.
  const std::string& resumeNote() const { return resumeNote_; }
  const CacheReader& reader() const { return *reader_; }
  static void checkRecord(const std::string& path, const run::RunState& state,
                          const run::Simulation& sim);
  void finishRestore(run::Simulation& sim);
  // Time of the cache's last frame (resume), s.
  double lastFrameTime() const;

  // New cache: written under PATH.partial until writeFrame() has committed frame 0, then renamed.
  void create(const run::Simulation& sim, const CacheProvenance& provenance,
              std::size_t expectedFrames);
  // Writes and commits the current state as the next frame and adds it to the sidecar.
  void writeFrame(const run::Simulation& sim);
  // The same, written by all ranks of an MPI run together (rank 0 calls this, the others
  // CacheWriter::joinFrame with path() and frameCount(); docs/scaling.md): `mine` is rank 0's
  // part of the frame, `state` the run's. A scene with rain passes `water`, the cells the whole
  // fluid occupies (every rank's, job/distributed/CollectiveCacheSink.h): the drops are stepped with it and
  // rank 0 writes them alone once the frame is committed, as one process does. Not for a rain
  // that feeds the fluid (refused on K processes).
  void writeFrameTogether(const run::Simulation& sim, const Particles& mine,
                          const run::RunState& state, const FrameSlice& slice,
                          const rain::WaterCells* water = nullptr);
  // FrameSink: the run loop's frames go to writeFrame().
  void frame(const run::Simulation& sim, std::size_t) override { writeFrame(sim); }
  // Stores a rendered image of frame `frame` (already written) as /Render#<renderer>#<frame>.
  void writeRenderedFrame(const std::string& renderer, std::size_t frame, int width, int height,
                          const std::uint8_t* rgb);
  // The run reached its end time `time` (s): records "finished" in the cache.
  void finish(double time);
  // The run stopped early (`reason`: "numerical blow-up at ...", "interrupted by SIGINT"):
  // records it in the cache, closes it and returns the line that tells the user what is left.
  std::string stop(const std::string& reason);
  // The same for the cache at `path` of a run that has ended without recording it (an MPI run
  // whose ranks stopped in a frame written together, job/distributed/StatusRecorder.h): opens it as a
  // resume would (a header torn by the end restored from the journal) and records the status,
  // if the cache still says "running" with at most `maxFrames` frames (else a resume has run).
  static void recordStop(const std::string& path, const std::string& reason, std::size_t maxFrames);
  void close();
  // Closes what is open; a new cache that never got its first frame leaves nothing behind.
  ~CacheSession() override;

  const std::string& path() const { return path_; }
  // The file the writer writes (PATH.partial until frame 0 is in) and its frame count: what the
  // other ranks of a frame written together open (writeFrameTogether).
  const std::string& writerPath() const { return writer_->path(); }
  std::size_t writerFrameCount() const { return writer_->frameCount(); }
  std::size_t frameCount() const;
  // "frames 0-41 (t = 0 - 1.367 s)" of what the cache holds now.
  std::string framesText() const;
  // "cache: run.h5 (+ run.xdmf for ParaView): 61 frames, 4.1 MB; frame datasets 25.1 bytes per
  // particle per frame; writing took 0.8 s = 3.1% of the run".
  std::string summary(double runSeconds) const;
  // The scene's rain, stepped at every frame and stored beside it as /Rain#N (io/cache/RainCache.h):
  // the session's own, or a feeding rain's (Simulation::rainFeed, which must outlive the
  // session's use of it); null without a rain section.
  const rain::RainStepper* rain() const { return rainShown_; }

 private:
  OutputLock lock_;  // first: held until every file below is closed
  std::string path_, xdmfPath_;
  bool overwrite_ = false;
  bool resume_ = false;
  std::string resumeNote_;
  std::unique_ptr<CacheReader> reader_;  // resume only
  std::unique_ptr<CacheWriter> writer_;
  // The writer's file is this run's PATH.partial, not yet moved into place: the one file that
  // close() may remove. A resumed cache, or a new one once published, is never removed.
  bool writingPartial_ = false;
  std::unique_ptr<XdmfWriter> xdmf_;
  cache::FieldSet fields_;
  bool doublePositions_ = false;
  std::size_t boundaryParticles_ = 0;
  std::vector<CacheFrame> frames_;
  double particleFrames_ = 0;         // sum over frames of the particle count
  double particleFramesWritten_ = 0;  // the same, of the frames this run wrote
  // The sidecar, the rain and the counts of a frame just written (of `particles` particles);
  // the rain meets `water` if given, else sim's fluid.
  void recordFrame(const run::Simulation& sim, std::size_t particles,
                   const rain::WaterCells* water = nullptr);
  // Sets rain_ (stepped here) or points rainShown_ at the simulation's feeding rain.
  void followRain(const run::Simulation& sim);
  std::unique_ptr<rain::RainStepper> rain_;
  const rain::RainStepper* rainShown_ = nullptr;
};

}  // namespace sph::io::cache
