// Divergence-free SPH (Bender & Koschier 2015, "Divergence-free smoothed particle hydrodynamics";
// 2017, "Divergence-free SPH for incompressible and viscous fluids"): the pressure passes of
// solver.pressure = "dfsph". Written from the papers' equations; the notation follows 2017:
//
//   V_j = m / rho0 (every particle, fluid or boundary, has the fluid's mass), s_i = rho_i / rho0,
//   G_i = sum_j V_j gradW_ij over fluid and boundary neighbours,
//   alpha_i = 1 / (|G_i|^2 + sum_{fluid j} |V_j gradW_ij|^2)                        (2017, eq. 9)
//
// A pressure-like stiffness k_i (m^2/s^2) accelerates particle i by
//   a_i = - sum_{fluid j} V_j (k_i + k_j) gradW_ij - sum_{boundary b} V_b (k_i + k_b) gradW_ib
//       = - k_i G_i - sum_{fluid j} V_j k_j gradW_ij - sum_b V_b k_b gradW_ib
// where k_b is the stiffness the wall particle takes from the fluid around it (DfsphWalls.cpp;
// solver.wall_pressure "extrapolated"), or 0 (walls that hold no pressure of their own, as the
// papers' Akinci et al. 2012 boundary particles: "none"), and the rate of change of s_i for
// velocities v is
//   Ds_i/Dt = sum_{fluid j} V_j (v_i - v_j) . gradW_ij + sum_b V_b v_i . gradW_ib
//           = v_i . G_i - sum_{fluid j} V_j v_j . gradW_ij                       (walls at rest).
// So G_i, computed once per step with the factor, carries the boundary: the solver iterations
// loop over fluid neighbours, and over the wall pairs only for k_b.
//
// Divergence-free solver (2017, Algorithm 2): k_i = alpha_i max(Ds_i/Dt, 0) / dt, until the mean
// dt Ds/Dt is at most max_divergence_error. Constant-density solver (Algorithm 3): with the
// predicted s*_i = s_i + dt Ds_i/Dt, k_i = alpha_i max(s*_i - 1, 0) / dt^2, until the mean
// s*_i - 1 is at most max_density_error. Both are Jacobi iterations (every k from the same
// velocities, then every velocity from the same k's) warm-started with a share of the last
// step's sums (jacobiSolve() says why a share); the constant-density solver applies a share of
// each increment (solver.density_relaxation), and past its first iterations turns to a relaxed
// Jacobi with momentum whose increments may take back the step's own (solveDensity() says why).
//
// The neighbours do not move within a step, so computeDfsphDensityAndFactor() (DfsphPairs.cpp)
// stores every fluid pair with its V_j gradW_ij once (StepScratch::pairRows), and each Jacobi
// pass is a gather over that list instead of a neighbour search with the kernel recomputed (half
// the time a pass on the peer's dam break: docs/notes/2026-11-25-dfsph-against-wcsph.md, "The
// peer's dam break: time to solution, and the Jacobi passes over stored pairs").
//
// Built with -ffast-math like SphPasses.cpp but without the vectoriser (sim/solver/CMakeLists.txt
// says why), under the same rules: every per-particle computation runs in a loop over rows of
// cells (the same split whatever the thread count) and sums its pairs in their stored order, and
// the error means are exact sums.
//
// On K processes (docs/scaling.md) the fluid holds this rank's particles and two cell planes of
// ghosts beyond each face of its slab, so the pairs of the first plane's ghosts are complete and
// their factors, sources and stiffnesses are the single process's. A velocity pass leaves the
// ghosts' velocities stale (the second plane's read stiffnesses beyond it): their owners send
// them again before every source pass (ranks::Halo::refreshGhosts). The warm start travels with
// its particles and ghosts (Halo::attach), and every decision (the warm start, when to stop) is
// taken from global sums, exact, so every rank iterates as the single process does.
#include <algorithm>
#include <array>
#include <cmath>

#include "sim/solver/DfsphPairs.h"
#include "sim/solver/DfsphWalls.h"
#include "sim/solver/SphPasses.h"
#include "sim/ranks/ExactSum.h"
#include "sim/ranks/Halo.h"

namespace sph::solver {
namespace {

bool wallsHoldPressure(const StepContext& c) {
  return c.solver.wallPressure == scene::WallPressure::Extrapolated;
}

bool owned(const StepContext& c, std::size_t i) {
  return !c.ghost || !(*c.ghost)[i];
}

// The mean of `v` over the fluid (every rank's owned particles): an exact sum, rounded once, so
// the same double whatever the split of the particles between threads and ranks.
double meanOverFluid(const StepContext& c, const std::vector<float>& v) {
  const std::size_t n = c.fluid.size();
  const std::uint8_t* ghost = c.ghost ? c.ghost->data() : nullptr;
  ranks::ExactSum sum;
  sum.addAll(v.data(), n, ghost);
  auto count = static_cast<std::int64_t>(ghost ? std::count(ghost, ghost + n, 0) : n);
  if (c.ranks) ranks::sumOverRanks(*c.ranks, sum, count);
  return count > 0 ? sum.toDouble() / static_cast<double>(count) : 0.0;
}

// True if any particle of the fluid (on any rank) has a non-zero warm start.
bool anyWarm(const StepContext& c, const std::vector<float>& warm) {
  std::int64_t warmed = 0;
  for (std::size_t i = 0; i < warm.size(); ++i) {
    if (owned(c, i) && warm[i] != 0.0f) {
      warmed = 1;
      break;
    }
  }
  if (!c.ranks) return warmed != 0;
  std::vector<std::int64_t> any{warmed};
  c.ranks->sumInPlace(any);
  return any[0] > 0;
}

// True if most of the fluid (on every rank) moves slower than `speed` (m/s).
bool mostlySlow(const StepContext& c, float speed) {
  const Particles& f = c.fluid;
  const float limit = speed * speed;
  std::int64_t slow = 0, count = 0;  // integer sums: the same whatever the split between threads
#pragma omp parallel for reduction(+ : slow, count) schedule(static)
  for (long long i = 0; i < static_cast<long long>(f.size()); ++i) {
    if (!owned(c, static_cast<std::size_t>(i))) continue;
    const float v2 = f.vx[i] * f.vx[i] + f.vy[i] * f.vy[i] + f.vz[i] * f.vz[i];
    slow += v2 < limit ? 1 : 0;
    ++count;
  }
  if (c.ranks) {
    std::vector<std::int64_t> both{slow, count};
    c.ranks->sumInPlace(both);
    slow = both[0], count = both[1];
  }
  return 2 * slow > count;
}

// The constant-density solver's warm start share for this step. The part of the weight it leaves
// out must compress the fluid past the stopping threshold within the step for the iterations to
// see a column at rest at all: (1 - share) g dt^2 / dx > max_density_error. Where it does not,
// each step stops at its first iteration, a push the warm start carries on is repeated at its
// share, and the column heaves as a whole, which compresses only the layer at the floor and so
// stays under the mean threshold (the accurate preset's 0.8 heaved the tests' still tank at steps
// of 1.5 ms). So for water mostly at rest (slower than 0.1 m/s: a heave's cm/s, not a flow's) the
// share is held clear of that edge: twice for the projected solve (1.5 times let a tank at twice
// the viscosity heave; three times moved the 117k dam break, whose step falls that short while
// most of its column is still at rest), three times for the papers' increments, which cannot take
// a step's warm start back within the step (twice let the default's 0.5 heave at 1.2-1.6 ms). Not
// for a flow: the peer's dam break's steps are as short against gravity's bound, but its flow
// compresses what gravity does not, and the same bound there cost it 16% of its time; with the
// rest condition every dam break measured is bit for bit the same
// (docs/notes/2026-12-01-still-tank-limits.md).
float densityWarmShare(const StepContext& c) {
  const float share = c.solver.densityWarmStart;
  const float gravity = c.solver.gravity.norm();
  if (share <= 0 || gravity <= 0) return share;
  constexpr float kRestSpeed = 0.1f;
  const float clearance = c.solver.densitySolve == scene::DensitySolve::Projected ? 2.0f : 3.0f;
  const float seen =
      clearance * c.solver.maxDensityError * 0.01f * c.solver.spacing / (gravity * c.dt * c.dt);
  const float open = std::max(0.0f, 1.0f - seen);
  if (open >= share || !mostlySlow(c, kRestSpeed)) return share;
  return open;
}

// One source pass: for every particle the rate Ds_i/Dt of the current velocities (1/s), turned
// by `source(i, rate)` into the solver's source term and stiffness.
template <class Source>
void sourcePass(StepContext& c, Source&& source) {
  Particles& f = c.fluid;
  const StepScratch& s = c.scratch;
  const Float4* v = packVelocities(c);
  forEachParticlePairs(c, [&](std::uint32_t i, const PairSpan& p) {
    const Float4 sum = weightedPairSum(p, [v](std::uint32_t j) { return v[j]; });
    const float rate = f.vx[i] * s.gradientSumX[i] + f.vy[i] * s.gradientSumY[i] +
                       f.vz[i] * s.gradientSumZ[i] - (sum[1] + sum[2] + sum[3]);
    source(i, rate);
  });
}

// One velocity pass: v_i -= dt (k_i G_i + sum_j V_j k_j gradW_ij), the stiffness of the last
// source pass, and with walls that hold pressure, - dt sum_b V_b k_b gradW_ib for the change of
// the wall's stiffness (DfsphWalls.cpp); adds k_i to `warm` (and, with `acceleration`, the
// pressure acceleration to a).
void velocityPass(StepContext& c, std::vector<float>& warm, bool acceleration) {
  Particles& f = c.fluid;
  const StepScratch& s = c.scratch;
  const float* k = s.stiffness.data();
  const float dt = c.dt;
  auto apply = [&](std::uint32_t i, Float4 a) {  // a: sum_j V_j k_j gradW_ij in lanes 1-3
    const float ki = k[i];
    const float px = -(ki * s.gradientSumX[i] + a[1]);
    const float py = -(ki * s.gradientSumY[i] + a[2]);
    const float pz = -(ki * s.gradientSumZ[i] + a[3]);
    f.vx[i] += dt * px, f.vy[i] += dt * py, f.vz[i] += dt * pz;
    if (acceleration) f.ax[i] += px, f.ay[i] += py, f.az[i] += pz;
    warm[i] += ki;
  };
  auto fluidStiffness = [k](std::uint32_t j) { return k[j]; };
  if (!wallsHoldPressure(c)) {
    forEachParticlePairs(c, [&](std::uint32_t i, const PairSpan& p) {
      apply(i, weightedPairSum(p, fluidStiffness));
    });
    return;
  }
  const float* kb = c.walls.change.data();
  forEachParticlePairsAndWalls(c, [&](std::uint32_t i, const PairSpan& p, const PairSpan& w) {
    apply(i, weightedPairSum(p, fluidStiffness) +
                 weightedPairSum(w, [kb](std::uint32_t b) { return kb[b]; }));
  });
}

// The wall particles' stiffness for the iteration about to move the velocities (DfsphWalls.cpp).
void changeWalls(StepContext& c, std::vector<float>& warm, bool hydrostatic) {
  if (!wallsHoldPressure(c)) return;
  // The ghosts' stiffness as their owners have it (a wall particle reaches 2h into the ghosts).
  if (c.halo) c.halo->refreshGhosts({&warm, &c.scratch.stiffness});
  changeWallStiffness(c, warm, c.scratch.stiffness, hydrostatic);
}

// A Jacobi solve: warm start from `warm` (which then collects this step's sum), then iterations
// of source and velocity passes until `error()` (a fraction) is at most `tolerance` after at
// least `minIterations`, or `maxIterations`. The warm start is `warmShare` of the last sum, and
// stays in scratch.solveStart. `rate(i, rate, iteration)` sets source[i] and stiffness[i] (which
// holds the last iteration's until then). Returns the iterations and the error reached.
template <class Rate>
std::pair<int, double> jacobiSolve(StepContext& c, std::vector<float>& warm, float warmShare,
                                   double tolerance, int minIterations, int maxIterations,
                                   bool acceleration, Rate&& rate) {
  // The density solver is the one that holds the fluid up: the walls' hydrostatic term is its.
  const bool hydrostatic = acceleration;
  if (wallsHoldPressure(c)) startWallSolve(c);
  const std::size_t n = c.fluid.size();
  StepScratch& s = c.scratch;
  s.source.resize(n);
  s.stiffness.resize(n);
  warm.resize(n, 0.0f);  // new particles start from 0
  if (anyWarm(c, warm)) {
    // A share of the last step's sum, not all of it: every iteration adds a non-negative
    // stiffness (only compression is corrected), so a start from the whole sum could only grow
    // from step to step, never relax. The share left out is what the iterations rebuild.
    std::transform(warm.begin(), warm.end(), s.stiffness.begin(),
                   [warmShare](float k) { return warmShare * k; });
    std::fill(warm.begin(), warm.end(), 0.0f);
    changeWalls(c, warm, hydrostatic);
    velocityPass(c, warm, acceleration);
  } else {
    std::fill(warm.begin(), warm.end(), 0.0f);
  }
  s.solveStart.assign(warm.begin(), warm.end());
  int iterations = 0;
  double error = 0;
  while (true) {
    // The ghosts' velocities as their owners have them now (distributed runs).
    if (c.halo) c.halo->refreshGhosts({&c.fluid.vx, &c.fluid.vy, &c.fluid.vz});
    sourcePass(c, [&](std::uint32_t i, float r) { rate(i, r, iterations); });
    error = meanOverFluid(c, s.source);
    if ((error <= tolerance && iterations >= minIterations) || iterations >= maxIterations) break;
    changeWalls(c, warm, hydrostatic);
    velocityPass(c, warm, acceleration);
    ++iterations;
  }
  if (wallsHoldPressure(c)) finishWallSolve(c);
  return {iterations, error};
}

}  // namespace

// Divergence-free solver: makes Ds/Dt = 0 for the velocities at the start of the step (2017,
// Algorithm 2; the papers run it at the end of a step, on the same positions and velocities).
void solveDivergence(StepContext& c) {
  StepScratch& s = c.scratch;
  const float invDt = 1.0f / c.dt, dt = c.dt;
  const auto [iterations, error] =
      jacobiSolve(c, c.warmStart.divergence, 0.5f, c.solver.maxDivergenceError * 0.01,
                  c.solver.minDivergenceIterations, c.solver.maxDivergenceIterations, false,
                  [&](std::uint32_t i, float rate, int) {
                    const float r = std::max(rate, 0.0f);
                    s.source[i] = dt * r;
                    s.stiffness[i] = s.factor[i] * r * invDt;
                  });
  c.solveStats.divergenceIterations = iterations;
  c.solveStats.divergenceError = static_cast<float>(100 * error);
  c.solveStats.totalDivergenceIterations += static_cast<std::uint64_t>(iterations);
}

// Constant-density solver on the velocities after the non-pressure forces (2017, Algorithm 3);
// the pressure acceleration is added to a, and for output p_i, the pressure that gives the same
// force in the WCSPH formula as both solvers' stiffness of this step.
//
// Its first density_momentum_after iterations are the papers' (at density_relaxation 1, bit for
// bit): each increment alpha_i max(e_i, 0) / dt^2, never negative, so an increment that
// overshoots stays. A flow that moves is held within 2-4 of them. Water at rest is not: the warm
// start leaves part of the column's weight to rebuild, the overshoot of a long solve throws the
// column up, the next step finds nothing compressed and holds only its warm start, and a still
// tank heaves (the whole fluid falling and thrown back at cm/s). So a step that needs more
// iterations goes on with increments of either sign, which may take back what this step's
// iterations added but not the warm start. At the full share those diverge (Jacobi's iteration
// on this system has modes past -1: the tests' still tank blew up at its second step), at half
// the share they converge but slowly (66 iterations a step), and a momentum of the last
// increment wins that back: a second-order Richardson iteration (Frankel 1950),
//   k_i = 0.7 alpha_i e_i / dt^2 + 0.5 k_i(last iteration),   sum of this step's k_i >= 0.
// The tests' still tank over 3-10 s then has no heave and takes 25.6 iterations a step against
// the papers' 31.6 (heave in 96 of 2437 steps), and none either with steps bound to 2 ms (the
// papers': 850 of 3500). Shares 0.5 and 0.8 took 19 iterations at gravity's step but let the
// 2 ms tank heave (docs/notes/2026-11-30-dfsph-momentum.md). The mean error that stops the solve
// is the papers' in every iteration, over compressed particles only.
//
// The increments that only add keep the warm start wherever the flow no longer needs it (a sheet
// leaving a wall), so a fuller warm start, which saves the iterations a longer step needs, pushes
// the water: at 0.8 the 117k-particle dam break ran its front 10% ahead or blew up. With
// solver.density_solve "projected" every iteration is the momentum form at half the share,
//   k_i = 0.5 alpha_i e_i / dt^2 + 0.5 k_i(last iteration),   this step's whole sum >= 0,
// a projected Jacobi on the whole stiffness, which may take the warm start back (as the peer's
// solve may: SPlisHSPlasH's TimeStepDFSPH.cpp, at a share of 0.5). At 0.7 the still tank stirred
// at 14 cm/s, at 0.9 the dam break blew up; without the momentum it took 7.7 iterations a step
// where it takes 4.5 (docs/notes/2026-11-30-dfsph-larger-steps.md).
void solveDensity(StepContext& c) {
  Particles& f = c.fluid;
  StepScratch& s = c.scratch;
  const float rho0 = c.solver.restDensity;
  constexpr float kMomentumShare = 0.7f, kMomentum = 0.5f, kProjectedShare = 0.5f;
  const bool projected = c.solver.densitySolve == scene::DensitySolve::Projected;
  // The first iteration of the momentum form: the projected solve's from the start.
  const int plainIterations = projected ? 0 : c.solver.densityMomentumAfter;
  // Each plain increment is the relaxation's share of the particle's full correction (at 1, the
  // papers'). Half of it also damps the overshoot, as IISPH's relaxed Jacobi does, for more
  // iterations; what it costs a dam break: docs/scene-format.md.
  const float invRho0 = 1.0f / rho0, dt = c.dt, invDt2 = 1.0f / (c.dt * c.dt),
              relaxedInvDt2 = c.solver.densityRelaxation * invDt2,
              momentumInvDt2 = (projected ? kProjectedShare : kMomentumShare) * invDt2;
  const std::vector<float>& sum = c.warmStart.density;
  const auto [iterations, error] = jacobiSolve(
      c, c.warmStart.density, densityWarmShare(c), c.solver.maxDensityError * 0.01,
      c.solver.minDensityIterations, c.solver.maxDensityIterations, true,
      [&](std::uint32_t i, float rate, int iteration) {
        const float e = f.rho[i] * invRho0 + dt * rate - 1.0f;
        const float compression = std::max(e, 0.0f);
        s.source[i] = compression;
        if (iteration < plainIterations) {
          s.stiffness[i] = s.factor[i] * compression * relaxedInvDt2;
          return;
        }
        const float momentum = iteration > plainIterations ? kMomentum * s.stiffness[i] : 0.0f;
        // What the iteration may take back: this step's iterations so far, or all of it.
        const float added = projected ? sum[i] : sum[i] - s.solveStart[i];
        s.stiffness[i] = std::max(s.factor[i] * e * momentumInvDt2 + momentum, -added);
      });
  c.solveStats.densityIterations = iterations;
  c.solveStats.densityError = static_cast<float>(100 * error);
  c.solveStats.totalDensityIterations += static_cast<std::uint64_t>(iterations);
  c.solveStats.steps += 1;
  // The WCSPH force is c sum m (p_i/rho_i^2 + p_j/rho_j^2) gradW_spiky (c the gradient
  // correction of the particles' arrangement this step, computeDfsphDensityAndFactor()); DFSPH's
  // is sum (m/rho0) n (k_i + k_j) gradW_spiky (n the density normalisation): the same force for
  // p_i = rho_i^2 / rho0 (n / c) k_i. k_i is all this step applied: the divergence solver's sum
  // with the constant-density solver's (each warm start included). With solver.wall_pressure
  // "none" p_i is not the physical pressure near a wall: the walls push with k_i alone, as if
  // they held none (DfsphWalls.cpp).
  const float scale = invRho0 * c.derived.densityNormalisation / c.gradientCorrection;
  const std::vector<float>& k = c.warmStart.density;
  const std::vector<float>& kv = c.warmStart.divergence;
  for (std::size_t i = 0; i < f.size(); ++i) f.p[i] = f.rho[i] * f.rho[i] * scale * (k[i] + kv[i]);
  if (wallsHoldPressure(c)) storeWallPressure(c);
}

}  // namespace sph::solver
