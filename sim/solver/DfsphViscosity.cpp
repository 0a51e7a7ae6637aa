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
  const float* vx = f.vx.data();
  const float* vy = f.vy.data();
  const float* vz = f.vz.data();
  const float* invRho = s.inverseDensity.data();
  forEachParticlePairs(c, [&](std::uint32_t i, const PairSpan& p) {
    const float vxi = vx[i], vyi = vy[i], vzi = vz[i];
    float ax = 0, ay = 0, az = 0;
    for (std::uint32_t q = 0; q < p.count; ++q) {
      const std::uint32_t j = p.index[q];
      const float w = invRho[j] * p.hr[q];
      ax += w * (vx[j] - vxi), ay += w * (vy[j] - vyi), az += w * (vz[j] - vzi);
    }
    // No-slip: the viscosity term with the wall at rest (v_b = 0, rho_b = rho0).
    const float drag = noSlip * s.wallWeight[i];
    ax -= drag * vxi, ay -= drag * vyi, az -= drag * vzi;
    const float visc = viscScale * invRho[i];
    f.ax[i] = visc * ax + g.x(), f.ay[i] = visc * ay + g.y(), f.az[i] = visc * az + g.z();
  });
}

}  // namespace sph::solver
