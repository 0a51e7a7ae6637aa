// The equation of state pass (DESIGN.md, "Pressure"): fluid and boundary particles. Kept apart
// from the neighbour passes because it is an element-wise loop and must not be built with
// -ffast-math (see SphPasses.cpp).
#include <algorithm>

#include "sim/Parallel.h"
#include "sim/solver/SphPasses.h"

namespace sph::solver {
namespace {

// Equation of state (DESIGN.md): Tait p = B((rho/rho0)^7 - 1) or linear p = k(rho - rho0),
// clamped at 0 unless the scene allows tension.
struct Eos {
  float rho0, k;
  bool tait, clamp;
  float operator()(float rho) const {
    float p;
    if (tait) {
      const float r = rho / rho0, r2 = r * r, r3 = r2 * r;
      p = k * (r3 * r3 * r - 1.0f);
    } else {
      p = k * (rho - rho0);
    }
    return clamp ? std::max(p, 0.0f) : p;
  }
};

Eos eosOf(const StepContext& c) {
  return {c.solver.restDensity, c.derived.stiffness, c.solver.eos == scene::EquationOfState::Tait,
          c.solver.clampNegativePressure};
}

}  // namespace

float equationOfState(const StepContext& c, float rho) {
  return eosOf(c)(rho);
}

// Equation of state for fluid and boundary particles; also caches p / rho^2 and 1 / rho, the
// per-neighbour factors of the force pass, so that pass does no division per pair.
void computePressure(StepContext& c) {
  Particles& f = c.fluid;
  const std::size_t n = f.size();
  std::vector<float>& pressureTerm = c.scratch.pressureTerm;
  std::vector<float>& inverseDensity = c.scratch.inverseDensity;
  BoundaryFields& bf = c.boundaryFields;
  pressureTerm.resize(n);
  inverseDensity.resize(n);
  const Eos eos = eosOf(c);
  parallelFor(n, [&](std::size_t i) {
    const float p = eos(f.rho[i]);
    const float inv = 1.0f / f.rho[i];
    f.p[i] = p;
    inverseDensity[i] = inv;
    pressureTerm[i] = p * inv * inv;
  });
  // Walls that hold the extrapolated pressure compute theirs with their density
  // (correctWallPressure()).
  if (c.solver.wallPressure == scene::WallPressure::Extrapolated) return;
  parallelFor(bf.density.size(), [&](std::size_t q) {
    const float rho = bf.density[q];
    bf.pressureTerm[q] = rho > 0 ? eos(rho) / (rho * rho) : 0.0f;
  });
}

}  // namespace sph::solver
