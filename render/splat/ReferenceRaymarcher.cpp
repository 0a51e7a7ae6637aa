#include "render/splat/ReferenceRaymarcher.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "sim/Parallel.h"
#include "sim/scene/Camera.h"

namespace sph::render::splat {
namespace {

// Casts one ray per pixel (through its centre, as the GL renderer's matrices) into the particles'
// box grown by `grow` (m), up to the backdrop's solid, and shades the first surface
// firstHit(eye, dir, t0, t1) returns (a distance along dir, or a negative number for none) with
// the normal -gradC there, as the splats are shaded.
template <class FirstHit>
frame::RenderImage castRays(const DensityField& field, float grow, const scene::CameraDesc& camera,
                            int width, int height, const frame::Lighting& lighting,
                            const Backdrop* backdrop, FirstHit&& firstHit) {
  const auto start = std::chrono::steady_clock::now();
  frame::RenderImage image;
  image.resize(width, height);
  Vec3 lo = Vec3::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (std::size_t s = 0; s < field.size(); ++s) {
    const Vec3 p(field.sortedX()[s], field.sortedY()[s], field.sortedZ()[s]);
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  lo -= Vec3::Constant(grow), hi += Vec3::Constant(grow);

  // Camera basis (gluLookAt / gluPerspective, as the GL renderer's matrices).
  const scene::CameraBasis basis = scene::cameraBasis(camera);
  const Vec3 &eye = basis.eye, &forward = basis.forward, &right = basis.right, &up = basis.up;
  const float tanHalf = scene::tanHalfFovY(camera);
  const float aspect = static_cast<float>(width) / height;

  parallelForDynamic(static_cast<std::size_t>(height), 1, [&](std::size_t row) {
    for (int col = 0; col < width; ++col) {
      const std::size_t pixel = row * width + col;
      // Through the pixel centre; row 0 is the top of the image.
      const float u = (2.0f * (col + 0.5f) / width - 1.0f) * tanHalf * aspect;
      const float v = (1.0f - 2.0f * (row + 0.5f) / height) * tanHalf;
      const Vec3 dir = (forward + u * right + v * up).normalized();
      // Slab test against the box, up to the solid behind (or in front of) the water.
      float t0 = camera.near, t1 = camera.far;
      if (backdrop) t1 = std::min(t1, backdrop->viewDepth[pixel] / dir.dot(forward));
      for (int a = 0; a < 3; ++a) {
        const float inv = 1.0f / dir[a];
        float ta = (lo[a] - eye[a]) * inv, tb = (hi[a] - eye[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta), t1 = std::min(t1, tb);
      }
      // No particles: nothing to hit (and no box: the bounds above stay inverted).
      const float t = t0 < t1 && field.size() > 0 ? firstHit(eye, dir, t0, t1) : -1.0f;
      if (t < 0) {
        for (int k = 0; k < 3; ++k) {
          image.rgb[3 * pixel + k] =
              backdrop ? backdrop->rgb[3 * pixel + k] : frame::toSrgb8(lighting.background[k]);
        }
        continue;
      }
      const Vec3 g = field.gradient(eye + t * dir);
      const Vec3 n = g.norm() > 0 ? Vec3(-g.normalized()) : Vec3(-dir);
      const Vec3 colour = frame::shade(lighting, n, -dir);
      image.covered[pixel] = 1;
      for (int k = 0; k < 3; ++k) {
        image.normal[3 * pixel + k] = n[k];
        image.rgb[3 * pixel + k] = frame::toSrgb8(colour[k]);
      }
    }
  });
  image.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

}  // namespace

frame::RenderImage raymarchReference(const DensityField& field, float SD,
                                     const scene::CameraDesc& camera, int width, int height,
                                     const frame::Lighting& lighting, const Backdrop* backdrop) {
  // The field is zero beyond the kernel radius of every particle.
  const float R = field.kernelRadius();
  const float step = 0.25f * R;
  auto crossing = [&](const Vec3& eye, const Vec3& dir, float t0, float t1) {
    float previous = t0;
    for (float t = t0; t <= t1 + step; t += step) {
      const float tc = std::min(t, t1);
      if (field.density(eye + tc * dir) >= SD) {
        float a = previous, b = tc;
        while (b - a > 1e-3f * R) {
          const float m = 0.5f * (a + b);
          (field.density(eye + m * dir) >= SD ? b : a) = m;
        }
        return b;
      }
      previous = tc;
      if (tc >= t1) break;
    }
    return -1.0f;
  };
  return castRays(field, R, camera, width, height, lighting, backdrop, crossing);
}

frame::RenderImage raytraceParticleBalls(const DensityField& field, float radius,
                                         const scene::CameraDesc& camera, int width, int height,
                                         const frame::Lighting& lighting,
                                         const Backdrop* backdrop) {
  // Segments of a grid cell's length; the balls whose entry point can lie in a segment have their
  // centres within `radius` of it, so in the cells of its box grown by `radius`.
  const float segment = field.grid().cellSize();
  const float r2 = radius * radius;
  const float *x = field.sortedX().data(), *y = field.sortedY().data(), *z = field.sortedZ().data();
  auto entry = [&](const Vec3& eye, const Vec3& dir, float t0, float t1) {
    for (float a = t0; a < t1; a += segment) {
      const float b = std::min(a + segment, t1);
      const Vec3 pa = eye + a * dir, pb = eye + b * dir;
      const Vec3 lo = pa.cwiseMin(pb) - Vec3::Constant(radius);
      const Vec3 hi = pa.cwiseMax(pb) + Vec3::Constant(radius);
      const float boxLo[3] = {lo.x(), lo.y(), lo.z()}, boxHi[3] = {hi.x(), hi.y(), hi.z()};
      float best = std::numeric_limits<float>::max();
      field.grid().forEachRangeInBox(boxLo, boxHi, [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t j = begin; j < end; ++j) {
          // |eye + t dir - c|^2 = r^2: t = -h -+ sqrt(h^2 - c0), with h = (eye - c).dir.
          const Vec3 oc(eye.x() - x[j], eye.y() - y[j], eye.z() - z[j]);
          const float h = oc.dot(dir), c0 = oc.squaredNorm() - r2;
          const float disc = h * h - c0;
          if (disc < 0) continue;
          const float t = -h - std::sqrt(disc);
          if (t >= a && t < best) best = t;
        }
      });
      if (best <= b) return best;
    }
    return -1.0f;
  };
  return castRays(field, radius, camera, width, height, lighting, backdrop, entry);
}

}  // namespace sph::render::splat
