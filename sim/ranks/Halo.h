// Slab domain decomposition of the fluid for a run on several processes (docs/scaling.md). Every
// rank owns the particles in its slab of whole grid-cell planes along the domain's longest axis;
// the slabs are re-cut every step so each holds about the same number of particles (a pour
// filling a cup moves the water). Each step the rank receives copies of the particles in the two
// cell planes beyond each face of its slab (ghosts): enough for its own particles' densities and
// forces and for the boundary particles those use (sim/solver/SphPasses.cpp), so no second exchange
// within the step is needed, except by DFSPH's iterations, whose velocities change within the
// step: refreshGhosts() sends them again along the step's ghost lists.
//
// Bit-identical to one process, whatever the number of ranks (the test:
// tests/test_mpi.cpp): a particle's sums run over the same candidates in the same order as in a
// single process, because the local arrays are always the single process's array restricted to
// the particles present. Each particle carries the key of its place in the global order (its cell
// in the domain's lattice, then its place within the cell, both fixed by the owner of the cell);
// before the grid's stable sort the local arrays are put in key order, so the sort reproduces the
// global order on every rank. The step's global sums (the gradient correction, DFSPH's error
// means) are exact (ExactSum) and so independent of the split; max/min reductions are exact.
//
// MPI-free: the collectives go through ranks::Communicator (job/distributed/mpi/MpiCommunicator.h
// implements it).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <vector>

#include "sim/grid/NeighbourGrid.h"
#include "sim/Particles.h"
#include "sim/StabilityError.h"
#include "sim/Types.h"
#include "sim/ranks/Communicator.h"
#include "sim/ranks/ExactSum.h"

namespace sph::ranks {

// Rank r owns the cell planes p (along `axis`) with first[r] <= p < first[r + 1]; the first rank
// reaches down to -infinity, the last up to +infinity.
struct Slabs {
  int axis = 0;
  std::vector<long long> first;  // size ranks + 1

  int ranks() const { return static_cast<int>(first.size()) - 1; }
  int ownerOf(long long plane) const;
  // Cuts the planes [firstPlane, firstPlane + counts.size()) so each rank gets about an equal
  // share of the particles (counts[i]: particles in plane firstPlane + i).
  static Slabs balance(int axis, int ranks, long long firstPlane,
                       const std::vector<std::int64_t>& counts);
};

// The cell plane holding coordinate x for cells of 1 / invCell (the slabs' and the keys' planes).
inline long long planeOf(float x, double invCell) {
  return static_cast<long long>(std::floor(static_cast<double>(x) * invCell));
}

// Ghost planes beyond each face: the density of a ghost one plane out needs the plane beyond it.
constexpr int kGhostPlanes = 2;

// What one rank's exchanges cost (docs/benchmarks.md, "Scale").
struct HaloStats {
  std::uint64_t steps = 0;
  std::uint64_t bytesSent = 0;       // migration + ghosts, to other ranks
  std::uint64_t ghostsReceived = 0;  // summed over steps
  std::uint64_t migrated = 0;        // particles that changed rank, sent from here
  // Particles that changed rank, summed over all ranks, from the second exchange on (the first
  // cuts the slabs the start or the resume already has, so it moves none) up to the one before
  // the last (each exchange's count rides on the next one's plane histogram).
  std::uint64_t migratedAllRanks = 0;
  double exchangeSeconds = 0;  // rebalance + migration + ghosts + key order
  // refreshGhosts(): calls, bytes sent to other ranks, seconds (DFSPH's iterations).
  std::uint64_t refreshes = 0, refreshBytesSent = 0;
  double refreshSeconds = 0;
  double imbalanceSum = 0, imbalanceMax = 0;  // max/mean owned particles per rank, per step
  // globalPlaces() (the frames the ranks write together): calls, the bytes this rank received
  // from other ranks in its collectives, the keys it sent to be placed elsewhere (migrated since
  // the sort, or after every cell key: HaloPlaces.cpp), seconds.
  std::uint64_t placesCalls = 0, placesBytesReceived = 0, placesStrays = 0;
  double placesSeconds = 0;
};

class Halo {
 public:
  // `h`: the support radius (the grid's cell size before any growth).
  Halo(Communicator& comm, const Aabb& domain, float h);

  Communicator& comm() { return comm_; }
  int rank() const { return comm_.rank(); }
  int ranks() const { return comm_.size(); }
  const Slabs& slabs() const { return slabs_; }

  // Takes this rank's part of the run's starting fluid, in global order: `keys` are the
  // particles' places in the single-process starting order (empty: 0, 1, ... as when rank 0
  // holds the whole fluid and the others nothing). Together the ranks' keys must be 0 .. N - 1:
  // until the first exchange() a key is its particle's place in a frame (globalPlaces() then
  // needs no collective). The first exchange() hands out whatever is not on its owner.
  void adopt(const Particles& fluid, std::vector<std::uint64_t> keys = {});
  // Sets the slabs and cell size the first exchange() will find (sim/run/StartSlab.h: the
  // starting fluid cut before anything is generated), so owns() and the start agree with it.
  void startWith(const Slabs& slabs, float cellSize);
  // True if this rank's slab holds point p (the emitters' nozzles, docs/scaling.md).
  bool owns(const Vec3& p) const;
  // A per-particle array kept beside the fluid, in its order (DFSPH's warm start, part of the run
  // state): from now on it moves with its particles wherever the halo moves the fluid (migration,
  // ghosts, the key order, sorted(), dropGhosts(), gather()); exchange() gives the particles it
  // does not cover yet (all, if it is empty; emitted ones) 0. removeLocal() leaves it to the
  // caller, who removes the particles from it as from the fluid. The caller keeps `field` alive.
  void attach(std::vector<float>& field);

  // Before the step's sort: re-cuts the slabs, migrates the particles that left this rank's slab
  // (the emitted ones included) and appends the ghosts, then puts the local arrays in global key
  // order. Returns the cell size the grid must use: the one the single-process grid would choose
  // for all particles (NeighbourGrid::cellSizeFor).
  float exchange(Particles& fluid, float h);
  // After the grid sort applied `order` (sorted[i] = old[order[i]]): the new keys of the owned
  // particles.
  void sorted(const grid::NeighbourGrid& grid, const std::vector<std::uint32_t>& order);
  // 1 for a ghost, in the local order (valid from exchange() until dropGhosts()).
  const std::vector<std::uint8_t>& ghost() const { return ghost_; }
  // Sends the owned particles' `fields` again to the ranks that hold them as ghosts (this step's
  // ghost lists, kept through the sorts) and overwrites the ghosts' copies: DFSPH's iterations
  // change the velocities the next iteration reads (docs/scaling.md). Between exchange() and
  // dropGhosts(); every array as long as the local fluid.
  void refreshGhosts(std::initializer_list<std::vector<float>*> fields);
  // Removes the ghosts (keeping the owned particles' order).
  void dropGhosts(Particles& fluid);
  // The caller removed the owned particles with keep[i] == 0, keeping the others' order (the
  // guard's lost particles, sim/solver/Integration.cpp): their keys go too. An empty `keep` keeps all.
  void removeLocal(const std::vector<std::uint8_t>& keep);

  // The owned fluid of every rank on rank 0, in the single-process order (a frame to write);
  // empty on the other ranks. With `attached`: the attached arrays too, in attach() order and the
  // same particle order.
  Particles gather(const Particles& fluid, std::vector<std::vector<float>>* attached = nullptr);
  // The owned fluid of every rank on every rank, in the single-process order; mine[i]: where this
  // rank's particle i is in it (a collision pass that needs the whole fluid, docs/scaling.md).
  Particles allGather(const Particles& fluid, std::vector<std::uint32_t>& mine);
  std::uint64_t globalCount(std::size_t local);
  // Where each owned particle stands in the single-process order (its index among every rank's
  // particles ordered by key), for the ranks writing a frame together (parallel HDF5, each rank
  // its places of the arrays). Costs a sum and an exclusive scan of one counter per row (slabs
  // across x), plane (across y) or none (across z) of the key lattice that the fluid spans, and
  // for keys migrated or emitted since the last sorted() (all of them before the first: the
  // particle model) two all-to-alls of 8 bytes a key: nothing is all-gathered. HaloPlaces.cpp.
  std::vector<std::uint64_t> globalPlaces();

  // The guard's verdict of every rank (each passes what its own checkStability() threw, or
  // nothing): throws, on every rank, the error one process would report: a non-finite state
  // before a particle outside the domain, then the lowest particle id at fault.
  void agreeOnStability(const std::optional<StabilityError>& local);
  // True on every rank if `local` is true on any (a signal seen by one rank stops all at the
  // same step).
  bool any(bool local);
  // The larger of each value over all ranks.
  void maxOverRanks(float& a, float& b);

  const HaloStats& stats() const { return stats_; }

 private:
  // A key: the cell's index in the lattice of the domain grown by kGhostPlanes, row-major
  // (x fastest), above kWithinBits bits of the place within the cell. Emitted particles join
  // after every particle of the previous order, in id order (as Particles::append puts them at
  // the end of the single process's arrays): kEmitted | id.
  static constexpr std::uint64_t kEmitted = std::uint64_t(1) << 63;
  static constexpr int kWithinBits = 24;  // a cell holds fewer than 2^24 particles
  struct KeyLattice {
    long long origin[3] = {0, 0, 0}, dims[3] = {1, 1, 1};
  };
  KeyLattice keyLattice() const;  // of cellSize_
  static std::uint64_t globalKey(const KeyLattice& lattice, const grid::CellCoord& cell,
                                 std::uint32_t within);
  Particles merged(const Particles& fluid, bool everyRank, std::vector<std::uint32_t>* mine,
                   std::vector<std::vector<float>>* attached);
  // The sort `order` (new[i] = old[order[i]]) moved the particles: the keys, ghost flags,
  // attached arrays and ghost lists follow.
  void permuted(const std::vector<std::uint32_t>& order);

  Communicator& comm_;
  Aabb domain_;
  Slabs slabs_;
  float cellSize_ = 0;               // of the last exchange
  std::vector<std::uint64_t> keys_;  // per local particle: its place in the global order
  // The lattice and the cut of the last sorted(), which keyed every owned particle (false until
  // the first: keys_ then hold the starting order). globalPlaces() reads a key's cell back.
  bool keyed_ = false;
  // From adopt() to the first exchange(): keys_ are the places of the starting order.
  bool startOrder_ = false;
  KeyLattice keyedLattice_;
  Slabs keyedSlabs_;
  std::vector<std::uint8_t> ghost_;   // per local particle
  std::vector<std::uint32_t> order_;  // scratch
  std::vector<std::vector<float>*> attached_;
  // This step's ghost lists: the local indices of the owned particles sent to rank r as ghosts,
  // and of the ghosts received from rank r, each in the order of the message.
  std::vector<std::vector<std::uint32_t>> sentTo_, receivedFrom_;
  std::uint64_t migratedLast_ = 0;  // sent from here in the last exchange
  HaloStats stats_;
};

}  // namespace sph::ranks
