#include "sim/cdt/CdtCamera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sph::cdt {

scene::CameraDesc collisionCamera(const scene::CollisionDesc& collision,
                                  const std::optional<scene::CameraDesc>& renderCamera) {
  switch (collision.camera) {
    case scene::CdtCameraMode::Fixed:
      if (!collision.hasPose)
        throw std::invalid_argument("collision.camera \"fixed\" needs collision.pose");
      return collision.pose;
    case scene::CdtCameraMode::Render:
    case scene::CdtCameraMode::Offset: {
      if (!renderCamera)
        throw std::invalid_argument(
            "collision.camera \"render\"/\"offset\" needs the scene's camera");
      scene::CameraDesc c = *renderCamera;
      if (collision.camera == scene::CdtCameraMode::Offset) {
        // Eq. 1 in the camera's frame: its z axis points from the target to the eye.
        const Vec3 back = (c.position - c.target).normalized();
        c.position += collision.offset * back;
        c.target += collision.offset * back;
      }
      return c;
    }
  }
  return *renderCamera;
}

View makeView(const scene::CameraDesc& camera, const std::array<int, 2>& resolution) {
  View v;
  v.width = resolution[0];
  v.height = resolution[1];
  const float aspect = static_cast<float>(v.width) / static_cast<float>(v.height);
  const scene::Mat4 projection =
      scene::perspective(camera.fovYDegrees, aspect, camera.near, camera.far);
  v.projView = multiply(projection, scene::lookAt(camera.position, camera.target, camera.up));
  // A world length l at view depth w spans l * P00 / w NDC units in x, i.e. l * P00 * width / (2 w)
  // texels (same in y with P11 and height).
  v.texelScale = 0.5f * std::max(projection.m[0] * static_cast<float>(v.width),
                                 projection.m[5] * static_cast<float>(v.height));
  return v;
}

// Mirrors cdtTexelOf() in shaders/cdt_common.glsl operation by operation.
TexelAddress texelOf(const View& view, float fx, float fy, float fz) {
  // Float inputs: each product below is exact in double, so only the order of the sums matters.
  const double px = fx, py = fy, pz = fz;
  const auto& m = view.projView.m;
  auto d = [&](int i) { return static_cast<double>(m[static_cast<std::size_t>(i)]); };
  const double cx = d(0) * px + d(4) * py + d(8) * pz + d(12);
  const double cy = d(1) * px + d(5) * py + d(9) * pz + d(13);
  const double cz = d(2) * px + d(6) * py + d(10) * pz + d(14);
  const double cw = d(3) * px + d(7) * py + d(11) * pz + d(15);
  TexelAddress t;
  if (!(cw > 0.0)) return t;
  const double inverseW = 1.0 / cw;
  const double nx = cx * inverseW, ny = cy * inverseW, nz = cz * inverseW;
  // Half-open in x and y so the texel index stays below the resolution; the depth must be
  // strictly inside too (a fragment at depth 1 would fail the GL depth test against the clear).
  if (!(nx >= -1.0 && nx < 1.0 && ny >= -1.0 && ny < 1.0 && nz >= -1.0 && nz < 1.0)) return t;
  // Pseudo-code lines 3-4: TexCoord = (xy + 1) * 0.5, texel = int(TexCoord * resolution).
  const int x = static_cast<int>((nx + 1.0) * 0.5 * view.width);
  const int y = static_cast<int>((ny + 1.0) * 0.5 * view.height);
  if (x >= view.width || y >= view.height) return t;
  t.onScreen = true;
  t.x = x, t.y = y;
  t.depth = static_cast<float>(nz * 0.5 + 0.5);
  t.inverseW = inverseW;
  return t;
}

int adaptiveTexelRange(const View& view, double inverseW, float range, int maxRange) {
  const double texels =
      std::ceil(static_cast<double>(range) * static_cast<double>(view.texelScale) * inverseW);
  return static_cast<int>(std::clamp(texels, 1.0, static_cast<double>(maxRange)));
}

}  // namespace sph::cdt
