// The visible fraction of the rain's budget (docs/rain.md, "The visible budget"): the share of
// the drops that the eye sees, not hidden by a solid or the water - measured from the geometry,
// independently of the rain's own depth image (sim/rain/EyeDepth.h), so that a check on it can
// fail: the solids' signed distance sphere-traced along the eye ray, the water as the particles'
// spheres cut exactly against it. With the scenes and camera paths it is measured on (rain_pour's
// and a stress path with snap turns), shared by test_rain_sight and bench_rain.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "sim/rain/RainSystem.h"
#include "sim/scene/Camera.h"
#include "sim/scene/Scene.h"
#include "sim/scene/Solid.h"

namespace sph::test {

// Whether the eye sees a point, from the geometry alone.
class EyeSight {
 public:
  // `water`: particle centres, each a sphere of `waterRadius` (m).
  EyeSight(std::vector<scene::Solid> solids, std::vector<Vec3> water, float waterRadius);
  bool visible(const Vec3& eye, const Vec3& p) const {
    return !solidOnRay(eye, p) && !waterOnRay(eye, p);
  }
  // Whether the segment eye..p enters a solid: sphere tracing of Solid::distance (a lower bound
  // of the distance, so a step never passes a surface), steps of at least 0.1 mm.
  bool solidOnRay(const Vec3& eye, const Vec3& p) const;
  // How far (m) from the eye along the segment eye..p its first point inside a solid is (found by
  // the same sphere tracing, to 0.1 mm), or a value beyond |p - eye| when there is none.
  float solidAlongRay(const Vec3& eye, const Vec3& p) const;
  // Whether the segment eye..p passes within waterRadius of a particle: the particles near
  // samples of the segment every waterRadius (a grid of cells 2 waterRadius, each particle listed
  // in the cells within 1.5 waterRadius of it), each tested exactly.
  bool waterOnRay(const Vec3& eye, const Vec3& p) const;

 private:
  std::uint64_t key(const Vec3& p) const;
  std::vector<scene::Solid> solids_;
  std::vector<Vec3> water_;
  float radius_, cell_;
  Aabb box_;  // the water's particles grown by 1.5 radius
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid_;
};

// The share of `drops` the eye sees.
double visibleFraction(const EyeSight& sight, const Vec3& eye, const std::vector<Vec3>& drops);
// The share of `drops` inside the rain camera's frustum near..far (sim/scene/Camera.h's
// viewFrustum, not the rain space's own test).
double inViewFraction(const std::vector<Vec3>& drops, const scene::CameraDesc& camera, float aspect,
                      float near, float far);

// The water of rain_pour's pour in full flow, as a stand-in for its simulated fluid (the SPH run
// takes minutes): the cup filled to 8 cm and the nozzle's jet, 2.4 cm across, from the nozzle down
// to the water, particles on the scene's spacing.
std::vector<Vec3> rainPourWater(const scene::Scene& rainPour);

// The paths the fraction is measured on, 30 frames a second.
enum class SightPath {
  RainPour,  // the scene's own camera path over its 2 s
  // From rain_pour's first pose: still, a 90-degree turn within one frame interval, another in
  // 0.1 s, a zoom from 40 to 10 degrees in 0.3 s, a 0.1 m dolly in 0.3 s and a 135-degree turn in
  // 0.2 s: the camera turning about the vertical through its target, the cup, so that the view
  // turns as much and the cup and the tray stay in it.
  Stress,
};
int sightFrames(SightPath path);
scene::CameraDesc sightCamera(const scene::Scene& rainPour, SightPath path, int frame);

// rain_pour's rain (`count` drops, 0: the scene's) along `path` with its solids and the stand-in
// water at every frame, with `occlusion`.
struct SightTrack {
  std::vector<double> visible, inView;  // per frame after the reset, the update's result
  double minVisible = 1, meanVisible = 0, minInView = 1;
  double updateSeconds = 0;  // the updates' wall time, all frames
  rain::RainCounters counters;
};
SightTrack trackSight(const scene::Scene& rainPour, scene::RainOcclusion occlusion, SightPath path,
                      std::size_t count = 0);

}  // namespace sph::test
