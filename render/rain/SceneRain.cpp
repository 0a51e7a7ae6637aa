#include "render/rain/SceneRain.h"

#include <chrono>

namespace sph::render::rain {

std::unique_ptr<SceneRain> SceneRain::create(const scene::Scene& scene, float aspect) {
  if (!scene.rain || !scene.camera) return nullptr;
  return std::unique_ptr<SceneRain>(new SceneRain(scene, aspect));
}

SceneRain::SceneRain(const scene::Scene& scene, float aspect)
    : stepper_(sph::rain::RainStepper::create(scene, aspect)), renderer_(*scene.rain) {}

void SceneRain::advanceTo(double time, const Particles& fluid) {
  const auto start = std::chrono::steady_clock::now();
  stepper_->advanceTo(time, fluid);
  renderer_.setDrops(stepper_->system());
  updateSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void SceneRain::restore(double time, const std::vector<Vec3>& positions,
                        const std::vector<std::uint32_t>& generations) {
  stepper_->restore(time, positions, generations);
  renderer_.setDrops(stepper_->system());
}

void SceneRain::show(const sph::rain::RainSystem& drops) {
  renderer_.setDrops(drops);
}

void SceneRain::follow(const scene::CameraDesc& camera) {
  stepper_->follow(camera);
  renderer_.setDrops(stepper_->system());
}

}  // namespace sph::render::rain
