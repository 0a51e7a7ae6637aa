// Builds the splats of one frame on the CPU (seed 003, sections 4-5; DESIGN.md, "The renderer"):
//  1. surface particles: field density D below SD = threshold x ID (ID = mean density);
//  2. normal n = gradC / |gradC| (eq. (4)-(5)), pointing into the fluid; shading uses -n;
//  3. point splats: one camera-facing square per surface particle, one normal (the baseline);
//     quad splats: a square of 4 triangles (centre + 4 corners) perpendicular to n, centred on
//     the particle, each vertex with its own normal and moved by eq. (6)
//        P' = P + R (SD - PD) / (ID - PD) n,   the fraction clamped to [-1, 1]
//     onto the estimated SD iso-surface (R the kernel radius). PD is the density at the vertex
//     (ours: it turns the flat square into a pyramid) or at the particle (the paper's reading).
// Splats of particles outside the view frustum are not built, nor (opaque water) those that face
// away from the eye.
#pragma once

#include <cstdint>
#include <vector>

#include "render/splat/DensityField.h"
#include "sim/scene/Camera.h"
#include "sim/scene/RenderDesc.h"
#include "sim/Types.h"

namespace sph::render::splat {

struct SplatParams {
  // spacings: R of the field (render.kernel_radius); 2.5 gave smoother normals than 2 (the
  // dam break's mean normal error fell from 17 to 14 deg) at 1.5x the cost.
  float kernelRadius = 2.5f;
  float surfaceThreshold = 0;  // SD / ID; 0 = automatic (surfaceThresholdAuto)
  // spacings from the centre to a corner: neighbours overlap at any rotation (1.0 left holes).
  float splatSize = 1.5f;
  // eq. (6) with PD at each vertex (false: the paper's, per particle).
  bool perVertexDensity = true;
  // false: flat squares with per-vertex normals, the paper's Figure 4(a), to show what eq. (6)
  // adds.
  bool pyramid = true;
  // How far eq. (6) moves a vertex: `Equation6` assumes the density rises linearly from PD to ID
  // over the kernel radius (the paper); `Newton` takes one Newton step on the field itself,
  // (SD - PD) / |gradD| along the normal, clamped to the kernel radius (ours).
  using Projection = scene::SplatProjection;
  Projection projection = Projection::Newton;
  // The splats are blended (render.alpha < 1): the back of the water shows through, so keep the
  // back-facing splats and draw far to near. Opaque (false): drop them (unless cullBackFacing is
  // false: render.cull_back_faces), draw near to far.
  bool translucent = false;
  bool cullBackFacing = true;
};

// The automatic SD: halfway between the density of a particle on a flat free surface and the
// rest density, so the top layer of a resting pool is surface and the layer below is not (the
// paper leaves the choice to the user and names an automatic one as future work). Returned as a
// fraction of the mean density ID, like render.surface_threshold.
float surfaceThresholdAuto(const DensityField& field);
// SD in kg/m^3, the iso-level every surface of the field is drawn at (the splats, the reference
// ray-marcher, the mesh): `surfaceThreshold` x ID, or the automatic fraction for 0.
float surfaceDensity(const DensityField& field, float surfaceThreshold);

// Vertex layout shared with shaders/splat_*.vert (location 0 position, 1 normal).
struct SplatVertex {
  float position[3];  // m
  float normal[3];    // unit, outward (for shading)
};
static_assert(sizeof(SplatVertex) == 24, "matches the vertex attributes of shaders/splat_*.vert");

struct SplatTimings {
  double surface = 0, normals = 0, build = 0;  // s
};

struct SplatFrame {
  std::vector<SplatVertex> points;     // one per point splat: centre + normal
  std::vector<SplatVertex> quads;      // 5 per quad splat: centre, then 4 corners
  std::vector<std::uint32_t> indices;  // 12 per quad splat: 4 triangles
  // surface: surface particles inside the frustum; culled: surface particles outside it;
  // backFacing: surface particles whose splat faces away from the eye, dropped when opaque.
  // Splats built: surface - backFacing, ordered for drawing (near to far; translucent: far to
  // near).
  std::size_t particles = 0, surface = 0, culled = 0, backFacing = 0;
  std::size_t splats() const { return surface - backFacing; }
  float ID = 0, SD = 0;  // mean and surface densities (kg/m^3)
  float halfSize = 0;    // m, centre-to-corner of a splat
  SplatTimings timings;
};

enum class SplatKind { Point, Quad };
// `view --splat`, the PNG names and the cache's /Render groups (sim/scene/EnumNames.h).
constexpr const char* nameOf(SplatKind v) {
  switch (v) {
    case SplatKind::Point:
      return "point";
    case SplatKind::Quad:
      return "quad";
  }
  return nullptr;
}

// Builds the splats of `kind` for the particles of `field`, seen through `projView`.
SplatFrame buildSplats(const DensityField& field, const SplatParams& params, SplatKind kind,
                       const scene::Mat4& projView, const Vec3& eye);

}  // namespace sph::render::splat
