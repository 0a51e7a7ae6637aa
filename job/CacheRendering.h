// What `render` and `compare` share: a cache opened for drawing, the scene it was made from (with
// the command's --set edits, --splat and --size applied), its camera, and reading a frame's
// positions. The reader lets go of the file while `render --to-cache` writes an image into it
// (HDF5 opens a file in one mode at a time).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "io/cache/CacheReader.h"
#include "render/frame/RenderImage.h"
#include "sim/scene/CameraDesc.h"
#include "sim/Particles.h"
#include "sim/scene/RenderDesc.h"
#include "sim/scene/Scene.h"

namespace sph::job {

// The fields a frame of `scene` needs to be drawn: positions, and velocities for lights coloured
// by speed.
io::cache::FieldSet fieldsToDraw(const scene::Scene& scene);

struct CacheRendering {
  std::string path;
  std::unique_ptr<io::cache::CacheReader> open;  // null while the cache is written
  io::cache::CacheSummary summary;
  scene::Scene scene;
  scene::RenderDesc desc;
  scene::CameraDesc camera;
  bool cameraFromScene = false;

  // `splat`: a render.splat name or empty (the scene's); `size`: WIDTHxHEIGHT or empty.
  CacheRendering(const std::string& path, const std::vector<std::string>& overrides,
                 const std::string& splat, const std::string& size);
  io::cache::CacheReader& reader();
  std::size_t frameCount() const { return summary.frames.size(); }
  double frameTime(std::size_t frame) const { return summary.frames[frame].time; }
  // Positions of `frame` (and velocities where the scene's lights are coloured by speed).
  Particles positions(std::size_t frame);
  // The boundary particles' positions x, y, z (m).
  std::array<std::vector<float>, 3> boundary();
  // Stores an image in the cache as Render#<renderer>#<frame>.
  void store(const std::string& renderer, std::size_t frame,
             const render::frame::RenderImage& image);
};

}  // namespace sph::job
