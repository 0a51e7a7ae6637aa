#include "sim/MemoryEstimate.h"

#include <algorithm>
#include <cmath>

#include "sim/Boundary.h"
#include "sim/Kernels.h"
#include "sim/SceneSetup.h"

namespace sph {
namespace {

// Resident bytes of a run, fitted to the peak resident memory of real runs on llvmpipe's machine
// (tests/test_memory_estimate.cpp keeps them within 20%): the dam break at spacings 2.5, 1.8,
// 1.4, 0.6 and 0.3 mm (34, 64, 110 MB, 1.1 and 7.8 GB: 1.6e5 to 9.2e7 fluid particles), the pour
// without and with pictures (15 and 114 MB) and cdt_rain with cdt-gl (123 MB). A fluid particle is
// 13 arrays of 4 bytes (Particles), 5 of per-step scratch (sort order, p/rho^2, 1/rho, gradient
// moment) and its grid slot; a boundary particle (counted as sampled, before those out of reach are
// dropped) its position, three per-step fields and its grid slot.
constexpr double kBytesPerFluidParticle = 76;
constexpr double kBytesPerBoundaryParticle = 50;
// DFSPH's on top (sim/Dfsph.cpp, solver.pressure "dfsph"): every fluid pair of the step stored
// with its V gradW and h - r (20 bytes; ~33 neighbours at support 2 spacings), in rows whose room
// grows to twice what a row once needed, and 9 more per-particle arrays (G, alpha, source,
// stiffness, the two warm starts, the wall weight). Fitted, as above, to the dam break's peak
// resident memory at spacings 3, 2.5, 1.8 and 1.4 mm (9.0e4 to 8.9e5 fluid particles: 102, 148,
// 291 and 835 MB, 2026-11-26, pairs of 16 bytes): the rows' doubling put 540-810 bytes a particle
// on top of WCSPH's at those sizes; the 4 bytes of h - r a pair (sim/DfsphPairs.cpp) added 172
// and 123 bytes a particle at 2.5 and 1.8 mm (peak 148 -> 174-179 MB and 291 -> 343-351 MB, same
// day): 760 puts the estimate at 0.87x and 1.10x of those peaks.
constexpr double kDfsphBytesPerFluidParticle = 760;
// A rain drop (sim/rain/RainSystem.h: position, respawn count, streak layer) and its copy for the
// cache's /Rain#N: 28.7 bytes a drop measured (peak resident memory of 10^7 drops, 307 MB against
// 20 MB for one drop, 2026-11-26, no render section).
constexpr double kBytesPerRainDrop = 30;
// What drawing them adds (render/rain/StreakRaster: a copy of position and layer, 13 B, and at
// least 4 B of band bins a drop) and feeding the fluid (sim/rain/RainFeed: 13 B a drop), counted
// from the arrays rather than measured.
constexpr double kBytesPerDrawnRainDrop = 17;
constexpr double kBytesPerFeedingRainDrop = 13;
// The program itself: code, libraries (HDF5, OpenMP, the C++ runtime), thread stacks.
constexpr double kBaseBytes = 15e6;
// An OpenGL context on Mesa's llvmpipe with the renderer's or cdt-gl's buffers and shaders.
constexpr double kGlBytes = 100e6;

}  // namespace

MemoryEstimate estimateMemory(const Scene& scene) {
  MemoryEstimate m;
  // The counts the id limit uses too (sim/SceneSetup.h): an upper bound from the description.
  const ParticleBudget budget = particleBudget(scene);
  m.fluidParticles = static_cast<double>(budget.blocks);
  double largestEmitter = 0;
  std::size_t largest = 0;
  for (std::size_t k = 0; k < budget.emitters.size(); ++k) {
    const double n = static_cast<double>(budget.emitters[k]);
    m.emittedParticles += n;
    if (n > largestEmitter) largestEmitter = n, largest = k;
  }
  m.rainParticles = static_cast<double>(budget.rain);
  const int layers = scene.solver.boundaryLayers > 0
                         ? scene.solver.boundaryLayers
                         : std::max(1, static_cast<int>(std::ceil(scene.solver.support)));
  for (const BoundaryShape& b : scene.boundaries)
    m.boundaryParticles += countBoundarySamples(b, scene.domain, scene.solver.spacing, layers);
  const bool gl =
      scene.render || (scene.collision && scene.collision->method == CollisionMethod::CdtGl);
  const bool dfsph =
      scene.solver.model == SolverModel::Sph && scene.solver.pressure == PressureSolver::Dfsph;
  const double perFluidParticle =
      kBytesPerFluidParticle + (dfsph ? kDfsphBytesPerFluidParticle : 0);
  double perDrop = kBytesPerRainDrop;
  if (scene.rain) {
    m.rainDrops = static_cast<double>(scene.rain->count);
    if (scene.render) perDrop += kBytesPerDrawnRainDrop;
    if (scene.rain->feedFluid) perDrop += kBytesPerFeedingRainDrop;
  }
  const double fluidBytes =
      perFluidParticle * (m.fluidParticles + m.emittedParticles + m.rainParticles);
  const double boundaryBytes = kBytesPerBoundaryParticle * m.boundaryParticles;
  const double rainBytes = perDrop * m.rainDrops;
  m.bytes = kBaseBytes + (gl ? kGlBytes : 0) + fluidBytes + boundaryBytes + rainBytes;
  // The key to change: the rain's budget or an emitter's size when it is most of the memory,
  // else the spacing.
  if (rainBytes > fluidBytes + boundaryBytes)
    m.largestKey = "rain.count";
  else if (m.rainParticles > std::max(largestEmitter, m.fluidParticles + m.boundaryParticles))
    m.largestKey = "rain.drop_volume";
  else if (largestEmitter > m.fluidParticles + m.boundaryParticles)
    m.largestKey = "emitters[" + std::to_string(largest) + "].radius";
  return m;
}

}  // namespace sph
