// The floor of the narrowed still tank (tests/test_still_tank.cpp, test_dfsph.cpp) read as a
// pressure sensor would read it, the same way for both pressure solvers: the force the fluid's
// pressure pairs put on the floor's boundary particles (wallLoad(), sim/Observables.h) over the
// area they stand for, sampled after every step and averaged (DFSPH's stiffness alternates from
// one step to the next, and frames a fixed number of steps apart would see one phase only).
#pragma once

#include "sim/Simulation.h"

namespace sph::test {

class StillTankFloor {
 public:
  // A tank `width` (m) square whose floor is the plane y = 0, its boundary particles at the
  // centres of a lattice of `spacing` (m) from the tank's corner at the origin.
  StillTankFloor(double width, double spacing) : width_(width), spacing_(spacing) {}

  // Steps `sim` to time `t` (s) as advanceTo() does, reading the floor after every step.
  void advanceTo(Simulation& sim, double t);

  // Mean downward force over area (Pa) on the centre of the floor (the middle half of each side,
  // to whole lattice cells, away from the side walls), and on all of the floor under the water.
  double centrePressure() const { return centre_ / steps_; }
  double floorPressure() const { return floor_ / steps_; }
  // Mean upward force of every boundary particle on the fluid over the fluid's weight: 1 for a
  // fluid at rest whose p is the pressure its solver applied.
  double loadOverWeight() const { return total_ / steps_; }
  // The fluid's bottom layer (the particles below one spacing above the floor), every step: its
  // mean pressure p (Pa) and its particles' mean height (m).
  double bottomLayerPressure() const { return bottomPressure_ / steps_; }
  double bottomLayerHeight() const { return bottomHeight_ / steps_; }
  int steps() const { return steps_; }
  // One line: the readings against the floor's `expected` pressure (Pa), named `solver`.
  void print(const char* solver, double expected) const;

 private:
  double width_, spacing_;
  double centre_ = 0, floor_ = 0, total_ = 0, bottomPressure_ = 0, bottomHeight_ = 0;
  int steps_ = 0;
};

}  // namespace sph::test
