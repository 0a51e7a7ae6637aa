#include "render/lights/ExactLights.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sph::render::lights {

int ExactLights::cellOf(const Vec3& p, int a) const {
  const int c = static_cast<int>(std::floor((p[a] - lo_[a]) / cellSize_));
  return std::clamp(c, 0, cells_[static_cast<std::size_t>(a)] - 1);
}

ExactLights::ExactLights(const scene::LightsDesc& desc,
                         const std::vector<sph::lights::LightParticle>& lights)
    : desc_(desc) {
  cellSize_ = std::max(desc.range, 1e-6f);
  Vec3 lo = Vec3::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (const sph::lights::LightParticle& l : lights) {
    const Vec3 p(l.position[0], l.position[1], l.position[2]);
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  if (lights.empty()) lo = hi = Vec3::Zero();
  lo_ = lo;
  for (int a = 0; a < 3; ++a) {
    cells_[static_cast<std::size_t>(a)] =
        std::clamp(static_cast<int>(std::floor((hi[a] - lo[a]) / cellSize_)) + 1, 1, 1024);
  }
  const std::size_t n = static_cast<std::size_t>(cells_[0]) * cells_[1] * cells_[2];
  auto index = [&](const sph::lights::LightParticle& l) {
    const Vec3 p(l.position[0], l.position[1], l.position[2]);
    return (static_cast<std::size_t>(cellOf(p, 2)) * cells_[1] + cellOf(p, 1)) * cells_[0] +
           cellOf(p, 0);
  };
  cellStart_.assign(n + 1, 0);
  for (const sph::lights::LightParticle& l : lights) ++cellStart_[index(l) + 1];
  for (std::size_t c = 0; c < n; ++c) cellStart_[c + 1] += cellStart_[c];
  lights_.resize(lights.size());
  std::vector<std::size_t> next(cellStart_.begin(), cellStart_.end() - 1);
  for (const sph::lights::LightParticle& l : lights) lights_[next[index(l)]++] = l;
}

LightTerms ExactLights::at(const Vec3& x, const Vec3& n, const Vec3& toEye,
                           const Vec3& base) const {
  LightTerms t;
  if (lights_.empty()) return t;
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    // Cells overlapping [x - range, x + range]; points far outside the lights' box see none.
    const float r = desc_.range;
    const float cLo = std::floor((x[a] - r - lo_[a]) / cellSize_);
    const float cHi = std::floor((x[a] + r - lo_[a]) / cellSize_);
    lo[a] = static_cast<int>(std::max(cLo, 0.0f));
    hi[a] = static_cast<int>(
        std::min(cHi, static_cast<float>(cells_[static_cast<std::size_t>(a)] - 1)));
    if (lo[a] > hi[a]) return t;
  }
  for (int cz = lo[2]; cz <= hi[2]; ++cz) {
    for (int cy = lo[1]; cy <= hi[1]; ++cy) {
      for (int cx = lo[0]; cx <= hi[0]; ++cx) {
        const std::size_t c = (static_cast<std::size_t>(cz) * cells_[1] + cy) * cells_[0] + cx;
        for (std::size_t k = cellStart_[c]; k < cellStart_[c + 1]; ++k) {
          const sph::lights::LightParticle& l = lights_[k];
          const Vec3 toLight = Vec3(l.position[0], l.position[1], l.position[2]) - x;
          const float d = toLight.norm();
          const float att = sph::lights::lightAttenuation(desc_, d);
          if (att == 0.0f || d <= 0.0f) continue;
          const Vec3 colour = att * Vec3(l.colour[0], l.colour[1], l.colour[2]);
          const Vec3 dir = toLight / d;
          t.diffuse += desc_.diffuse * std::max(n.dot(dir), 0.0f) * base.cwiseProduct(colour);
          const Vec3 r = 2.0f * n.dot(dir) * n - dir;  // reflect(-dir, n)
          t.specular +=
              desc_.specular * std::pow(std::max(r.dot(toEye), 0.0f), desc_.shininess) * colour;
        }
      }
    }
  }
  return t;
}

LightError lightError(const std::vector<Vec3>& approx, const std::vector<Vec3>& exact) {
  LightError e;
  double se = 0, ae = 0;
  const std::size_t n = std::min(approx.size(), exact.size());
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      const double d = std::clamp(approx[i][a], 0.0f, 1.0f) - std::clamp(exact[i][a], 0.0f, 1.0f);
      se += d * d, ae += std::abs(d);
    }
  }
  const double count = 3.0 * static_cast<double>(std::max<std::size_t>(n, 1));
  const double mse = se / count;
  e.meanAbs = ae / count;
  e.psnr = mse > 0 ? 10 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
  return e;
}

}  // namespace sph::render::lights
