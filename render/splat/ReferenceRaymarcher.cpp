#include "render/splat/ReferenceRaymarcher.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "sim/Parallel.h"

namespace sph::render::splat {

RenderImage raymarchReference(const DensityField& field, float SD, const CameraDesc& camera,
                              int width, int height, const Lighting& lighting) {
  const auto start = std::chrono::steady_clock::now();
  RenderImage image;
  image.resize(width, height);
  // Box of the particles grown by the kernel radius: the field is zero outside it.
  const float R = field.kernelRadius();
  Vec3 lo = Vec3::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (std::size_t s = 0; s < field.size(); ++s) {
    const Vec3 p(field.sortedX()[s], field.sortedY()[s], field.sortedZ()[s]);
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  lo -= Vec3::Constant(R), hi += Vec3::Constant(R);

  // Camera basis (gluLookAt / gluPerspective, as the GL renderer's matrices).
  const Vec3 eye = camera.position;
  const Vec3 forward = (camera.target - eye).normalized();
  const Vec3 right = forward.cross(camera.up).normalized();
  const Vec3 up = right.cross(forward);
  const float tanHalf = std::tan(0.5f * camera.fovYDegrees * static_cast<float>(kPi) / 180.0f);
  const float aspect = static_cast<float>(width) / height;
  const float step = 0.25f * R;
  const Vec3 backgroundColour = lighting.background;

  parallelForDynamic(static_cast<std::size_t>(height), 1, [&](std::size_t row) {
    for (int col = 0; col < width; ++col) {
      const std::size_t pixel = row * width + col;
      // Through the pixel centre; row 0 is the top of the image.
      const float u = (2.0f * (col + 0.5f) / width - 1.0f) * tanHalf * aspect;
      const float v = (1.0f - 2.0f * (row + 0.5f) / height) * tanHalf;
      const Vec3 dir = (forward + u * right + v * up).normalized();
      // Slab test against the box.
      float t0 = camera.near, t1 = camera.far;
      for (int a = 0; a < 3; ++a) {
        const float inv = 1.0f / dir[a];
        float ta = (lo[a] - eye[a]) * inv, tb = (hi[a] - eye[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta), t1 = std::min(t1, tb);
      }
      Vec3 colour = backgroundColour;
      if (t0 < t1) {
        float previous = t0;
        for (float t = t0; t <= t1 + step; t += step) {
          const float tc = std::min(t, t1);
          if (field.density(eye + tc * dir) >= SD) {
            float a = previous, b = tc;
            while (b - a > 1e-3f * R) {
              const float m = 0.5f * (a + b);
              (field.density(eye + m * dir) >= SD ? b : a) = m;
            }
            const Vec3 p = eye + b * dir;
            const Vec3 g = field.gradient(p);
            const Vec3 n = g.norm() > 0 ? Vec3(-g.normalized()) : Vec3(-dir);
            colour = shade(lighting, n, -dir);
            image.covered[pixel] = 1;
            for (int k = 0; k < 3; ++k) image.normal[3 * pixel + k] = n[k];
            break;
          }
          previous = tc;
          if (tc >= t1) break;
        }
      }
      for (int k = 0; k < 3; ++k) image.rgb[3 * pixel + k] = toSrgb8(colour[k]);
    }
  });
  image.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

}  // namespace sph::render::splat
