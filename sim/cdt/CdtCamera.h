// The collision camera of the CDT algorithm and the one texel-addressing formula shared by
// cdt-cpu (sim/cdt/CdtCpu.cpp) and cdt-gl (shaders/cdt_common.glsl, cdtTexelOf) - seed 000, section
// 3.2, pseudo-code lines 2-4, and section 3.4 (camera modes, eq. 1).
//
// Texel addressing is done in double on both sides: the inputs are floats, so every product of
// two of them is exact in double and an FMA, or its absence, cannot change a texel. The GLSL
// marks the same expressions `precise` and evaluates them in the same order, so the CPU and GL
// passes put every particle in the same texel bit for bit (tests/test_cdt_gl.cpp).
#pragma once

#include <array>
#include <optional>

#include "sim/scene/Camera.h"
#include "sim/scene/CollisionDesc.h"

namespace sph::cdt {

// The collision camera's pose (seed 000, section 3.4): `render` = the scene camera, `fixed` =
// collision.pose, `offset` = the render camera moved by `offset` along its own z axis (eq. 1:
// C_CDC = C_RC + [0, 0, offset] in the camera's frame; +z points away from the target, so a
// positive offset moves it back). Throws std::invalid_argument if the mode needs a camera that
// the scene lacks (the loader refuses such scenes first).
scene::CameraDesc collisionCamera(const scene::CollisionDesc& collision,
                                  const std::optional<scene::CameraDesc>& renderCamera);

// A collision camera with its texture: projection * view, resolution, and texels per metre at
// view depth 1 (for the adaptive texel range).
struct View {
  scene::Mat4 projView;
  int width = 0, height = 0;  // texels
  float texelScale = 0;       // texels per metre at depth 1: max(P00 width, P11 height) / 2
};
View makeView(const scene::CameraDesc& camera, const std::array<int, 2>& resolution);

// Where a world position lands: its base texel and its depth in [0, 1] (NDC z / 2 + 1/2), or not
// on the texture at all (behind the camera, outside the frustum).
struct TexelAddress {
  bool onScreen = false;
  int x = 0, y = 0;
  float depth = 0;
  double inverseW = 0;  // 1 / clip w (1 / view depth, m^-1)
};
TexelAddress texelOf(const View& view, float px, float py, float pz);

// texel_collide_range for a particle at 1/w = inverseW: the collision range projected to texels,
// rounded up, in [1, maxRange] (our improvement for failure mode 1, close-up vs long shot).
int adaptiveTexelRange(const View& view, double inverseW, float range, int maxRange);

}  // namespace sph::cdt
