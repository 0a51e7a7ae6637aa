// The XDMF sidecar of a cache (DESIGN.md, "HDF5 cache"): an XML file beside `run.h5` that
// describes every frame as a Polyvertex point set with its time and point attributes, pointing
// at the datasets in the HDF5 file, so ParaView (its default Xdmf3 readers and the older XDMF
// reader) and VisIt open `run.xdmf` as an animated point cloud with the container's boundary
// particles as a second block. Points and vectors come from the cache's [n][3] views
// (Vectors#N, CacheFormat.h), the only form ParaView's Xdmf3 readers take; each point is a
// vertex cell numbered from the cache's point index (Index#L), without which those readers make
// no cells and ParaView draws nothing.
//
// Kept up to date frame by frame: append() writes the whole document to a temporary file and
// renames it over the sidecar, so a reader (or a kill) only ever meets a complete document that
// lists frames already committed to the HDF5 file (it is written after them). Appending in place
// would be cheaper but is not safe: SIGKILL can cut a write that spans memory pages short. To
// keep very long runs linear, a document past 256 kB is rewritten every few frames instead
// (the sidecar then trails the cache by at most size/256 kB frames until flush()).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/cache/CacheFormat.h"
#include "io/cache/CacheReader.h"

namespace sph::io::cache {

class XdmfWriter {
 public:
  // "dir/run.h5" -> "dir/run.xdmf" (the extension replaced, or added when there is none).
  static std::string sidecarPath(const std::string& cachePath);

  // Writes the sidecar for `cacheFileName` (referenced without a directory: the two files move
  // together) listing `frames`; replaces `xdmfPath` atomically (temporary file + rename).
  XdmfWriter(std::string xdmfPath, std::string cacheFileName, const cache::FieldSet& fields,
             bool doublePositions, std::size_t boundaryParticles,
             const std::vector<CacheFrame>& frames);
  XdmfWriter(const XdmfWriter&) = delete;
  XdmfWriter& operator=(const XdmfWriter&) = delete;

  void append(const CacheFrame& frame);
  // Writes the frames appended since the last rewrite, if any.
  void flush();
  const std::string& path() const { return path_; }

  // The sidecar's text for these frames (what the constructor writes).
  std::string document(const std::vector<CacheFrame>& frames) const;

 private:
  std::string frameGrid(const CacheFrame& frame) const;
  std::string head() const;
  std::string tail() const;
  std::string dataItem(const std::string& dataset, const std::string& dimensions, bool isId,
                       bool isPosition, const std::string& indent) const;
  std::string pointGrid(const std::string& name, std::size_t count, const std::string& positions,
                        bool isFluid) const;

  void rewrite();

  std::string path_, cacheFile_;
  cache::FieldSet fields_;
  bool doublePositions_ = false;
  std::size_t boundaryParticles_ = 0;
  std::vector<CacheFrame> frames_;
  std::size_t pending_ = 0;        // frames appended since the last rewrite
  std::size_t documentBytes_ = 0;  // size of the last rewrite
};

}  // namespace sph::io::cache
