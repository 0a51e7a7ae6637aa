#include "tests/StillTankFloor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/run/Observables.h"

namespace sph::test {

void StillTankFloor::advanceTo(run::Simulation& sim, double t) {
  const float below = -1.0f, above = 1e3f;
  // Boundary particles stand at the centres of lattice cells: a box whose sides lie on cell
  // faces holds those of a floor area (its side)^2 (a quarter of a side that is not a whole
  // number of cells would cut through a row of them and count it or not).
  const double margin = std::round(0.25 * width_ / spacing_) * spacing_;
  const double side = std::round((width_ - 2 * margin) / spacing_) * spacing_;
  const float lo = static_cast<float>(margin), hi = static_cast<float>(margin + side);
  const Aabb centre{Vec3(lo, below, lo), Vec3(hi, 0, hi)};
  // The whole floor: every boundary particle below its surface, the side walls' feet included,
  // since the particles in the corner under a wall carry the floor's load there as much as the
  // wall's (over the floor's area under the water).
  const Aabb floor{Vec3(-above, below, -above), Vec3(above, 0, above)};
  const Aabb all{Vec3::Constant(-above), Vec3::Constant(above)};
  while (sim.time() < t) {
    sim.step(t);
    const Particles& p = sim.fluid();
    const solver::DerivedParams& d = sim.params();
    auto load = [&](const Aabb& sensor) {
      return run::wallLoad(p, sim.boundary().particles(), sim.boundaryPressureTerm(), sensor,
                           d.mass, d.h, sim.gradientCorrection());
    };
    const double weight =
        static_cast<double>(p.size()) * d.mass * sim.scene().solver.gravity.norm();
    const double reading = -load(centre).y() / (side * side);
    centre_ += reading;
    centreReadings_.push_back(reading);
    floor_ += -load(floor).y() / (width_ * width_);
    total_ += load(all).dot(sim.scene().solver.gravity.cast<double>()) /
              (weight * sim.scene().solver.gravity.norm());
    readProfile(p, d.mass, sim.scene().solver.gravity.norm());
    const run::LayerMean bottom = run::bottomLayer(p, spacing_);
    bottomPressure_ += bottom.pressure;
    bottomHeight_ += bottom.height;
    ++steps_;
  }
}

namespace {

// The standard deviation of `v` around their mean.
double spread(const std::vector<double>& v) {
  if (v.size() < 2) return 0;
  double mean = 0, squares = 0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  for (double x : v) squares += (x - mean) * (x - mean);
  return std::sqrt(squares / static_cast<double>(v.size() - 1));
}

}  // namespace

double StillTankFloor::centreStepSpread() const {
  return spread(centreReadings_);
}

double StillTankFloor::centreMeanError() const {
  constexpr std::size_t kBlock = 10;
  std::vector<double> blocks;
  for (std::size_t at = 0; at + kBlock <= centreReadings_.size(); at += kBlock) {
    double sum = 0;
    for (std::size_t k = at; k < at + kBlock; ++k) sum += centreReadings_[k];
    blocks.push_back(sum / kBlock);
  }
  return blocks.size() < 2 ? 0 : spread(blocks) / std::sqrt(static_cast<double>(blocks.size()));
}

void StillTankFloor::readProfile(const Particles& p, double mass, double g) {
  const double lo = 0.25 * width_, hi = 0.75 * width_, rim = 1.5 * spacing_;
  // The weight above a particle's centre over the tank's area: the particles above it, and half
  // a particle for its own (the ranks across a layer of equal heights average half the layer).
  order_.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) order_[i] = static_cast<std::uint32_t>(i);
  std::sort(order_.begin(), order_.end(), [&](std::uint32_t a, std::uint32_t b) {
    return p.y[a] != p.y[b] ? p.y[a] > p.y[b] : a < b;
  });
  const double top = p.size() ? p.y[order_[0]] : 0, weightScale = mass * g / (width_ * width_);
  const double depth =
      static_cast<double>(p.size()) * spacing_ * spacing_ * spacing_ / (width_ * width_);
  double topSum = 0, stepSpeed = 0, meanVy = 0;
  int topCount = 0;
  for (std::size_t rank = 0; rank < order_.size(); ++rank) {
    const std::uint32_t i = order_[rank];
    const double x = p.x[i], y = p.y[i], z = p.z[i];
    const double speed = p.velocity(i).norm();
    stepSpeed = std::max(stepSpeed, speed);
    if (speed > kStill) ++fastParticleSteps_, fastIds_.insert(p.id[i]);
    meanVy += p.vy[i];
    if (y > top - spacing_) topSum += y, ++topCount;
    const bool centre = x > lo && x < hi && z > lo && z < hi;
    const bool besideWall = std::min({x, z, width_ - x, width_ - z}) < rim;
    const bool midDepth = y > 0.2 * depth && y < 0.8 * depth;
    auto add = [&](Region r) {
      pressure_[r] += p.p[i];
      expected_[r] += weightScale * (static_cast<double>(rank) + 0.5);
    };
    if (y < spacing_) add(centre ? kFloorLayerCentre : kFloorLayerRim);
    if (midDepth && besideWall) add(kBesideSideWalls);
    if (midDepth && centre) add(kCentreColumns);
  }
  maxSpeed_ = std::max(maxSpeed_, stepSpeed);
  meanVy = p.size() ? std::fabs(meanVy) / static_cast<double>(p.size()) : 0;
  largestHeave_ = std::max(largestHeave_, meanVy);
  if (meanVy > kHeave) {
    ++heaveSteps_;
  } else {
    quietMaxSpeed_ = std::max(quietMaxSpeed_, stepSpeed);
  }
  lastTop_ = topCount ? topSum / topCount : 0;
  depth_ = depth;
  if (steps_ == 0) firstTop_ = lastTop_;
}

void StillTankFloor::print(const char* solver, double expected, bool profile) const {
  std::printf(
      "%s floor sensor: centre %.1f Pa (+-%.1f Pa; a step's reading: sd %.1f Pa), whole floor %.1f "
      "Pa, rho0 g d %.1f Pa (%+.2f%%, %+.2f%%); walls' load / weight %.4f (%d steps)\n",
      solver, centrePressure(), centreMeanError(), centreStepSpread(), floorPressure(), expected,
      100 * (centrePressure() / expected - 1), 100 * (floorPressure() / expected - 1),
      loadOverWeight(), steps());
  if (!profile) return;
  std::printf(
      "%s p against the weight above: floor layer centre %+.2f%%, rim %+.2f%%; beside the side "
      "walls %+.2f%%, centre columns %+.2f%% (20-80%% of the depth); bottom layer against rho0 g "
      "(d - its height) %+.2f%%; top speed %.4f m/s; top layer %.4f -> %.4f m\n"
      "%s heave: %d of %d steps with the fluid's mean vertical speed over %.3f m/s (largest "
      "%.4f m/s); top speed on the other steps %.4f m/s; over %.3f m/s: %lld particle-steps, "
      "%zu particles\n",
      solver, 100 * pressureError(kFloorLayerCentre), 100 * pressureError(kFloorLayerRim),
      100 * pressureError(kBesideSideWalls), 100 * pressureError(kCentreColumns),
      100 * (bottomLayerPressure() / (expected / depth_ * (depth_ - bottomLayerHeight())) - 1),
      maxSpeed(), firstTopHeight(), lastTopHeight(), solver, heaveSteps(), steps(), kHeave,
      largestHeave(), quietMaxSpeed(), kStill, static_cast<long long>(fastParticleSteps()),
      fastParticles());
}

}  // namespace sph::test
