// Pictures while simulating (`sphsplat run` of a scene with a render section): each output frame
// (or every n-th, render.every) is drawn with the scene's splats and camera, written as PNG and,
// with a cache, stored in it under /Render. The GL context exists only in such runs.
#pragma once

#include <memory>
#include <string>

#include "io/OutputLock.h"
#include "io/cache/CacheSession.h"
#include "render/compose/SceneFrame.h"
#include "render/gl/GlContext.h"
#include "sim/run/RunLoop.h"
#include "sim/scene/Scene.h"

namespace sph::job {

class RenderOutput final : public run::FrameSink {
 public:
  // nullptr if the scene has no render section. `cachePath` ("" for none) names the default
  // picture directory: next to the cache, else results/<scene>_frames.
  // Where the pictures of `scene` go: render.directory, else next to the cache, else
  // results/<scene>_frames.
  static std::string directoryFor(const scene::Scene& scene, const std::string& cachePath);
  // With a cache, pictures also go into it (render.to_cache).
  static std::unique_ptr<RenderOutput> prepare(const scene::Scene& scene,
                                               const solver::BoundaryParticles& boundary,
                                               io::cache::CacheSession* cache);

  // Draws output frame `index` of the run (the current state of `sim`).
  void frame(const run::Simulation& sim, std::size_t index) override;

  const std::string& directory() const { return directory_; }
  std::size_t images() const { return images_; }
  double seconds() const { return seconds_; }

 private:
  RenderOutput(const scene::Scene& scene, const solver::BoundaryParticles& boundary,
               std::string directory, io::cache::CacheSession* cache);
  render::gl::GlContext context_;  // first: outlives the GL objects below
  render::compose::SceneFrame frame_;
  scene::RenderDesc desc_;
  scene::CameraDesc camera_;
  scene::CameraPath cameraPath_;
  std::string name_, directory_;
  io::cache::CacheSession* cache_;
  std::size_t images_ = 0;
  double seconds_ = 0;
};

// Creates `dir` and its parents; throws InputError naming it if that fails.
void makeDirectory(const std::string& dir);
// Takes the lock of a directory of frames (io/OutputLock.h) before anything is written into it,
// creating its parent if needed (not the directory itself).
io::OutputLock lockDirectory(const std::string& dir);

}  // namespace sph::job
