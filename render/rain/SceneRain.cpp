#include "render/rain/SceneRain.h"

#include <algorithm>
#include <chrono>

#include "sim/Camera.h"
#include "sim/SceneSetup.h"

namespace sph::render::rain {

std::unique_ptr<SceneRain> SceneRain::create(const Scene& scene, float aspect) {
  if (!scene.rain || !scene.camera) return nullptr;
  return std::unique_ptr<SceneRain>(new SceneRain(scene, aspect));
}

SceneRain::SceneRain(const Scene& scene, float aspect)
    : camera_(*scene.camera),
      path_(scene.cameraPath),
      interval_(1.0 / scene.output.fps),
      // Cells of two spacings: the particles of a body of water leave none of them empty.
      waterCell_(2 * scene.solver.spacing),
      system_(*scene.rain, aspect),
      renderer_(*scene.rain) {
  const float thickness = deriveParams(scene).boundaryLayers * scene.solver.spacing;
  for (const BoundaryShape& b : scene.boundaries) solids_.emplace_back(b, thickness);
}

void SceneRain::advanceTo(double time, const Particles& fluid) {
  const auto start = std::chrono::steady_clock::now();
  sph::rain::RainObstacles solidsOnly;
  solidsOnly.solids = &solids_;
  if (time_ < 0 || time < time_) {
    system_.reset(cameraAt(camera_, path_, 0.0), solidsOnly);
    time_ = 0;
  }
  std::vector<Vec3> water;
  water.reserve(fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i)
    water.emplace_back(fluid.x[i], fluid.y[i], fluid.z[i]);
  const sph::rain::WaterCells cells(water, waterCell_);
  sph::rain::RainObstacles all = solidsOnly;
  all.water = &cells;
  while (time_ < time - 1e-9) {
    const double next = std::min(time_ + interval_, time);
    const bool last = next >= time - 1e-9;
    system_.update(cameraAt(camera_, path_, next), static_cast<float>(next - time_),
                   last ? all : solidsOnly);
    time_ = next;
  }
  renderer_.setDrops(system_);
  updateSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void SceneRain::follow(const CameraDesc& camera) {
  sph::rain::RainObstacles solidsOnly;
  solidsOnly.solids = &solids_;
  system_.update(camera, 0, solidsOnly);
  renderer_.setDrops(system_);
}

std::unique_ptr<SceneRain> showRain(const Scene& scene, splat::FrameRenderer& renderer,
                                    splat::FrameLayer* solids) {
  const RenderDesc& d = renderer.desc();
  auto rain = SceneRain::create(scene, static_cast<float>(d.width) / static_cast<float>(d.height));
  if (!rain) return nullptr;
  std::vector<splat::FrameLayer*> layers;
  if (solids) layers.push_back(solids);
  layers.push_back(&rain->layer());
  renderer.setLayers(std::move(layers));
  renderer.setSpotlight(scene.rain->spotlight);
  return rain;
}

}  // namespace sph::render::rain
