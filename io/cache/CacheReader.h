// Reads an HDF5 cache written by CacheWriter (docs/cache-format.md): what it holds, any frame's
// particles, the resume record, the boundary and rendered frames. Every problem with the file
// (missing, not HDF5, truncated, another program's HDF5 file, a missing dataset, a frame out of
// range) is an InputError with one line naming the file and the frame or dataset.
//
// Frames are the groups Step#0, Step#1, ... without a gap; a run killed while writing leaves its
// committed frames only (io/cache/CacheCommit.cpp), so a cache is read the same whether its run finished,
// stopped or was killed. Opening takes no HDF5 file lock, so a cache can be read while a run is
// still appending to it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/cache/CacheFormat.h"
#include "io/cache/Hdf5.h"
#include "sim/Particles.h"
#include "sim/run/Simulation.h"

namespace sph::io::cache {

struct CacheFrame {
  std::size_t index = 0;
  double time = 0;            // s (TimeValue)
  std::size_t particles = 0;  // fluid particles in the frame
  std::uint64_t step = 0;     // solver steps taken up to this frame
  bool hasRestart = false;
  std::size_t rainDrops = 0;  // drops stored as /Rain#N (io/cache/RainCache.h); 0: none
};

struct CacheSummary {
  std::string path;
  std::uint64_t fileBytes = 0;
  std::int64_t formatVersion = 0;
  std::string programVersion, created, status;
  std::string sceneName, scenePath, sceneText, sceneOverrides, sceneFingerprint;
  std::int64_t threads = 0;
  double fps = 0;
  cache::FieldSet fields;
  int compression = 0;
  bool restart = false, doublePositions = false;
  std::vector<cache::Parameter> parameters;  // as recorded (solver.*)
  std::size_t boundaryParticles = 0;
  bool boundaryView = false;  // /Boundary/position exists (caches written before it lack it)
  std::vector<CacheFrame> frames;
  // Set when Step#<frames.size()> exists but does not read back (with what went wrong).
  std::string damagedFrame;
  // Each renderer with the frames it has a picture of, ascending (every frame, or every
  // render.every-th one).
  std::vector<std::pair<std::string, std::vector<std::size_t>>> renderers;
  // The file had a header torn by a kill during a commit and was restored from its journal.
  bool repaired = false;
};

// The scene's --set edits the run was given (stored a line each in sceneOverrides), in order.
std::vector<std::string> sceneEdits(const CacheSummary& summary);

// Frame numbers (ascending) in words for messages and `info`: "31 frames (0-30)",
// "4 frames (0-30, every 10 frames)", "3 frames (1, 4, 9)", "no frame".
std::string describeFrames(const std::vector<std::size_t>& frames);

struct RenderedFrame {
  int width = 0, height = 0;
  double time = 0;
  std::vector<std::uint8_t> rgb;  // height rows of width RGB triplets, top row first
};

class CacheReader {
 public:
  // Opens and checks `path`; reads the summary (cheap: attributes and dataset shapes only).
  explicit CacheReader(const std::string& path);

  const CacheSummary& summary() const { return summary_; }
  std::size_t frameCount() const { return summary_.frames.size(); }

  // The fields of frame `frame` that the cache holds (others left empty), in the order the
  // run had them in memory. `fields` limits what is read; a field asked for but missing is an
  // error naming the dataset. With `runs`, only the particles at those indices (a rank's slab).
  Particles readFrame(std::size_t frame, const cache::FieldSet& fields,
                      const h5::Runs* runs = nullptr) const;
  // Frame `frame` with every field the cache holds.
  Particles readFrame(std::size_t frame) const { return readFrame(frame, summary_.fields); }

  // The state to continue the run from frame `frame`: RunState and every particle array (those
  // not recorded, which the first step recomputes, are zero). With `runs`, only the particles at
  // those indices, and their part of the per-particle state (DFSPH's warm start).
  std::pair<run::RunState, Particles> readRestart(std::size_t frame,
                                                  const h5::Runs* runs = nullptr) const;
  // rain.feed_fluid's ledger of frame `frame` (RunState::rain) without its particles: all zero
  // for a frame without a resume record or a run without fed rain.
  rain::FeedState readRainFeed(std::size_t frame) const;

  // Boundary particle positions (m): x, y, z.
  std::vector<std::vector<float>> readBoundary() const;

  RenderedFrame readRenderedFrame(const std::string& renderer, std::size_t frame) const;

  // Bytes the frames' datasets take in the file (Step#N and Restart#N, as stored, compressed),
  // without the header, the boundary and HDF5's own structures. Opens every dataset: not free.
  std::uint64_t frameDataBytes() const;

  // The open file, for sets stored beside the frames (io/cache/RainCache.h).
  hid_t file() const { return file_.get(); }

 private:
  void load();
  void readHeader();
  void scanFrames(const std::set<std::string>& rootLinks);
  void scanRenderers(const std::set<std::string>& rootLinks);
  void checkFrame(std::size_t frame) const;
  [[noreturn]] void fail(const std::string& message) const;

  std::string path_;
  h5::Handle file_;
  CacheSummary summary_;
};

}  // namespace sph::io::cache
