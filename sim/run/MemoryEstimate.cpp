#include "sim/run/MemoryEstimate.h"

#include <algorithm>
#include <cmath>

#include "sim/solver/Boundary.h"
#include "sim/solver/Kernels.h"
#include "sim/grid/PairStore.h"
#include "sim/Parallel.h"
#include "sim/solver/SceneSetup.h"

namespace sph::run {
namespace {

// Resident bytes of a run, fitted to the peak resident memory of real runs on llvmpipe's machine
// (tests/test_memory_estimate.cpp keeps them within 20%): the dam break at spacings 2.5, 1.8,
// 1.4, 0.6 and 0.3 mm (34, 64, 110 MB, 1.1 and 7.8 GB: 1.6e5 to 9.2e7 fluid particles), the pour
// without and with pictures (15 and 114 MB) and cdt_rain with cdt-gl (123 MB). A fluid particle is
// 13 arrays of 4 bytes (Particles), 5 of per-step scratch (sort order, p/rho^2, 1/rho, gradient
// moment) and its grid slot; a boundary particle (counted as sampled, before those out of reach are
// dropped) its position, three per-step fields and its grid slot. WCSPH's walls that hold pressure
// (sim/solver/WcsphWalls.cpp) add a share per fluid particle and a residual and a reach per
// boundary particle, counted from the arrays: 4 and 8 bytes on the fitted 76 and 50.
constexpr double kBytesPerFluidParticle = 80;
constexpr double kBytesPerBoundaryParticle = 58;
// DFSPH's on top (sim/solver/Dfsph.cpp, solver.pressure "dfsph"): 9 per-particle arrays (G, alpha,
// source, stiffness, the two warm starts, the wall weight, the pair count, 1/rho) and the packed
// velocity (16 bytes), and every fluid
// pair of the step stored with its V gradW and h - r (PairStore::kBytesPerPair, 20 bytes): the
// neighbours of a particle inside the rest lattice (26 at support 2 spacings) times a margin for
// compression and the unused ends of the store's chunks, plus two chunks a thread (the one it
// fills and a spare). The margin, 1.15, fits the peak resident memory of the dam break at 2.5 and
// 1.8 mm after 2 steps (1.6e5 and 4.2e5 fluid particles, 133 and 317 MB; estimate 1.10x and
// 1.08x) and of the peer's dam break through its impact at 0.04 m to 0.5 s and 0.025 m to 0.2 s
// (1.6e4 and 5.9e4 fluid particles, 37 and 75 MB; 1.05x and 1.00x), 2026-11-26, 2 threads. Before
// the store followed the step's need (a vector a row, kept at twice the most it ever held) those
// two impact runs peaked at 73 and 106 MB, 2.0x and 1.4x.
constexpr double kDfsphBytesPerParticleArrays = 52;
constexpr double kDfsphPairMargin = 1.15;

// Lattice points within the support of one (0 < r < h, in spacings): a particle's fluid pairs.
double latticeNeighbours(float support) {
  const int reach = static_cast<int>(std::ceil(support));
  int count = 0;
  for (int i = -reach; i <= reach; ++i)
    for (int j = -reach; j <= reach; ++j)
      for (int k = -reach; k <= reach; ++k) {
        const int r2 = i * i + j * j + k * k;
        if (r2 > 0 && r2 < support * support) ++count;
      }
  return count;
}
// A rain drop (sim/rain/RainSystem.h: position, respawn count, streak layer) and its copy for the
// cache's /Rain#N: 28.7 bytes a drop measured (peak resident memory of 10^7 drops, 307 MB against
// 20 MB for one drop, 2026-11-26, no render section).
constexpr double kBytesPerRainDrop = 30;
// What drawing them adds (render/rain/StreakRaster: a copy of position and layer, 13 B, and at
// least 4 B of band bins a drop) and feeding the fluid (sim/rain/RainFeed: 13 B a drop), counted
// from the arrays rather than measured.
constexpr double kBytesPerDrawnRainDrop = 17;
constexpr double kBytesPerFeedingRainDrop = 13;
// A fluid particle of a distributed run (RankShare), on its rank: fitted to the peak resident
// memory of every rank of the dam break at 1,003,104 and 262,710 fluid particles on K = 1-4 ranks
// x 1 thread, frames written together (2026-11-26, Open MPI 4.1.4; estimate 0.85-1.10x of the
// ranks' peaks). 2.2 times one process's: the halo's global keys and cache places, the exchange's
// send and receive buffers and the collective frame's copy in key order come on top of the
// particle's arrays. Open MPI's own libraries and buffers add kMpiBytes a rank.
constexpr double kBytesPerDistributedParticle = 167;
constexpr double kMpiBytes = 7e6;
// A gathered frame on rank 0 (RankShare::gathersFrames): the fluid's 13 arrays of 4 bytes, its
// DFSPH warm start (2) and the frame's copy for the cache's chunks (13).
constexpr double kBytesPerGatheredParticle = 112;
// A rain scene's water cells on rank 0 when the frames are written together (app/
// CollectiveCacheSink.h): a cell of two spacings holds about 8 particles of a body of water, and
// each cell is a received key (8 B), a key of the union (8 B) and a hash-set node (~48 B). Counted
// from the arrays; rank 0 peaked 3.6 MB above rank 1 at 386,942 particles, its 8,000 drops and
// the cache's metadata included (docs/benchmarks.md, "Scale").
constexpr double kBytesPerWaterCellParticle = 8;
// The imbalance margin of a rank's share of the fluid (RankShare).
constexpr double kRankImbalance = 1.1;
// The program itself: code, libraries (HDF5, OpenMP, the C++ runtime), thread stacks.
constexpr double kBaseBytes = 15e6;
// An OpenGL context on Mesa's llvmpipe with the renderer's or cdt-gl's buffers and shaders.
constexpr double kGlBytes = 100e6;

}  // namespace

MemoryEstimate estimateMemory(const scene::Scene& scene, const RankShare& share) {
  MemoryEstimate m;
  m.ranks = share.distributed ? std::max(1, share.ranks) : 1;
  // The counts the id limit uses too (sim/solver/SceneSetup.h): an upper bound from the description.
  const solver::ParticleBudget budget = solver::particleBudget(scene);
  m.fluidParticles = static_cast<double>(budget.blocks);
  double largestEmitter = 0;
  std::size_t largest = 0;
  for (std::size_t k = 0; k < budget.emitters.size(); ++k) {
    const double n = static_cast<double>(budget.emitters[k]);
    m.emittedParticles += n;
    if (n > largestEmitter) largestEmitter = n, largest = k;
  }
  m.rainParticles = static_cast<double>(budget.rain);
  for (const scene::BoundaryShape& b : scene.boundaries)
    m.boundaryParticles += solver::countBoundarySamples(b, scene.domain, scene.solver.spacing,
                                                        scene.solver.wallLayers());
  const bool gl =
      scene.render || (scene.collision && scene.collision->method == scene::CollisionMethod::CdtGl);
  const bool dfsph = scene.solver.model == scene::SolverModel::Sph &&
                     scene.solver.pressure == scene::PressureSolver::Dfsph;
  const double pairBytes = static_cast<double>(grid::PairStore::kBytesPerPair);
  const double perFluidParticle =
      (share.distributed ? kBytesPerDistributedParticle : kBytesPerFluidParticle) +
      (dfsph ? kDfsphBytesPerParticleArrays +
                   kDfsphPairMargin * pairBytes * latticeNeighbours(scene.solver.support)
             : 0);
  const double pairChunks =
      dfsph ? 2.0 * threadCount() * pairBytes * static_cast<double>(grid::PairStore::kChunkPairs)
            : 0;
  double perDrop = kBytesPerRainDrop;
  if (scene.rain) {
    m.rainDrops = static_cast<double>(scene.rain->count);
    if (scene.render) perDrop += kBytesPerDrawnRainDrop;
    if (scene.rain->feedFluid) perDrop += kBytesPerFeedingRainDrop;
  }
  const double allFluid = m.fluidParticles + m.emittedParticles + m.rainParticles;
  // A rank's share (RankShare): slabs along the domain's longest side, in planes of the support
  // radius as the halo cuts them.
  double fluidShare = 1;
  if (m.ranks > 1) {
    const Vec3 extent = scene.domain.hi - scene.domain.lo;
    const double planes = std::max(
        1.0, std::floor(static_cast<double>(extent.maxCoeff()) / scene.solver.supportRadius()));
    fluidShare = std::min(1.0, kRankImbalance / m.ranks + 2.0 / planes);
  }
  // What rank 0 holds of the whole fluid: a gathered frame, or the water cells the drops meet.
  double onRoot =
      share.gathersFrames && share.distributed ? kBytesPerGatheredParticle * allFluid : 0;
  if (share.distributed && !share.gathersFrames && scene.rain && scene.camera)
    onRoot = kBytesPerWaterCellParticle * allFluid;
  const double fluidBytes = perFluidParticle * allFluid * fluidShare + onRoot;
  const double boundaryBytes = kBytesPerBoundaryParticle * m.boundaryParticles;
  const double rainBytes = perDrop * m.rainDrops;
  m.bytes = kBaseBytes + (share.distributed ? kMpiBytes : 0) + (gl ? kGlBytes : 0) + fluidBytes +
            boundaryBytes + rainBytes + pairChunks;
  if (share.distributed) m.rootOnlyBytes = onRoot + rainBytes;
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

}  // namespace sph::run
