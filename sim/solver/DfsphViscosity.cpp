// The non-pressure forces of a DFSPH step (viscosity, no-slip walls, gravity) as a gather over
// the step's stored pairs (DfsphPairs.h): the same terms as computeForces() (SphPasses.cpp)
// without its pressure terms, which DFSPH's solvers replace.
//
// Built with -ffast-math and scalar loops like Dfsph.cpp (sim/solver/CMakeLists.txt says why);
// each particle sums its own pairs in their stored order, the same whatever the thread count.
#include "sim/solver/DfsphPairs.h"
#include "sim/solver/SphPasses.h"

namespace sph::solver {

// a_i = nu (rho0 / rho_i) [sum_j m / rho_j (v_j - v_i) lapW_visc - (no-slip) sum_b m / rho0 v_i
// lapW_visc] + g, computeForces()'s viscosity, wall and gravity terms (Müller 2003), over the
// stored pairs.
void computeDfsphViscosity(StepContext& c) {
  Particles& f = c.fluid;
  const StepScratch& s = c.scratch;
  const Kernels& kern = c.derived.kernels;
  const float viscScale =
      c.derived.viscosity * c.solver.restDensity * c.derived.mass * kern.viscLapFactor;
  const Vec3 g = c.solver.gravity;
  const float noSlip = c.solver.noSlipWalls ? 1.0f / c.solver.restDensity : 0.0f;
  const Float4* v = packVelocities(c);
  const float* invRho = s.inverseDensity.data();
  forEachParticlePairs(c, [&](std::uint32_t i, const PairSpan& p) {
    const Float4 vi = v[i];
    Float4 a = {0, 0, 0, 0};
    for (std::uint32_t q = 0; q < p.count; ++q) {
      const std::uint32_t j = p.pair[q].index;
      a += (invRho[j] * p.hr[q]) * (v[j] - vi);
    }
    // No-slip: the viscosity term with the wall at rest (v_b = 0, rho_b = rho0).
    a -= (noSlip * s.wallWeight[i]) * vi;
    const float visc = viscScale * invRho[i];
    f.ax[i] = visc * a[1] + g.x(), f.ay[i] = visc * a[2] + g.y(), f.az[i] = visc * a[3] + g.z();
  });
}

}  // namespace sph::solver
