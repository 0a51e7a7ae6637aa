#include "render/splat/SplatBuilder.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sim/Parallel.h"

namespace sph::render::splat {
namespace {

// A splat stays flat when the field at the end of its centre's Newton step is below this
// fraction of SD (SplatBuilder.cpp, "flat"): a real surface is there within a few percent.
constexpr float kFlatBelow = 0.85f;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Two unit vectors spanning the plane perpendicular to unit n.
void tangents(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 helper = std::abs(n.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
  t1 = n.cross(helper).normalized();
  t2 = n.cross(t1);
}

void store(SplatVertex& v, const Vec3& p, const Vec3& outward) {
  for (int a = 0; a < 3; ++a) v.position[a] = p[a], v.normal[a] = outward[a];
}

// A surface particle on its way to a splat: the field at its centre, from the normals pass, is
// also the field at the splat's centre vertex (the build reuses it: a fifth of its work).
struct SurfaceParticle {
  std::uint32_t slot;  // in the field's sorted order
  float density;       // D at the particle
  Vec3 gradient;       // gradC (eq. (4))
  Vec3 densityGradient;
  Vec3 normal;  // inward unit
};

// Opaque water: drops the splats that face away from the eye (they lie behind the front surface
// that faces it) and sorts the rest near to far, so the depth test rejects hidden fragments
// before they are shaded. On llvmpipe at 960x540 the two cut the draw of the 25,503-particle
// pool from 18 to 11 ms with the same error figures; splashy simulation frames lose 0.2-0.5 dB
// and a few outline pixels (docs/notes/2026-11-23-splat-renderer.md), so render.cull_back_faces
// can keep them all
// (`cull` false: near to far, nothing dropped). A splat is back-facing when its outward normal
// is more than ~107 deg from the eye direction, not 90: the SPH normals are smoothed, and at the
// outline a splat tilted slightly away still shows.
// Translucent water (alpha < 1) shows its back: keep every splat and sort far to near, the order
// blending needs.
constexpr float kBackFacingCosine = -0.3f;

void orderForDrawing(const DensityField& field, const Vec3& eye, bool translucent, bool cull,
                     std::vector<SurfaceParticle>& surface, SplatFrame& frame) {
  struct Keyed {
    float distance2;
    std::uint32_t k;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(surface.size());
  for (std::uint32_t k = 0; k < surface.size(); ++k) {
    const std::uint32_t s = surface[k].slot;
    const Vec3 toEye = eye - Vec3(field.sortedX()[s], field.sortedY()[s], field.sortedZ()[s]);
    const float distance2 = toEye.squaredNorm();
    // -normal is outward: back-facing when -n . toEye / |toEye| < kBackFacingCosine.
    if (cull && surface[k].normal.dot(toEye) > -kBackFacingCosine * std::sqrt(distance2)) {
      ++frame.backFacing;
      continue;
    }
    keyed.push_back({distance2, k});
  }
  // Ties broken by slot, so the order (and the image) never depends on the sort.
  std::sort(keyed.begin(), keyed.end(), [&](const Keyed& a, const Keyed& b) {
    if (a.distance2 != b.distance2)
      return translucent ? a.distance2 > b.distance2 : a.distance2 < b.distance2;
    return a.k < b.k;
  });
  std::vector<SurfaceParticle> ordered(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) ordered[i] = surface[keyed[i].k];
  surface.swap(ordered);
}

}  // namespace

float surfaceThresholdAuto(const DensityField& field) {
  const float SD = 0.5f * (1.0f + field.flatSurfaceFraction()) * field.restDensity();
  return field.meanDensity() > 0 ? SD / field.meanDensity() : 1.0f;
}

float surfaceDensity(const DensityField& field, float surfaceThreshold) {
  const float threshold = surfaceThreshold > 0 ? surfaceThreshold : surfaceThresholdAuto(field);
  return threshold * field.meanDensity();
}

SplatFrame buildSplats(const DensityField& field, const SplatParams& params, SplatKind kind,
                       const scene::Mat4& projView, const Vec3& eye) {
  SplatFrame frame;
  frame.particles = field.size();
  frame.ID = field.meanDensity();
  frame.SD = surfaceDensity(field, params.surfaceThreshold);
  frame.halfSize = params.splatSize * field.spacing();
  const float R = field.kernelRadius();

  // 1. Surface particles inside the frustum (sorted slots, in order: deterministic).
  auto t0 = Clock::now();
  const scene::Frustum frustum(projView);
  const auto& x = field.sortedX();
  const auto& y = field.sortedY();
  const auto& z = field.sortedZ();
  const auto& rho = field.sortedDensity();
  std::vector<SurfaceParticle> surface;
  for (std::size_t s = 0; s < field.size(); ++s) {
    if (rho[s] >= frame.SD) continue;
    if (!frustum.sphereVisible(Vec3(x[s], y[s], z[s]), frame.halfSize + R)) {
      ++frame.culled;
      continue;
    }
    surface.push_back(SurfaceParticle{static_cast<std::uint32_t>(s), 0, Vec3::Zero(), Vec3::Zero(),
                                      Vec3::Zero()});
  }
  frame.surface = surface.size();
  frame.timings.surface = since(t0);

  // 2. Normals at the particles (inward; the viewer's direction where the field is flat), then
  // the order of drawing (and, opaque, without the back-facing ones).
  t0 = Clock::now();
  parallelFor(surface.size(), [&](std::size_t k) {
    SurfaceParticle& sp = surface[k];
    const Vec3 p(x[sp.slot], y[sp.slot], z[sp.slot]);
    field.densityAndGradients(p, sp.density, sp.gradient, sp.densityGradient);
    const float len = sp.gradient.norm();
    sp.normal = len > 1e-12f ? Vec3(sp.gradient / len) : Vec3((p - eye).normalized());
  });
  orderForDrawing(field, eye, params.translucent, params.cullBackFacing && !params.translucent,
                  surface, frame);
  frame.timings.normals = since(t0);

  // 3. Geometry.
  t0 = Clock::now();
  if (kind == SplatKind::Point) {
    frame.points.resize(surface.size());
    parallelFor(surface.size(), [&](std::size_t k) {
      const std::uint32_t s = surface[k].slot;
      store(frame.points[k], Vec3(x[s], y[s], z[s]), -surface[k].normal);
    });
  } else {
    frame.quads.resize(5 * surface.size());
    frame.indices.resize(12 * surface.size());
    const float ID = frame.ID, SD = frame.SD;
    parallelFor(surface.size(), [&](std::size_t k) {
      const SurfaceParticle& sp = surface[k];
      const Vec3 p(x[sp.slot], y[sp.slot], z[sp.slot]);
      const Vec3 n = sp.normal;
      Vec3 t1, t2;
      tangents(n, t1, t2);
      // A particle whose SD surface is not where the Newton step leads (a thin jet or sheet, a
      // lone drop: D < SD all through it) keeps its splat flat where it is. Moved towards a
      // surface that is not there, every vertex would end on the jet's axis and the jet would be
      // drawn far thinner than its particles (36% of the pour's jet against the particles' own
      // balls, `compare`'s fourth panel). One more field value per splat, at the step's end:
      // short of kFlatBelow x SD there, no surface is near.
      const float reach = frame.halfSize;
      bool flat = false;
      if (params.pyramid && params.projection == SplatParams::Projection::Newton) {
        const float PD0 = params.perVertexDensity ? sp.density : rho[sp.slot];
        const float slope0 = sp.densityGradient.dot(n);
        const float step = slope0 > 1e-6f * ID / R ? (SD - PD0) / slope0 : reach + 1.0f;
        flat = step > reach || (step > 0 && field.density(p + step * n) < kFlatBelow * SD);
      }
      for (int v = 0; v < 5; ++v) {
        Vec3 q = p;
        float PD = sp.density;
        Vec3 g = sp.gradient, gD = sp.densityGradient;
        if (v > 0) {
          const float angle = static_cast<float>(solver::kPi) * (0.25f + 0.5f * (v - 1));
          q += frame.halfSize * (std::cos(angle) * t1 + std::sin(angle) * t2);
          field.densityAndGradients(q, PD, g, gD);
        }
        const Vec3 nv = g.norm() > 1e-12f ? Vec3(g.normalized()) : n;
        if (!params.perVertexDensity) PD = rho[sp.slot];
        float distance = 0;  // along nv, m
        if (!params.pyramid || flat) {
          distance = 0;
        } else if (params.projection == SplatParams::Projection::Newton) {
          // dD/ds along the normal (> 0 into the fluid); a move past `reach` turned thin jets
          // into star-shaped shards.
          const float slope = gD.dot(nv);
          distance = slope > 1e-6f * ID / R ? std::clamp((SD - PD) / slope, -reach, reach) : 0.0f;
        } else {
          // eq. (6). The paper's denominator ID - PD assumes the vertex is less dense than the
          // mean; where it is denser (compressed fluid) the sign flips and the vertex would move
          // the wrong way, so we take its size: the move always points at the SD surface.
          const float denominator = std::max(std::abs(ID - PD), 0.05f * ID);
          distance = R * std::clamp((SD - PD) / denominator, -1.0f, 1.0f);
        }
        // Shaded with the normal from where the vertex started (the paper's order): evaluated
        // again where it lands, on the SD surface, the normal came out noisier (the field is
        // flat near SD ~ ID), 42 deg against 17 deg mean error on the dam break.
        store(frame.quads[5 * k + v], q + distance * nv, -nv);
      }
      const std::uint32_t base = static_cast<std::uint32_t>(5 * k);
      for (std::uint32_t tri = 0; tri < 4; ++tri) {
        frame.indices[12 * k + 3 * tri + 0] = base;
        frame.indices[12 * k + 3 * tri + 1] = base + 1 + tri;
        frame.indices[12 * k + 3 * tri + 2] = base + 1 + (tri + 1) % 4;
      }
    });
  }
  frame.timings.build = since(t0);
  return frame;
}

}  // namespace sph::render::splat
