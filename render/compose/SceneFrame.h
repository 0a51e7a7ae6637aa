// The frame of a scene, assembled one way for every command that draws one (`run` with a render
// section, `render`, `compare`, `view`): the water's splats (render/splat) with the walls the
// render section asks for - boundary points or opaque solids (render/solids) - the particle lights
// of a `lights` section (render/lights) and the rain of a `rain` section (render/rain), each wired
// into the splat frame as its layer, its lights or its spotlight. Needs a current GL context.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "render/lights/SceneLights.h"
#include "render/rain/SceneRain.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/FrameRenderer.h"
#include "sim/Particles.h"
#include "sim/scene/Scene.h"

namespace sph::render::compose {

// The boundary particles' positions x, y, z (m), asked for only when the walls are drawn as
// points.
using BoundaryPositions = std::function<std::array<std::vector<float>, 3>()>;

// What a frame shows besides the water and its opaque solids. The error figures (`compare`) have
// none of these: their reference could not show translucent points, and it has no lights or rain.
struct SceneParts {
  bool boundaryPoints = true;
  bool lights = true;
  bool rain = true;
  // What the error figures show: the water and the opaque solids alone.
  static SceneParts scored() { return {false, false, false}; }
};

// A frame's pictures: one per splat kind render.splat asks for, in drawing order.
struct Picture {
  splat::SplatKind kind;
  splat::RenderedSplats splats;
};
struct Pictures {
  std::vector<Picture> pictures;
  double lightSeconds = 0;  // the particle lights' accumulation (0 without lights)
};

class SceneFrame {
 public:
  // `desc`: the render section the frame is drawn with (the scene's, or a command's edit of it).
  SceneFrame(const scene::Scene& scene, const scene::RenderDesc& desc,
             const BoundaryPositions& boundary, const SceneParts& parts = {});
  SceneFrame(const SceneFrame&) = delete;
  SceneFrame& operator=(const SceneFrame&) = delete;

  // The water `fluid` at time `time` (s) through `camera`: its field, its particle lights and the
  // pictures, each drawn and read back. The rain shows the drops last given to rain().
  Pictures draw(const Particles& fluid, double time, const scene::CameraDesc& camera);

  // draw() in steps, for a window that redraws a frame as its user moves the camera: the water's
  // field, kept for the draws until the next call;
  void setWater(const Particles& fluid);
  // the particle lights of `fluid` at `time`, culled to `camera` over pictures of `aspect` (0:
  // the render section's) where lights.cull asks, the whole volume where `camera` is null;
  // returns the seconds they took (0 without lights);
  double updateLights(const Particles& fluid, double time, const scene::CameraDesc* camera,
                      float aspect = 0);
  // and splats of `kind` into the current window's framebuffer of width x height pixels.
  splat::FrameTimings drawToScreen(splat::SplatKind kind, const scene::CameraDesc& camera,
                                   int width, int height);

  // The splat frame itself, for what only the error figures draw (renderScored, the references).
  splat::FrameRenderer& renderer() { return renderer_; }
  // The splat kinds render.splat asks for, in drawing order.
  const std::vector<splat::SplatKind>& kinds() const { return kinds_; }
  // The scene's lights and rain; null where it has none or the frame does not show them.
  lights::SceneLights* lights() { return lights_.get(); }
  rain::SceneRain* rain() { return rain_.get(); }

 private:
  splat::FrameRenderer renderer_;
  std::vector<splat::SplatKind> kinds_;
  // Layers and lights of renderer_, which points to them.
  std::unique_ptr<solids::SolidRenderer> solids_;
  std::unique_ptr<lights::SceneLights> lights_;
  std::unique_ptr<rain::SceneRain> rain_;
};

}  // namespace sph::render::compose
