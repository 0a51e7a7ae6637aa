#include "sim/cdt/CdtCpu.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "sim/Parallel.h"
#include "sim/collision/Response.h"

namespace sph::cdt {
namespace {

constexpr std::uint64_t kEmptyKey = std::numeric_limits<std::uint64_t>::max();

std::uint32_t floatBits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

}  // namespace

std::uint64_t texelKey(float depth, std::uint32_t index) {
  return (static_cast<std::uint64_t>(floatBits(depth)) << 32) | index;
}

Settings makeSettings(const scene::CollisionDesc& c,
                      const std::optional<scene::CameraDesc>& renderCamera) {
  Settings s;
  s.view = makeView(collisionCamera(c, renderCamera), c.resolution);
  s.range = c.range;
  s.speedFactor = c.speedFactor;
  s.cooldown = c.cooldown;
  s.texelRange = c.texelRange;
  s.maxTexelRange = c.maxTexelRange;
  s.layers = c.layers;
  if (c.positionSource == scene::CdtPositionSource::Texel) s.flags |= kFlagTexelPosition;
  if (c.adaptiveTexelRange) s.flags |= kFlagAdaptiveRange;
  if (c.response == scene::CollisionResponse::Paper) s.flags |= kFlagPaperResponse;
  s.rasterWrite = c.textureWrite == scene::CdtTextureWrite::Raster;
  return s;
}

CdtCpu::CdtCpu(const Settings& settings) : settings_(settings) {
  // Preconditions: the scene loader allows exactly these ranges (io/scene/SimulationSections.cpp).
  if (settings.layers < 1 || settings.layers > kMaxLayers)
    throw std::invalid_argument("cdt: layers out of range");
  if (settings.texelRange < 0 || settings.texelRange > kMaxTexelRange ||
      settings.maxTexelRange > kMaxTexelRange) {
    throw std::invalid_argument("cdt: texel range out of range");
  }
  texture_.width = settings.view.width;
  texture_.height = settings.view.height;
  texture_.layers = settings.layers;
  const std::size_t count =
      static_cast<std::size_t>(texture_.width) * texture_.height * texture_.layers;
  texture_.texels.assign(count, {0, 0, 0, kEmptyTexel});
  texture_.keys.assign(count, kEmptyKey);
}

void CdtCpu::reset() {
  std::fill(texture_.texels.begin(), texture_.texels.end(),
            std::array<float, 4>{0, 0, 0, kEmptyTexel});
  std::fill(texture_.keys.begin(), texture_.keys.end(), kEmptyKey);
  touched_.clear();
  valid_ = false;
}

void CdtCpu::writeTexture(const float* x, const float* y, const float* z, const std::uint32_t* id,
                          std::size_t n) {
  const std::size_t plane = static_cast<std::size_t>(texture_.width) * texture_.height;
  for (std::uint32_t t : touched_) {
    for (int l = 0; l < texture_.layers; ++l) {
      texture_.texels[l * plane + t] = {0, 0, 0, kEmptyTexel};
      texture_.keys[l * plane + t] = kEmptyKey;
    }
  }
  touched_.clear();
  texelOfParticle_.resize(n);
  keyOfParticle_.resize(n);
  const View& view = settings_.view;
  parallelFor(n, [&](std::size_t i) {
    const TexelAddress a = texelOf(view, x[i], y[i], z[i]);
    texelOfParticle_[i] = a.onScreen ? static_cast<std::int64_t>(a.y) * view.width + a.x : -1;
    keyOfParticle_[i] = texelKey(a.depth, static_cast<std::uint32_t>(i));
  });
  // Draw order, as the GL depth test sees the points: strictly nearer replaces, so among equal
  // depths the first particle stays. Layer k only takes keys beyond layer k-1's (depth peeling).
  for (int l = 0; l < texture_.layers; ++l) {
    std::uint64_t* keys = texture_.keys.data() + l * plane;
    const std::uint64_t* previous = l > 0 ? texture_.keys.data() + (l - 1) * plane : nullptr;
    for (std::size_t i = 0; i < n; ++i) {
      const std::int64_t t = texelOfParticle_[i];
      if (t < 0) continue;
      const std::uint64_t key = keyOfParticle_[i];
      if (previous && key <= previous[t]) continue;
      if (key < keys[t]) {
        if (l == 0 && keys[t] == kEmptyKey) touched_.push_back(static_cast<std::uint32_t>(t));
        keys[t] = key;
        texture_.texels[l * plane + t] = {x[i], y[i], z[i], static_cast<float>(id[i])};
      }
    }
  }
  valid_ = true;
}

void CdtCpu::step(Particles& p, float dt, bool integrate) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    // A precondition: runs never start with a scene that could pass it (requireIdsInRange).
    if (p.id[i] >= kMaxId)
      throw std::invalid_argument(
          "cdt: particle ids must stay below 2^24 (the texture stores them as floats)");
  }
  diagnostics_.assign(n, Diagnostics{});
  pairs_.clear();
  nx_.resize(n), ny_.resize(n), nz_.resize(n), nvx_.resize(n), nvy_.resize(n), nvz_.resize(n),
      nt_.resize(n);
  const Settings& s = settings_;
  const View& view = s.view;
  const bool texelPosition = (s.flags & kFlagTexelPosition) != 0;
  const bool adaptive = (s.flags & kFlagAdaptiveRange) != 0;
  const bool paper = (s.flags & kFlagPaperResponse) != 0;
  const double h = dt;
  const double range = s.range;
  const double range2 = range * range;
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> threadPairs(
      recordPairs_ ? threadCount() : 0);

  collision::ResponseParams response;
  response.paper = paper;
  response.range = range;
  response.speedFactor = s.speedFactor;
  response.cooldown = s.cooldown;
  response.dt = h;

  parallelFor(n, [&](std::size_t i) {
    const std::uint32_t self = p.id[i];
    const float P[3] = {p.x[i], p.y[i], p.z[i]}, V[3] = {p.vx[i], p.vy[i], p.vz[i]},
                A[3] = {p.ax[i], p.ay[i], p.az[i]};
    const collision::StepState state = collision::stepState(P, V, A, h, integrate);
    Diagnostics& diag = diagnostics_[i];
    bool found = false;
    double best = range2;
    float partner[3] = {0, 0, 0};
    float cur[3] = {state.p0[0], state.p0[1], state.p0[2]};
    const TexelAddress a = texelOf(view, state.p0[0], state.p0[1], state.p0[2]);
    // Line 8: only particles whose cooldown has run out search.
    if (valid_ && a.onScreen && p.collideTime[i] < 0.0f) {
      bool search = true;
      if (texelPosition) {
        // Line 5: curr_pos = the base texel, whoever is stored there.
        const std::array<float, 4>& c = texture_.at(0, a.x, a.y);
        search = c[3] >= 0.0f;
        cur[0] = c[0], cur[1] = c[1], cur[2] = c[2];
      }
      if (search) {
        const int r = adaptive ? adaptiveTexelRange(view, a.inverseW, s.range, s.maxTexelRange)
                               : s.texelRange;
        diag.texel = static_cast<std::uint32_t>(a.x) | (static_cast<std::uint32_t>(a.y) << 16);
        diag.texelRange = static_cast<std::uint32_t>(r);
        for (int l = 0; l < s.layers; ++l) {
          for (int ty = -r; ty <= r; ++ty) {
            const int y = a.y + ty;
            if (y < 0 || y >= view.height) continue;
            for (int tx = -r; tx <= r; ++tx) {
              // Lines 12-13: the paper skips the base texel, which it read as curr_pos.
              if (texelPosition && tx == 0 && ty == 0) continue;
              const int x = a.x + tx;
              if (x < 0 || x >= view.width) continue;
              const std::array<float, 4>& t = texture_.at(l, x, y);
              if (t[3] < 0.0f) continue;  // empty
              const std::uint32_t other = static_cast<std::uint32_t>(t[3]);
              if (other == self) continue;  // its own previous position
              const double dx = static_cast<double>(cur[0]) - static_cast<double>(t[0]);
              const double dy = static_cast<double>(cur[1]) - static_cast<double>(t[1]);
              const double dz = static_cast<double>(cur[2]) - static_cast<double>(t[2]);
              const double d2 = dx * dx + dy * dy + dz * dz;
              if (!(d2 < range2)) continue;
              ++diag.candidates;
              if (recordPairs_)
                threadPairs[static_cast<std::size_t>(threadIndex())].emplace_back(self, other);
              // Lines 16-19: the nearest in range wins, the first of equals.
              if (d2 < best) {
                best = d2, found = true, diag.partner = other;
                partner[0] = t[0], partner[1] = t[1], partner[2] = t[2];
              }
            }
          }
        }
      }
    }
    const collision::Outcome o =
        found ? collision::collideOutcome(state, cur, partner, best, self, diag.partner,
                                          p.collideTime[i], response)
              : collision::freeOutcome(state, p.collideTime[i], h);
    nx_[i] = o.p[0], ny_[i] = o.p[1], nz_[i] = o.p[2];
    nvx_[i] = o.v[0], nvy_[i] = o.v[1], nvz_[i] = o.v[2];
    nt_[i] = o.collideTime;
  });

  p.x.swap(nx_), p.y.swap(ny_), p.z.swap(nz_);
  p.vx.swap(nvx_), p.vy.swap(nvy_), p.vz.swap(nvz_);
  p.collideTime.swap(nt_);
  for (auto& t : threadPairs) pairs_.insert(pairs_.end(), t.begin(), t.end());
  writeTexture(p.x.data(), p.y.data(), p.z.data(), p.id.data(), n);
}

void CdtCpuPass::apply(Particles& particles, const CollisionContext& context) {
  cdt_.step(particles, static_cast<float>(context.dt), false);
}

}  // namespace sph::cdt
