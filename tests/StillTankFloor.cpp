#include "tests/StillTankFloor.h"

#include <cmath>
#include <cstdio>

#include "sim/Observables.h"

namespace sph::test {

void StillTankFloor::advanceTo(Simulation& sim, double t) {
  const float w = static_cast<float>(width_), below = -1.0f, above = 1e3f;
  // Boundary particles stand at the centres of lattice cells: a box whose sides lie on cell
  // faces holds those of a floor area (its side)^2 (a quarter of a side that is not a whole
  // number of cells would cut through a row of them and count it or not).
  const double margin = std::round(0.25 * width_ / spacing_) * spacing_;
  const double side = std::round((width_ - 2 * margin) / spacing_) * spacing_;
  const float lo = static_cast<float>(margin), hi = static_cast<float>(margin + side);
  const Aabb centre{Vec3(lo, below, lo), Vec3(hi, 0, hi)};
  const Aabb floor{Vec3(0, below, 0), Vec3(w, 0, w)};
  const Aabb all{Vec3::Constant(-above), Vec3::Constant(above)};
  while (sim.time() < t) {
    sim.step(t);
    const Particles& p = sim.fluid();
    const DerivedParams& d = sim.params();
    auto load = [&](const Aabb& sensor) {
      return wallLoad(p, sim.boundary().particles(), sim.boundaryPressureTerm(), sensor, d.mass,
                      d.h, sim.gradientCorrection());
    };
    const double weight =
        static_cast<double>(p.size()) * d.mass * sim.scene().solver.gravity.norm();
    centre_ += -load(centre).y() / (side * side);
    floor_ += -load(floor).y() / (width_ * width_);
    total_ += load(all).dot(sim.scene().solver.gravity.cast<double>()) /
              (weight * sim.scene().solver.gravity.norm());
    const LayerMean bottom = bottomLayer(p, spacing_);
    bottomPressure_ += bottom.pressure;
    bottomHeight_ += bottom.height;
    ++steps_;
  }
}

void StillTankFloor::print(const char* solver, double expected) const {
  std::printf(
      "%s floor sensor: centre %.1f Pa, whole floor %.1f Pa, rho0 g d %.1f Pa (%+.2f%%, %+.2f%%); "
      "walls' load / weight %.4f (%d steps)\n",
      solver, centrePressure(), floorPressure(), expected, 100 * (centrePressure() / expected - 1),
      100 * (floorPressure() / expected - 1), loadOverWeight(), steps());
}

}  // namespace sph::test
