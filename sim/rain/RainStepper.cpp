#include "sim/rain/RainStepper.h"

#include <algorithm>

#include "sim/scene/RenderDesc.h"
#include "sim/solver/SceneSetup.h"

namespace sph::rain {

std::unique_ptr<RainStepper> RainStepper::create(const scene::Scene& scene, float aspect) {
  if (!scene.rain || !scene.camera) return nullptr;
  return std::unique_ptr<RainStepper>(new RainStepper(scene, aspect));
}

float RainStepper::sceneAspect(const scene::Scene& scene) {
  const scene::RenderDesc d = scene.render ? *scene.render : scene::RenderDesc{};
  return static_cast<float>(d.width) / static_cast<float>(d.height);
}

RainStepper::RainStepper(const scene::Scene& scene, float aspect)
    : camera_(*scene.camera),
      path_(scene.cameraPath),
      interval_(1.0 / scene.output.fps),
      waterCell_(waterCell(scene)),
      system_(*scene.rain, aspect) {
  const float thickness = scene.solver.wallThickness();
  for (const scene::BoundaryShape& b : scene.boundaries) solids_.emplace_back(b, thickness);
}

void RainStepper::advanceTo(double time, const Particles& fluid) {
  std::vector<Vec3> water;
  water.reserve(fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i)
    water.emplace_back(fluid.x[i], fluid.y[i], fluid.z[i]);
  advanceTo(time, WaterCells(water, waterCell_));
}

void RainStepper::advanceTo(double time, const WaterCells& water) {
  RainObstacles solidsOnly;
  solidsOnly.solids = &solids_;
  if (time_ < 0 || time < time_) {
    system_.reset(cameraAt(camera_, path_, 0.0), solidsOnly);
    time_ = 0;
  }
  RainObstacles all = solidsOnly;
  all.water = &water;
  while (time_ < time - 1e-9) {
    const double next = std::min(time_ + interval_, time);
    const bool last = next >= time - 1e-9;
    system_.update(cameraAt(camera_, path_, next), static_cast<float>(next - time_),
                   last ? all : solidsOnly);
    time_ = next;
  }
}

void RainStepper::follow(const scene::CameraDesc& camera) {
  RainObstacles solidsOnly;
  solidsOnly.solids = &solids_;
  system_.update(camera, 0, solidsOnly);
}

void RainStepper::restore(double time, const std::vector<Vec3>& positions,
                          const std::vector<std::uint32_t>& generations) {
  system_.restore(cameraAt(camera_, path_, time), positions, generations);
  time_ = time;
}

}  // namespace sph::rain
