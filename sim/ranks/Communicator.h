// The collective operations a distributed run needs (docs/scaling.md), as an interface so sim/
// stays free of MPI: job/distributed/mpi/MpiCommunicator.h implements it with MPI; a single process
// needs none (Simulation without a Halo). Every call is collective: all ranks call it, in the same
// order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sph::ranks {

using Bytes = std::vector<std::uint8_t>;

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;

  // Element-wise over all ranks, in place. Max/min are exact; the integer sum is exact and does
  // not depend on the order of the ranks.
  virtual void maxInPlace(std::vector<double>& values) = 0;
  virtual void minInPlace(std::vector<double>& values) = 0;
  virtual void sumInPlace(std::vector<std::int64_t>& values) = 0;
  // Element-wise, the sum over the ranks below this one (rank r gets ranks 0..r-1's values; rank
  // 0 gets zeros): where a rank's share starts when the ranks' shares are laid out in rank order.
  virtual void exclusiveScanInPlace(std::vector<std::int64_t>& values) = 0;
  // send[r] goes to rank r; returns what each rank sent to this one (received[r] from rank r).
  virtual std::vector<Bytes> allToAll(const std::vector<Bytes>& send) = 0;
  // Every rank's `mine`, indexed by rank, on every rank.
  virtual std::vector<Bytes> allGather(const Bytes& mine) = 0;
  // Every rank's `mine` on rank 0 (indexed by rank); empty on the others.
  virtual std::vector<Bytes> gatherToRoot(const Bytes& mine) = 0;
  // Rank 0's `data` on every rank.
  virtual void broadcastFromRoot(Bytes& data) = 0;
};

}  // namespace sph::ranks
