#include "sim/rain/RainFeed.h"

#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace sph::rain {
namespace {

// The fluid's particles in cells of one spacing, to find a free place for a new one straight
// above a landing. Only the columns of cells next to a landing's column are indexed: a place is
// searched upwards from a landing, and clear() reads the 27 cells around it, so no other cell
// can matter (hashing the whole fluid at every frame cost about a million allocations a frame
// at a million particles).
class FreeSpace {
 public:
  FreeSpace(const Particles& fluid, float spacing, const std::vector<Vec3>& landings)
      : spacing_(spacing) {
    std::unordered_set<std::uint64_t> columns;
    for (const Vec3& l : landings) {
      const Eigen::Vector3i c = cellOf(l);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dz = -1; dz <= 1; ++dz)
          columns.insert(key(Eigen::Vector3i(c.x() + dx, 0, c.z() + dz)));
    }
    for (std::size_t i = 0; i < fluid.size(); ++i) {
      const Vec3 p = fluid.position(i);
      const Eigen::Vector3i c = cellOf(p);
      if (columns.count(key(Eigen::Vector3i(c.x(), 0, c.z())))) add(p);
    }
  }
  void add(const Vec3& p) { cells_[key(cellOf(p))].push_back(p); }
  // No particle closer than one spacing.
  bool clear(const Vec3& p) const {
    const Eigen::Vector3i c = cellOf(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const Vec3& q : it->second)
            if ((q - p).squaredNorm() < spacing_ * spacing_) return false;
        }
    return true;
  }

 private:
  Eigen::Vector3i cellOf(const Vec3& p) const { return (p / spacing_).array().floor().cast<int>(); }
  static std::uint64_t key(const Eigen::Vector3i& c) {
    auto k = [](int v) { return static_cast<std::uint64_t>(v + (1 << 20)) & 0x1fffff; };
    return k(c.x()) | k(c.y()) << 21 | k(c.z()) << 42;
  }
  float spacing_;
  std::unordered_map<std::uint64_t, std::vector<Vec3>> cells_;
};

}  // namespace

std::unique_ptr<RainFeed> RainFeed::create(const scene::Scene& scene) {
  if (!scene.rain || !scene.rain->feedFluid || !scene.camera) return nullptr;
  return std::unique_ptr<RainFeed>(new RainFeed(scene));
}

RainFeed::RainFeed(const scene::Scene& scene)
    : stepper_(RainStepper::create(scene, RainStepper::sceneAspect(scene))),
      interval_(1.0 / scene.output.fps),
      particleVolume_(static_cast<double>(scene.solver.spacing) * scene.solver.spacing *
                      scene.solver.spacing),
      dropVolume_(scene.rain->dropVolume),
      restDensity_(scene.solver.restDensity),
      spacing_(scene.solver.spacing) {
  stepper_->advanceTo(0, Particles{});  // the drops of t = 0, as the cache stores them
}

double RainFeed::nextTick(double time) const {
  // The run loop's frame times, computed alike (frame * interval) so that both land on the
  // same doubles.
  double k = std::floor(time / interval_);
  double tick = k * interval_;
  while (tick <= time) tick = (++k) * interval_;
  return tick;
}

const std::vector<Vec3>& RainFeed::advanceTo(double time, const Particles& fluid) {
  stepper_->advanceTo(time, fluid);
  return stepper_->system().landings();
}

std::size_t RainFeed::addLandings(const std::vector<Vec3>& landings, FeedState& state,
                                  Particles& fluid, std::uint32_t& nextId) const {
  // The scene refuses drops of more than a particle's water (io/scene/ViewSections.cpp), so a landing
  // completes at most one particle and no two new particles share a position.
  const Vec3 velocity = stepper_->system().velocity();
  std::unique_ptr<FreeSpace> space;  // built at the first particle of the tick
  std::size_t added = 0;
  for (const Vec3& landing : landings) {
    state.landedDrops += 1;
    state.pending += dropVolume_;
    if (state.pending < particleVolume_) continue;
    state.pending -= particleVolume_;
    // Not where the drop entered, among the fluid's particles (a particle closer than a spacing
    // to another is blown away by the pressure, out of the pool), but straight above it where
    // none is within a spacing: on the surface, a new layer of the pool.
    if (!space) space = std::make_unique<FreeSpace>(fluid, spacing_, landings);
    Vec3 p = landing;
    bool clear = space->clear(p);
    for (int k = 0; k < kMaxRise && !clear; ++k) p.y() += 0.25f * spacing_, clear = space->clear(p);
    if (!clear) {  // no room above this landing (a splash): the water waits for the next one
      state.pending += particleVolume_;
      continue;
    }
    space->add(p);
    fluid.append(p, velocity, nextId++, restDensity_);
    state.particles += 1;
    ++added;
  }
  return added;
}

void RainFeed::restore(double time, const std::vector<Vec3>& positions,
                       const std::vector<std::uint32_t>& generations) {
  stepper_->restore(time, positions, generations);
}

}  // namespace sph::rain
