// The floor of the narrowed still tank (tests/test_still_tank.cpp, test_dfsph.cpp) read as a
// pressure sensor would read it, the same way for both pressure solvers: the force the fluid's
// pressure pairs put on the floor's boundary particles (wallLoad(), sim/run/Observables.h) over the
// area they stand for, sampled after every step and averaged (DFSPH's stiffness alternates from
// one step to the next, and frames a fixed number of steps apart would see one phase only).
#pragma once

#include <cstdint>
#include <set>
#include <vector>

#include "sim/run/Simulation.h"

namespace sph::test {

class StillTankFloor {
 public:
  // A tank `width` (m) square whose floor is the plane y = 0, its boundary particles at the
  // centres of a lattice of `spacing` (m) from the tank's corner at the origin.
  StillTankFloor(double width, double spacing) : width_(width), spacing_(spacing) {}

  // Steps `sim` to time `t` (s) as advanceTo() does, reading the floor after every step.
  void advanceTo(run::Simulation& sim, double t);

  // Mean downward force over area (Pa) on the centre of the floor (the middle half of each side,
  // to whole lattice cells, away from the side walls), and on all of the floor (the side walls'
  // feet included) over the area under the water.
  double centrePressure() const { return centre_ / steps_; }
  // How far the centre's reading strays (Pa): the standard deviation of one step's reading
  // (DFSPH's stiffness alternates from step to step), and the standard error of the mean, from
  // the spread of the means of blocks of 10 steps (consecutive steps are not independent).
  double centreStepSpread() const;
  double centreMeanError() const;
  double floorPressure() const { return floor_ / steps_; }
  // Mean upward force of every boundary particle on the fluid over the fluid's weight: 1 for a
  // fluid at rest whose p is the pressure its solver applied.
  double loadOverWeight() const { return total_ / steps_; }
  // The fluid's bottom layer (the particles below one spacing above the floor), every step: its
  // mean pressure p (Pa) and its particles' mean height (m).
  double bottomLayerPressure() const { return bottomPressure_ / steps_; }
  double bottomLayerHeight() const { return bottomHeight_ / steps_; }
  int steps() const { return steps_; }
  // The fluid's p against the hydrostatic pressure, the weight of the water above each particle
  // over the tank's area, by region, every step: sum p / sum hydrostatic - 1 over the particles of
  // the region. The floor's layer (below one spacing above the floor) in the middle half of
  // each side and along the walls; the water beside the side walls (within 1.5 spacings of one)
  // and the centre columns (the middle half of each side), both at 20-80% of the depth.
  enum Region { kFloorLayerCentre, kFloorLayerRim, kBesideSideWalls, kCentreColumns, kRegions };
  double pressureError(Region r) const {
    return expected_[r] > 0 ? pressure_[r] / expected_[r] - 1 : 0;
  }
  // The largest speed of any particle over the reading (m/s), and the mean height of the top
  // layer (the particles within one spacing of the highest) at the first and the last step (m).
  double maxSpeed() const { return maxSpeed_; }
  // The whole fluid rising or falling together: the steps whose mean vertical velocity is over
  // kHeave (m/s) in size, the largest such mean, and the largest speed of any particle on the
  // other steps (what moves when the tank does not heave).
  static constexpr double kHeave = 0.005;
  int heaveSteps() const { return heaveSteps_; }
  double largestHeave() const { return largestHeave_; }
  double quietMaxSpeed() const { return quietMaxSpeed_; }
  // How much moves faster than kStill (m/s): the particle-steps over it, and the particles that
  // ever were (a single fast particle is the top speed; these say whether it is one or many).
  static constexpr double kStill = 0.01;
  std::int64_t fastParticleSteps() const { return fastParticleSteps_; }
  std::size_t fastParticles() const { return fastIds_.size(); }
  double firstTopHeight() const { return firstTop_; }
  double lastTopHeight() const { return lastTop_; }
  // One line: the readings against the floor's `expected` pressure (Pa), named `solver`; and
  // with `profile`, a second with the pressure by region, the top speed and the height.
  void print(const char* solver, double expected, bool profile = false) const;

 private:
  void readProfile(const Particles& p, double mass, double g);

  double width_, spacing_;
  double centre_ = 0, floor_ = 0, total_ = 0, bottomPressure_ = 0, bottomHeight_ = 0;
  double pressure_[kRegions] = {}, expected_[kRegions] = {};
  double maxSpeed_ = 0, firstTop_ = 0, lastTop_ = 0, depth_ = 0;
  double largestHeave_ = 0, quietMaxSpeed_ = 0;
  int steps_ = 0, heaveSteps_ = 0;
  std::int64_t fastParticleSteps_ = 0;
  std::set<std::uint32_t> fastIds_;
  std::vector<double> centreReadings_;  // every step's
  std::vector<std::uint32_t> order_;  // the fluid by height, highest first (readProfile())
};

}  // namespace sph::test
