#include "sim/rain/RainSystem.h"

#include <algorithm>
#include <cmath>

#include "sim/rain/RainRandom.h"
#include "sim/rain/ViewSampler.h"

namespace sph::rain {
namespace {

// Candidates before a drop gives up and is parked at the sphere's centre (inside the frustum),
// counted in RainCounters::parked. `view` with `uniform` sampling draws from the sphere's cube or
// the frustum's pyramid, whichever holds more of the rain space (sim/rain/ViewSampler.h): it
// accepts at least ~1/4 of its candidates at any field of view (docs/rain.md), so 512 miss only
// where the solids and the water fill nearly all the rain space. `paper`'s eq. (7) samples of
// the whole sphere pile up at its centre, on the camera's axis, so a narrow frustum catches more
// of them than of uniform ones, but not enough at the narrowest: 15% of drops parked at fov 1
// degree, 0.3% at 2, none from 3 (16:9).
constexpr int kMaxTries = 512;
// Draws per try in the counter space (see unitRandom's `draw`) for `box`, `region` and `paper`.
constexpr std::uint64_t kDrawsPerTry = 8;

}  // namespace

WaterCells::WaterCells(const std::vector<Vec3>& fluid, float cell) : cell_(cell) {
  cells_.reserve(fluid.size());
  for (const Vec3& p : fluid) {
    cells_.insert(key(p));
    const Vec3 corner = (p / cell_).array().floor().matrix() * cell_;
    bounds_.grow(corner), bounds_.grow(Vec3(corner + Vec3::Constant(cell_)));
  }
}

bool WaterCells::near(const Vec3& a, const Vec3& b) const {
  // A cell's margin: the corners are rounded, and so is the key of a point on a face.
  const Vec3 margin = Vec3::Constant(cell_);
  return (a.cwiseMin(b).array() <= (bounds_.hi + margin).array()).all() &&
         (a.cwiseMax(b).array() >= (bounds_.lo - margin).array()).all();
}

WaterCells WaterCells::fromKeys(const std::vector<std::uint64_t>& keys, float cell) {
  WaterCells w(cell);
  w.cells_.reserve(keys.size());
  w.cells_.insert(keys.begin(), keys.end());
  // The bounds `near` tests, as the constructor grows them.
  for (std::uint64_t k : w.cells_) {
    const Vec3 corner = cornerOf(k, cell);
    w.bounds_.grow(corner), w.bounds_.grow(Vec3(corner + Vec3::Constant(cell)));
  }
  return w;
}

Vec3 WaterCells::cornerOf(std::uint64_t key, float cell) {
  // The cell's index times the cell: the same float as floor(p / cell) * cell.
  auto index = [&](int shift) {
    return static_cast<float>(static_cast<std::int64_t>((key >> shift) & 0x1fffff) - (1 << 20));
  };
  return Vec3(index(0), index(21), index(42)) * cell;
}

std::vector<std::uint64_t> WaterCells::keys() const {
  std::vector<std::uint64_t> k(cells_.begin(), cells_.end());
  std::sort(k.begin(), k.end());
  return k;
}

std::uint64_t WaterCells::keyOf(const Vec3& p, float cell) {
  auto c = [&](float v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / cell)) + (1 << 20)) &
           0x1fffff;
  };
  return c(p.x()) | c(p.y()) << 21 | c(p.z()) << 42;
}

bool WaterCells::contains(const Vec3& p) const {
  return cells_.count(key(p)) != 0;
}

Vec3 paperBallPoint(const float u[5]) {
  const float theta = 2 * static_cast<float>(M_PI) * u[0];  // eq. (6)
  // eq. (6)'s phi = acos(2 u1 - 1), used only through its cosine and sine: those directly,
  // without the acos and a second sincos.
  const float cosPhi = 2 * u[1] - 1;
  const float sinPhi = std::sqrt(std::max(0.0f, 1 - cosPhi * cosPhi));
  const Vec3 dir(sinPhi * std::cos(theta), sinPhi * std::sin(theta), cosPhi);
  // eq. (7): random seed(-r, r) drawn separately for x, y and z.
  return Vec3((2 * u[2] - 1) * dir.x(), (2 * u[3] - 1) * dir.y(), (2 * u[4] - 1) * dir.z());
}

RainSystem::RainSystem(const scene::RainDesc& desc, float aspect) : desc_(desc), aspect_(aspect) {}

void RainSystem::setCamera(const scene::CameraDesc& camera, const RainObstacles& obstacles) {
  const float oldFov = space_.radius > 0 ? lastFov_ : -1;
  space_ = RainSpace::build(camera, aspect_, desc_.near, desc_.far);
  if (desc_.spawn == scene::RainSpawn::Box && camera.fovYDegrees != oldFov)
    boxEdge_ = static_cast<float>(std::cbrt(space_.volume()));
  lastFov_ = camera.fovYDegrees;
  if (desc_.spawn == scene::RainSpawn::View && desc_.occlusion == scene::RainOcclusion::DepthMap) {
    eyeDepth_.build(space_, obstacles.solids, obstacles.water);
    // A wall across the view: no drop is seen beyond it, so none is drawn there.
    if (eyeDepth_.active()) space_.limitDraws(eyeDepth_.maxDepth());
  } else {
    eyeDepth_.clear();
  }
}

bool RainSystem::inSpawnVolume(const Vec3& p) const {
  switch (desc_.spawn) {
    case scene::RainSpawn::View:
      return space_.contains(p);
    case scene::RainSpawn::Box:
      return ((p - space_.eye).cwiseAbs().array() <= 0.5f * boxEdge_).all();
    case scene::RainSpawn::Region:
      return desc_.region.contains(p);
  }
  return false;
}

bool insideSolid(const Vec3& p, const std::vector<scene::Solid>& solids) {
  for (const scene::Solid& s : solids) {
    if (s.distance(p) < 0) return true;
  }
  return false;
}

float firstSolidEntry(const Vec3& a, const Vec3& b, const std::vector<scene::Solid>& solids) {
  float first = 2;
  for (const scene::Solid& s : solids) first = std::min(first, s.segmentEntry(a, b));
  return first;
}

bool RainSystem::blocked(const Vec3& p, const RainObstacles& obstacles) {
  return (obstacles.solids && insideSolid(p, *obstacles.solids)) ||
         (obstacles.water && obstacles.water->contains(p));
}

std::uint8_t RainSystem::layerOf(std::size_t i) const {
  return layerFrom(DropRandom(desc_.seed, i, generations_[i]));
}

std::uint8_t RainSystem::layerFrom(const DropRandom& u) const {
  const float u0 = u(0);
  return static_cast<std::uint8_t>(std::min<int>(
      static_cast<int>(u0 * static_cast<float>(desc_.streakLayers)), desc_.streakLayers - 1));
}

void RainSystem::spawn(std::size_t i, const RainObstacles& obstacles, ViewSpawnCount& count) {
  const DropRandom u(desc_.seed, i, generations_[i]);
  layers_[i] = layerFrom(u);
  const bool view = desc_.spawn == scene::RainSpawn::View;
  if (view && desc_.sampling == scene::RainSampling::Uniform) {
    auto freeHere = [&](const Vec3& p) { return placeable(p, obstacles); };
    if (!spawnInView(space_, u, kMaxTries, freeHere, positions_[i], count))
      positions_[i] = space_.centre, ++count.parked;  // nowhere free: as the other models, below
    return;
  }
  const Vec3 lo = desc_.spawn == scene::RainSpawn::Box
                      ? Vec3(space_.eye - Vec3::Constant(0.5f * boxEdge_))
                      : desc_.region.lo;
  const Vec3 size = desc_.spawn == scene::RainSpawn::Box ? Vec3::Constant(boxEdge_)
                                                         : Vec3(desc_.region.hi - desc_.region.lo);
  for (int t = 0; t < kMaxTries; ++t) {
    const std::uint64_t d = 1 + static_cast<std::uint64_t>(t) * kDrawsPerTry;
    // Draws 3 and 4 only where eq. (7) uses them (numbers are per draw index: skipping some
    // changes none of the others).
    const float draws[5] = {u(d), u(d + 1), u(d + 2), view ? u(d + 3) : 0.0f,
                            view ? u(d + 4) : 0.0f};
    Vec3 p;
    if (view) {
      p = space_.centre + space_.radius * paperBallPoint(draws);
      if (!space_.insideSides(p)) {  // eq. (8)-(9)
        ++count.rejected;
        continue;
      }
    } else {
      p = lo + Vec3(draws[0], draws[1], draws[2]).cwiseProduct(size);
    }
    if (!placeable(p, obstacles)) continue;
    positions_[i] = p;
    return;
  }
  // Nowhere free found (the space is nearly all solid or unlucky): park the drop at the
  // space's centre, where the next update tries again.
  positions_[i] = view ? space_.centre : Vec3(lo + 0.5f * size);
  ++count.parked;
}

void RainSystem::reset(const scene::CameraDesc& camera, const RainObstacles& obstacles) {
  setCamera(camera, obstacles);
  positions_.assign(desc_.count, Vec3::Zero());
  generations_.assign(desc_.count, 0);
  layers_.assign(desc_.count, 0);
  counters_ = {};
  landings_.clear();
  std::uint64_t rejected = 0, outside = 0, parked = 0;
  const auto n = static_cast<std::ptrdiff_t>(desc_.count);
#pragma omp parallel for reduction(+ : rejected, outside, parked) schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    ViewSpawnCount c;
    spawn(static_cast<std::size_t>(i), obstacles, c);
    rejected += c.rejected, outside += c.outsideSphere, parked += c.parked;
  }
  counters_.rejected += rejected;
  counters_.outsideSphere += outside;
  counters_.parked += parked;
  counters_.accepted += desc_.count;
}

void RainSystem::restore(const scene::CameraDesc& camera, const std::vector<Vec3>& positions,
                         const std::vector<std::uint32_t>& generations) {
  setCamera(camera, {});
  positions_ = positions;
  generations_ = generations;
  layers_.resize(positions_.size());
  for (std::size_t i = 0; i < layers_.size(); ++i) layers_[i] = layerOf(i);
  counters_ = {};
  landings_.clear();
}

bool RainSystem::entersWater(const Vec3& from, const Vec3& to, float upTo,
                             const RainObstacles& obstacles, Vec3& entry) {
  const WaterCells& water = *obstacles.water;
  if (!water.near(from, to)) return false;
  const float quarter = 0.25f * water.cell();
  const int samples = std::max(1, static_cast<int>(std::ceil((to - from).norm() / quarter)));
  for (int k = 1; k <= samples; ++k) {
    const float t = static_cast<float>(k) / static_cast<float>(samples);
    // The samples of the whole path, not of the part up to the solid, so that a drop that meets
    // the water before any solid finds it at the same point either way (a feeding rain places
    // its particle there).
    if (t > upTo) return false;
    const Vec3 p = k == samples ? to : Vec3(from + t * (to - from));
    if (water.contains(p) && !(obstacles.solids && insideSolid(p, *obstacles.solids))) {
      entry = p;
      return true;
    }
  }
  return false;
}

void RainSystem::moveAndTest(std::size_t begin, std::size_t end, const Vec3& step,
                             std::uint8_t* out) {
  // One loop per spawn model, each without a call or a branch: GCC runs the view's in SIMD
  // lanes (16 drops at a time with AVX-512). The rain space and the step are copied so that the
  // compiler sees the stores to the drops cannot change them. The moves are those one at a time
  // would make.
  Vec3* p = positions_.data() + begin;
  const std::size_t n = end - begin;
  const Vec3 move = step;
  if (desc_.spawn == scene::RainSpawn::View) {
    const RainSpace s = space_;
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 q = p[k] + move;
      p[k] = q;
      out[k] = !s.contains(q);
    }
    return;
  }
  for (std::size_t k = 0; k < n; ++k) {
    p[k] += move;
    out[k] = !inSpawnVolume(p[k]);
  }
}

void RainSystem::update(const scene::CameraDesc& camera, float dt, const RainObstacles& obstacles) {
  landings_.clear();
  if (positions_.empty()) return reset(camera, obstacles);
  setCamera(camera, obstacles);
  const Vec3 step = velocity() * dt;
  // Only a feeding rain records where drops landed: nothing of it otherwise.
  const bool feed = desc_.feedFluid && obstacles.water;
  if (feed) hit_.assign(positions_.size(), 0), entries_.resize(positions_.size());
  const bool anyObstacle = obstacles.water || obstacles.solids;
  std::uint64_t left = 0, solid = 0, water = 0, hidden = 0, rejected = 0, outside = 0, parked = 0;
  // Chunks of drops: first all of a chunk moved and tested in lanes, then the few that left
  // respawned (~17% a frame in a 90-degree-a-second pan), while the chunk is in the cache.
  constexpr std::size_t kChunk = 1024;
  const std::size_t size = positions_.size();
  const auto chunks = static_cast<std::ptrdiff_t>((size + kChunk - 1) / kChunk);
#pragma omp parallel for reduction(+ : left, solid, water, hidden, rejected, outside, parked) \
    schedule(static)
  for (std::ptrdiff_t c = 0; c < chunks; ++c) {
    const std::size_t begin = static_cast<std::size_t>(c) * kChunk;
    const std::size_t end = std::min(size, begin + kChunk);
    std::uint8_t out[kChunk];
    moveAndTest(begin, end, step, out);
    // The drops to look at - those out of the space, all where there are obstacles - listed
    // without a branch: a branch per drop, taken by ~17% at random, cost more than the listing.
    std::uint16_t look[kChunk];
    std::size_t count = 0;
    for (std::size_t k = 0; k < end - begin; ++k) {
      look[count] = static_cast<std::uint16_t>(k);
      count += anyObstacle | out[k];
    }
    ViewSpawnCount spawned;  // the chunk's spawns' candidates
    for (std::size_t j = 0; j < count; ++j) {
      const std::size_t i = begin + look[j];
      const bool outOfSpace = out[look[j]] != 0;
      const Vec3& p = positions_[i];
      const Vec3 from = p - step;
      // The whole path over the step against the solids, not its end: a drop falls ~10 cm a
      // frame, through a 1 cm floor (docs/rain.md, "Replay"). It stops where it first enters one.
      const float inSolid = obstacles.solids ? firstSolidEntry(from, p, *obstacles.solids) : 2;
      Vec3 entry;
      // The water along the path up to there: a drop that entered it landed, also when it went on
      // into the floor or out of the sheet of water; one that met a solid first did not reach it.
      if (obstacles.water && entersWater(from, p, inSolid, obstacles, entry)) {
        ++water;
        if (feed) hit_[i] = 1, entries_[i] = entry;
      } else if (inSolid <= 1) {
        ++solid;
      } else if (outOfSpace) {
        ++left;
      } else if (!eyeDepth_.visible(p)) {  // fell or turned out of the eye's sight
        ++hidden;
      } else {
        continue;
      }
      ++generations_[i];
      spawn(i, obstacles, spawned);
    }
    rejected += spawned.rejected, outside += spawned.outsideSphere, parked += spawned.parked;
  }
  counters_.leftSpace += left, counters_.hitSolid += solid, counters_.hitWater += water;
  counters_.hidden += hidden;
  counters_.rejected += rejected;
  counters_.outsideSphere += outside;
  counters_.parked += parked;
  counters_.accepted += left + solid + water + hidden;
  if (feed) {
    for (std::size_t i = 0; i < hit_.size(); ++i)
      if (hit_[i]) landings_.push_back(entries_[i]);
  }
}

}  // namespace sph::rain
