// The non-pressure forces of a DFSPH step (viscosity, no-slip walls, gravity) as a gather over
// the step's stored pairs (DfsphPairs.h): the same terms as computeForces() (SphPasses.cpp)
// without its pressure terms, which DFSPH's solvers replace.
//
// Built with -ffast-math and scalar loops like Dfsph.cpp (sim/solver/CMakeLists.txt says why);
// each particle sums its own pairs in their stored order, the same whatever the thread count.
#include "sim/solver/DfsphPairs.h"
#include "sim/solver/SphPasses.h"

namespace sph::solver {

namespace {

// Monaghan's form between fluid particles, as the peer (SPlisHSPlasH's "Standard" viscosity)
// writes it: a_i = 10 nu' sum_j m / rho_j (v_ij . x_ij) / (r^2 + 0.01 h^2) gradW_ij, nu' =
// kMonaghanShare nu, plus the Laplacian form's no-slip wall drag. Only a pair's approach or
// separation along x_ij is damped, so shear flows past it, and a still tank's slow creep (the
// packing settling) is damped by a viscosity 2.5 times the automatic one without the friction
// that slows a dam break's front (docs/notes/2026-11-30-dfsph-momentum.md). The record R_j = V_j
// gradW_ij = g (h - r)^2 / r x_ij (DfsphPairs.h) gives x_ij back: v_ij . x_ij = (v_ij . R_j) r /
// (g (h - r)^2), so the pass reads no positions; the factor pass stored each pair's r / ((h -
// r)^2 (r^2 + 0.01 h^2)) as its viscosity weight. `viscScale`, `noSlip` and `g`: the wall drag's
// factors and gravity, as computeDfsphViscosity() has them.
void monaghanViscosity(StepContext& c, const Float4* v, float viscScale, float noSlip, Vec3 g) {
  Particles& f = c.fluid;
  const StepScratch& s = c.scratch;
  const float nu = scene::SolverParams::kMonaghanShare * c.derived.viscosity;
  const float scale = 10.0f * nu * c.solver.restDensity / dfsphGradientScale(c);
  const float* invRho = s.inverseDensity.data();
  forEachParticlePairs(c, [&](std::uint32_t i, const PairSpan& p) {
    const Float4 vi = v[i];
    Float4 a = {0, 0, 0, 0};
    for (std::uint32_t q = 0; q < p.count; ++q) {
      const std::uint32_t j = p.pair[q].index;
      // Lane 0 holds j's bits, a denormal float for j < 2^23: multiplied into the sum it made
      // every pair a slow denormal operation (3x the pass's time on Zen 5). Zero it.
      Float4 record = loadRecord(p.pair[q]);
      record[0] = 0.0f;
      const Float4 t = (vi - v[j]) * record;
      const float approach = (t[1] + t[2] + t[3]) * p.weight[q];
      a += (invRho[j] * approach) * record;
    }
    a *= scale;
    a -= (viscScale * invRho[i] * noSlip * s.wallWeight[i]) * vi;
    f.ax[i] = a[1] + g.x(), f.ay[i] = a[2] + g.y(), f.az[i] = a[3] + g.z();
  });
}

}  // namespace

// a_i = nu (rho0 / rho_i) [sum_j m / rho_j (v_j - v_i) lapW_visc - (no-slip) sum_b m / rho0 v_i
// lapW_visc] + g, computeForces()'s viscosity, wall and gravity terms (Müller 2003), over the
// stored pairs; or Monaghan's form between fluid particles (solver.viscosity_form).
void computeDfsphViscosity(StepContext& c) {
  Particles& f = c.fluid;
  const StepScratch& s = c.scratch;
  const Kernels& kern = c.derived.kernels;
  const float viscScale =
      c.derived.viscosity * c.solver.restDensity * c.derived.mass * kern.viscLapFactor;
  const Vec3 g = c.solver.gravity;
  const float noSlip = c.solver.noSlipWalls ? 1.0f / c.solver.restDensity : 0.0f;
  const Float4* v = packVelocities(c);
  if (c.solver.viscosityForm == scene::ViscosityForm::Monaghan)
    return monaghanViscosity(c, v, viscScale, noSlip, g);
  const float* invRho = s.inverseDensity.data();
  forEachParticlePairs(c, [&](std::uint32_t i, const PairSpan& p) {
    const Float4 vi = v[i];
    Float4 a = {0, 0, 0, 0};
    for (std::uint32_t q = 0; q < p.count; ++q) {
      const std::uint32_t j = p.pair[q].index;
      a += (invRho[j] * p.weight[q]) * (v[j] - vi);
    }
    // No-slip: the viscosity term with the wall at rest (v_b = 0, rho_b = rho0).
    a -= (noSlip * s.wallWeight[i]) * vi;
    const float visc = viscScale * invRho[i];
    f.ax[i] = visc * a[1] + g.x(), f.ay[i] = visc * a[2] + g.y(), f.az[i] = visc * a[3] + g.z();
  });
}

}  // namespace sph::solver
