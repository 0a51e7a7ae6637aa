#include "tests/RainSight.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sim/rain/RainStepper.h"

namespace sph::test {

EyeSight::EyeSight(std::vector<scene::Solid> solids, std::vector<Vec3> water, float waterRadius)
    : solids_(std::move(solids)),
      water_(std::move(water)),
      radius_(waterRadius),
      cell_(2 * waterRadius) {
  const float reach = 1.5f * radius_;
  for (std::size_t i = 0; i < water_.size(); ++i) {
    const Vec3& q = water_[i];
    box_.grow(Vec3(q - Vec3::Constant(reach))), box_.grow(Vec3(q + Vec3::Constant(reach)));
    const Vec3 lo = ((q - Vec3::Constant(reach)) / cell_).array().floor();
    const Vec3 hi = ((q + Vec3::Constant(reach)) / cell_).array().floor();
    for (float x = lo.x(); x <= hi.x(); ++x)
      for (float y = lo.y(); y <= hi.y(); ++y)
        for (float z = lo.z(); z <= hi.z(); ++z)
          grid_[key(Vec3((x + 0.5f) * cell_, (y + 0.5f) * cell_, (z + 0.5f) * cell_))].push_back(
              static_cast<std::uint32_t>(i));
  }
}

std::uint64_t EyeSight::key(const Vec3& p) const {
  auto c = [&](float v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / cell_)) +
                                      (1 << 20)) &
           0x1fffff;
  };
  return c(p.x()) | c(p.y()) << 21 | c(p.z()) << 42;
}

float EyeSight::solidAlongRay(const Vec3& eye, const Vec3& p) const {
  auto distance = [&](const Vec3& q) {
    float d = 1e30f;
    for (const scene::Solid& s : solids_) d = std::min(d, s.distance(q));
    return d;
  };
  const Vec3 ray = p - eye;
  const float length = ray.norm();
  const Vec3 dir = ray / length;
  for (float t = 0; t < length;) {
    const float d = distance(eye + t * dir);
    if (d < 0) return t;
    t += std::max(d, 1e-4f);
  }
  return distance(p) < 0 ? length : 2 * length + 1;
}

bool EyeSight::solidOnRay(const Vec3& eye, const Vec3& p) const {
  return solidAlongRay(eye, p) <= (p - eye).norm();
}

bool EyeSight::waterOnRay(const Vec3& eye, const Vec3& p) const {
  if (water_.empty()) return false;
  // The part of the segment inside the water's box (slab test).
  float t0 = 0, t1 = 1;
  const Vec3 ray = p - eye;
  for (int k = 0; k < 3; ++k) {
    if (ray[k] == 0) {
      if (eye[k] < box_.lo[k] || eye[k] > box_.hi[k]) return false;
      continue;
    }
    float a = (box_.lo[k] - eye[k]) / ray[k], b = (box_.hi[k] - eye[k]) / ray[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a), t1 = std::min(t1, b);
  }
  if (t0 > t1) return false;
  const float length = ray.norm();
  const float r2 = radius_ * radius_;
  auto near = [&](const Vec3& q) {  // the segment within radius of q
    const float t = std::clamp((q - eye).dot(ray) / ray.squaredNorm(), 0.0f, 1.0f);
    return (eye + t * ray - q).squaredNorm() < r2;
  };
  // Samples every radius: the point of the segment nearest a particle it passes within radius
  // of is within half a radius of a sample, which is then within 1.5 radius of the particle.
  const int samples = std::max(1, static_cast<int>(std::ceil((t1 - t0) * length / radius_)));
  for (int k = 0; k <= samples; ++k) {
    const float t = t0 + (t1 - t0) * static_cast<float>(k) / static_cast<float>(samples);
    const auto cell = grid_.find(key(Vec3(eye + t * ray)));
    if (cell == grid_.end()) continue;
    for (std::uint32_t i : cell->second)
      if (near(water_[i])) return true;
  }
  return false;
}

double visibleFraction(const EyeSight& sight, const Vec3& eye, const std::vector<Vec3>& drops) {
  std::size_t seen = 0;
  const auto n = static_cast<std::ptrdiff_t>(drops.size());
#pragma omp parallel for reduction(+ : seen) schedule(dynamic, 256)
  for (std::ptrdiff_t i = 0; i < n; ++i)
    seen += sight.visible(eye, drops[static_cast<std::size_t>(i)]);
  return static_cast<double>(seen) / static_cast<double>(drops.size());
}

double inViewFraction(const std::vector<Vec3>& drops, const scene::CameraDesc& camera, float aspect,
                      float near, float far) {
  const scene::Frustum f = scene::viewFrustum(camera, aspect, near, far);
  std::size_t in = 0;
  for (const Vec3& p : drops) {
    bool inside = true;
    for (int k = 0; k < 6; ++k) inside = inside && f.distance(k, p) >= -1e-4f;
    in += inside;
  }
  return static_cast<double>(in) / static_cast<double>(drops.size());
}

std::vector<Vec3> rainPourWater(const scene::Scene& rainPour) {
  std::vector<Vec3> water;
  const float h = rainPour.solver.spacing;
  for (float x = -0.05f + h / 2; x < 0.05f; x += h)
    for (float z = -0.05f + h / 2; z < 0.05f; z += h) {
      const float r2 = x * x + z * z;
      for (float y = h / 2; y < 0.08f && r2 < 0.05f * 0.05f; y += h) water.emplace_back(x, y, z);
      for (float y = 0.08f; y < 0.2f && r2 < 0.012f * 0.012f; y += h) water.emplace_back(x, y, z);
    }
  return water;
}

int sightFrames(SightPath path) {
  return path == SightPath::RainPour ? 60 : 46;
}

scene::CameraDesc sightCamera(const scene::Scene& rainPour, SightPath path, int frame) {
  if (path == SightPath::RainPour)
    return scene::cameraAt(*rainPour.camera, rainPour.cameraPath, frame / 30.0);
  scene::CameraDesc c = *rainPour.camera;
  const int f = frame;
  double yaw = 0;         // degrees the camera has turned about the vertical through its target
  if (f >= 10) yaw = 90;  // within one frame interval (9 -> 10)
  if (f >= 20) yaw = 90 + 30.0 * std::min(f - 19, 3);        // 90 more in 0.1 s
  if (f >= 41) yaw = 180 + 135.0 * std::min(f - 40, 6) / 6;  // 135 more in 0.2 s
  if (f >= 23) c.fovYDegrees = static_cast<float>(40 - 30.0 * std::min(f - 22, 9) / 9);
  const double a = yaw * M_PI / 180;
  Vec3 arm = c.position - c.target;  // about the vertical through the target
  arm = Vec3(static_cast<float>(arm.x() * std::cos(a) + arm.z() * std::sin(a)), arm.y(),
             static_cast<float>(-arm.x() * std::sin(a) + arm.z() * std::cos(a)));
  if (f >= 32) arm *= 1 - 0.1f / arm.norm() * static_cast<float>(std::min(f - 31, 9)) / 9;
  c.position = c.target + arm;
  return c;
}

SightTrack trackSight(const scene::Scene& rainPour, scene::RainOcclusion occlusion, SightPath path,
                      std::size_t count) {
  scene::RainDesc d = *rainPour.rain;
  d.occlusion = occlusion;
  if (count > 0) d.count = count;
  const float aspect = rain::RainStepper::sceneAspect(rainPour);
  std::vector<scene::Solid> solids;
  for (const scene::BoundaryShape& b : rainPour.boundaries)
    solids.emplace_back(b, rainPour.solver.wallThickness());
  const std::vector<Vec3> water = rainPourWater(rainPour);
  const rain::WaterCells cells(water, rain::RainStepper::waterCell(rainPour));
  const EyeSight sight(solids, water, rainPour.solver.spacing);
  rain::RainObstacles obstacles;
  obstacles.solids = &solids, obstacles.water = &cells;
  rain::RainSystem r(d, aspect);
  SightTrack track;
  using Clock = std::chrono::steady_clock;
  for (int f = 0; f <= sightFrames(path); ++f) {
    const scene::CameraDesc c = sightCamera(rainPour, path, f);
    const Clock::time_point start = Clock::now();
    if (f == 0)
      r.reset(c, obstacles);
    else
      r.update(c, 1.0f / 30, obstacles);
    if (f > 0) track.updateSeconds += std::chrono::duration<double>(Clock::now() - start).count();
    track.visible.push_back(visibleFraction(sight, c.position, r.positions()));
    track.inView.push_back(inViewFraction(r.positions(), c, aspect, d.near, d.far));
  }
  for (std::size_t k = 0; k < track.visible.size(); ++k) {
    track.minVisible = std::min(track.minVisible, track.visible[k]);
    track.meanVisible += track.visible[k] / static_cast<double>(track.visible.size());
    track.minInView = std::min(track.minInView, track.inView[k]);
  }
  track.counters = r.counters();
  return track;
}

}  // namespace sph::test
