#include "sim/lights/LightParticles.h"

#include "sim/solver/SceneSetup.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace sph::lights {
namespace {

// SplitMix64: a well-mixed 64-bit hash, so every light's numbers depend on (seed, index) alone.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}
double unit(std::uint64_t h) {
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

LightParticle make(const Vec3& p, const Vec3& colour, float intensity) {
  return {{p.x(), p.y(), p.z(), 0.0f},
          {colour.x() * intensity, colour.y() * intensity, colour.z() * intensity, intensity}};
}

}  // namespace

Vec3 emitterLightPosition(const scene::LightEmitterDesc& e, std::size_t i, double time) {
  const std::uint64_t key = mix((static_cast<std::uint64_t>(e.seed) << 32) ^ i);
  std::uint64_t h = key;
  double u[5];
  for (double& v : u) v = unit(h = mix(h));
  // A uniform direction: z uniform in [-1, 1], azimuth uniform.
  const double z = 2 * u[3] - 1, phi = 2 * 3.14159265358979323846 * u[4];
  const double s = std::sqrt(std::max(0.0, 1 - z * z));
  const double dir[3] = {s * std::cos(phi), s * std::sin(phi), z};
  Vec3 p;
  for (int a = 0; a < 3; ++a) {
    const double lo = e.box.lo[a], size = e.box.hi[a] - e.box.lo[a];
    double x = u[a] * size + dir[a] * e.speed * time;
    x -= size * std::floor(x / size);
    p[a] = static_cast<float>(lo + x);
  }
  return p;
}

std::vector<scene::Solid> lightSolids(const scene::Scene& scene) {
  std::vector<scene::Solid> solids;
  const float thickness = scene.solver.wallThickness();
  for (const scene::BoundaryShape& b : scene.boundaries) solids.emplace_back(b, thickness);
  return solids;
}

std::vector<LightParticle> lightParticles(const scene::LightsDesc& d, const Particles& fluid,
                                          double time, const std::vector<scene::Solid>& solids) {
  std::vector<LightParticle> out;
  auto colourAt = [&](float speed) {
    if (d.colouring == scene::LightColouring::Constant) return d.colour;
    const float t = std::clamp(speed / d.fastSpeed, 0.0f, 1.0f);
    return Vec3((1 - t) * d.colour + t * d.fastColour);
  };
  switch (d.source) {
    case scene::LightSource::Fluid:
      out.resize(fluid.size());
      for (std::size_t i = 0; i < fluid.size(); ++i) {
        const float speed = fluid.vx.empty()
                                ? 0.0f
                                : std::sqrt(fluid.vx[i] * fluid.vx[i] + fluid.vy[i] * fluid.vy[i] +
                                            fluid.vz[i] * fluid.vz[i]);
        out[i] = make(fluid.position(i), colourAt(speed), d.intensity);
      }
      break;
    case scene::LightSource::Emitter:
      out.reserve(d.emitter.count);
      for (std::size_t i = 0; i < d.emitter.count; ++i) {
        const Vec3 p = emitterLightPosition(d.emitter, i, time);
        bool inside = false;
        for (const scene::Solid& s : solids) inside = inside || s.distance(p) < 0;
        if (!inside) out.push_back(make(p, colourAt(d.emitter.speed), d.intensity));
      }
      break;
  }
  return out;
}

}  // namespace sph::lights
