// Writes a run's HDF5 cache as the run goes (DESIGN.md, "HDF5 cache"; layout in
// docs/cache-format.md): the scene and resolved parameters as root attributes, the boundary
// particles once, then one H5Part `Step#N` group per output frame, a `Restart#N` resume record
// beside it, and rendered images under /Render.
//
// Crash safety: every frame is committed before writeFrame() returns, and a process killed at any
// moment (SIGKILL included) leaves a file whose committed frames all read back bit-exact. How:
// see the comment on commitObjects() in io/cache/CacheCommit.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "io/cache/CacheFileLock.h"
#include "io/cache/CacheFormat.h"
#include "io/cache/Hdf5.h"
#include "sim/solver/Boundary.h"
#include "sim/run/Simulation.h"
#include "sim/ranks/Communicator.h"

namespace sph::io::cache {

// What the root records about the program and the run besides the scene.
struct CacheProvenance {
  std::string programVersion;  // "0.1.0"
  int threads = 0;             // worker threads of the run (bit-exact resume needs the same)
  std::vector<std::string> overrides;  // the --set edits applied to the scene file
};

// This rank's part of a frame that all ranks of an MPI run write together with parallel HDF5
// (docs/scaling.md, "The cache is written by all ranks"): its particles go to `part`'s places of
// the frame's arrays. Every rank passes the same RunState (rank 0's).
struct FrameSlice {
  ranks::Communicator* ranks = nullptr;
  h5::Part part;
};

class CacheWriter {
 public:
  // Creates a new cache at `path`, truncating whatever is there (the caller decides whether that
  // is allowed). Records the scene (its output section says which fields, the compression and
  // whether resume records are written), the resolved parameters and the boundary particles, and
  // commits. `expectedFrames` sizes the root group (see CacheWriter.cpp); more frames still work.
  static std::unique_ptr<CacheWriter> create(const std::string& path,
                                             const sph::scene::Scene& scene,
                                             const solver::DerivedParams& derived,
                                             const solver::BoundaryParticles& boundary,
                                             const CacheProvenance& provenance,
                                             std::size_t expectedFrames);
  // Opens an existing cache whose frames 0..frames-1 are complete to append frame `frames` on
  // (resume). The fields, compression and resume records follow the cache's own settings. A
  // cache written before the vector views (Vectors#N) gets them for its frames.
  static std::unique_ptr<CacheWriter> append(const std::string& path, std::size_t frames);

  ~CacheWriter();
  CacheWriter(const CacheWriter&) = delete;
  CacheWriter& operator=(const CacheWriter&) = delete;

  // Writes and commits frame frameCount(): the fields asked for, the frame time as TimeValue and,
  // if enabled, the resume record (RunState + the fields the frame lacks of restartFields()).
  // With `slice`, all ranks write the frame together: rank 0 calls this on its writer while
  // every other rank calls joinFrame() with its part (the file is opened through MPI-IO for the
  // frame and closed again, so that everything else stays rank 0's, as before).
  void writeFrame(const Particles& fluid, const run::RunState& state,
                  const FrameSlice* slice = nullptr);
  // The other ranks' half of writeFrame(fluid, state, slice): frame `frame` of the cache at
  // `path` (rank 0's writer's frameCount() and path()).
  static void joinFrame(const std::string& path, std::size_t frame, const Particles& fluid,
                        const run::RunState& state, const FrameSlice& slice);

  // Stores one rendered image of frame `frame` (which must already be written) for `renderer`
  // (letters, digits, '_' and '-'): `rgb` holds height rows of width RGB triplets, top row first.
  // Lands in /Render#<renderer>#<frame> (docs/cache-format.md, "Rendered frames"), for `render
  // --to-cache` and runs whose scene stores its pictures.
  void writeRenderedFrame(const std::string& renderer, std::size_t frame, int width, int height,
                          const std::uint8_t* rgb);

  // Writes and commits a group of frame `frame` (already written) linked as /`name`: `fill`
  // writes its datasets (flushed, with `storage`) and attributes (no variable-length strings:
  // they would go to the global heap) into the group before it is linked, with the two-phase
  // commit of a frame. For sets stored beside the frames (io/cache/RainCache.h: the rain's drops).
  void writeFrameGroup(const std::string& name, std::size_t frame,
                       const std::function<void(hid_t group, const h5::Storage& storage)>& fill);

  // Makes sure the root holds the point index of a point set of `points` points
  // (cache::pointIndexName), which the sidecar's cells refer to: written and committed like a
  // frame's group the first time its length is needed. create() and writeFrame() see to the
  // boundary and the frames; the other point sets (the rain's drops) and a resumed cache written
  // before the indexes call it.
  void writePointIndex(std::size_t points);

  // Removes the records of frame `first` and every later frame (their Step, Vectors, Restart,
  // Rain and Render links) in one commit; the next frame written is `first`. For a resume after a
  // run that ended between two frame times: that last frame lies off the frame grid, and the
  // resume writes its number again at the grid's time (io/cache/CacheSession.h).
  void dropFramesFrom(std::size_t first);

  // Rewrites the root attribute run_status ("running", "finished", "stopped: ...") and commits.
  void setStatus(const std::string& status);

  // Renames the file to `finalPath` (atomically replacing what is there); writing goes on. A new
  // cache is written under a temporary name until its first frame is in, then published.
  void publishAs(const std::string& finalPath);

  std::size_t frameCount() const { return frames_; }
  const std::string& path() const { return path_; }
  // Wall time spent in writeFrame and setStatus (s), for the write share of a run.
  double secondsWriting() const { return secondsWriting_; }
  // Bytes the datasets of the frames written by this writer take in the file (compressed).
  std::uint64_t frameDataBytes() const { return frameDataBytes_; }
  // Bytes the file takes now.
  std::uint64_t fileBytes() const;

  // Closes the file; errors surface here rather than in the destructor.
  void close();

 private:
  CacheWriter(std::string path, h5::Handle file, int lockFd);
  void readSettings();
  void reopen();
  void addMissingVectorViews();
  h5::Handle writeVectorViews(std::size_t frame, std::size_t particles);
  void linkVectorViews(std::size_t frame, std::size_t particles);
  void commitObjects(hid_t rewritten = H5I_INVALID_HID);
  // Removes these links from the root, keeping HDF5's end of allocation (not committed).
  void removeRootLinks(const std::vector<std::string>& names);
  void growFile();
  void journalHeader(hid_t object);
  void writeField(hid_t group, cache::Field field, const Particles& fluid);
  void writeFrameObjects(const Particles& fluid, const run::RunState& state);
  void writeRestart(hid_t record, const Particles& fluid, const run::RunState& state);
  std::uint64_t writeValues(hid_t group, const char* name, hid_t memType, hid_t fileType,
                            const void* data, std::size_t count);
  bool onAllRanks(bool mine) const;
  bool constantEverywhere(const std::vector<float>& v, float& first) const;
  std::size_t frameParticles(const Particles& fluid) const;

  std::string path_;
  h5::Handle file_;
  int fd_ = -1;  // same file, for the write lock and for growing the file ahead of a flush
  std::uint64_t userBlock_ = 0;  // bytes before HDF5's superblock: the journal (CacheJournal.h)
  std::size_t frames_ = 0;
  cache::FieldSet fields_;
  bool restart_ = true;
  bool doublePositions_ = false;
  h5::Storage storage_;
  double secondsWriting_ = 0;
  std::uint64_t frameDataBytes_ = 0;
  const FrameSlice* slice_ = nullptr;   // during a frame written by all ranks together
  std::uint64_t frameEnd_ = 0;          // ... the file size that holds whatever it allocates
  std::set<std::size_t> pointIndexes_;  // lengths of the point indexes the file holds
};

}  // namespace sph::io::cache
