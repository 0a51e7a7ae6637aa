#include "render/lights/ExactLights.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sph::render::lights {

namespace {

// Cells per axis a key can name (21 bits each): the cell is grown past `range` only for a scene
// more than 2^21 ranges wide.
constexpr std::int64_t kAxisCells = std::int64_t{1} << 21;

}  // namespace

std::uint64_t ExactLights::keyOf(std::int64_t cx, std::int64_t cy, std::int64_t cz) const {
  return (static_cast<std::uint64_t>(cz) << 42) | (static_cast<std::uint64_t>(cy) << 21) |
         static_cast<std::uint64_t>(cx);
}

ExactLights::ExactLights(const scene::LightsDesc& desc,
                         const std::vector<sph::lights::LightParticle>& lights)
    : desc_(desc) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (const sph::lights::LightParticle& l : lights) {
    const Vec3 p(l.position[0], l.position[1], l.position[2]);
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  if (lights.empty()) lo = hi = Vec3::Zero();
  lo_ = lo;
  const float extent = (hi - lo).maxCoeff();
  cellSize_ = std::max({desc.range, 1e-6f, extent / static_cast<float>(kAxisCells - 2)});
  auto cell = [&](float v, int a) {
    return std::clamp(static_cast<std::int64_t>(std::floor((v - lo_[a]) / cellSize_)),
                      std::int64_t{0}, kAxisCells - 1);
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order(lights.size());
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const auto& p = lights[i].position;
    order[i] = {keyOf(cell(p[0], 0), cell(p[1], 1), cell(p[2], 2)), static_cast<std::uint32_t>(i)};
  }
  std::sort(order.begin(), order.end());
  lights_.resize(lights.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    lights_[i] = lights[order[i].second];
    if (i == 0 || order[i].first != order[i - 1].first) {
      keys_.push_back(order[i].first);
      cellStart_.push_back(i);
    }
  }
  cellStart_.push_back(lights_.size());
}

LightTerms ExactLights::at(const Vec3& x, const Vec3& n, const Vec3& toEye,
                           const Vec3& base) const {
  LightTerms t;
  if (lights_.empty()) return t;
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    // Cells overlapping [x - range, x + range]; points far outside the lights' box see none.
    const float r = desc_.range;
    const double cLo = std::floor((static_cast<double>(x[a]) - r - lo_[a]) / cellSize_);
    const double cHi = std::floor((static_cast<double>(x[a]) + r - lo_[a]) / cellSize_);
    if (cHi < 0 || cLo > static_cast<double>(kAxisCells - 1)) return t;
    lo[a] = static_cast<std::int64_t>(std::max(cLo, 0.0));
    hi[a] = static_cast<std::int64_t>(std::min(cHi, static_cast<double>(kAxisCells - 1)));
  }
  for (std::int64_t cz = lo[2]; cz <= hi[2]; ++cz) {
    for (std::int64_t cy = lo[1]; cy <= hi[1]; ++cy) {
      for (std::int64_t cx = lo[0]; cx <= hi[0]; ++cx) {
        const auto found = std::lower_bound(keys_.begin(), keys_.end(), keyOf(cx, cy, cz));
        if (found == keys_.end() || *found != keyOf(cx, cy, cz)) continue;
        const std::size_t c = static_cast<std::size_t>(found - keys_.begin());
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
