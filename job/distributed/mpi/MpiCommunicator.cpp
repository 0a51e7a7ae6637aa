#include "job/distributed/mpi/MpiCommunicator.h"

#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace sph::job::distributed::mpi {
namespace {

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

int byteCount(std::size_t n) {
  if (n > static_cast<std::size_t>(INT32_MAX))
    throw std::runtime_error("MPI: a message of over 2 GiB (more ranks spread it)");
  return static_cast<int>(n);
}

// Byte counts and displacements for the v-collectives (int, as MPI wants them): the whole of
// what one rank receives must stay under 2 GiB too (an all-gather of 30M particles would not).
std::vector<int> displacements(const std::vector<int>& counts) {
  std::vector<int> d(counts.size(), 0);
  std::size_t at = 0;
  for (std::size_t r = 1; r < counts.size(); ++r) {
    at += static_cast<std::size_t>(counts[r - 1]);
    d[r] = byteCount(at);
  }
  if (!counts.empty()) byteCount(at + static_cast<std::size_t>(counts.back()));
  return d;
}

std::vector<ranks::Bytes> split(const std::vector<std::uint8_t>& all,
                                const std::vector<int>& counts) {
  std::vector<ranks::Bytes> out(counts.size());
  std::size_t at = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    out[r].assign(all.begin() + static_cast<std::ptrdiff_t>(at),
                  all.begin() + static_cast<std::ptrdiff_t>(at + counts[r]));
    at += static_cast<std::size_t>(counts[r]);
  }
  return out;
}

class MpiCommunicator final : public ranks::Communicator {
 public:
  MpiCommunicator() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void maxInPlace(std::vector<double>& v) override {
    check(MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_MAX,
                        MPI_COMM_WORLD),
          "max");
  }
  void minInPlace(std::vector<double>& v) override {
    check(MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_MIN,
                        MPI_COMM_WORLD),
          "min");
  }
  void sumInPlace(std::vector<std::int64_t>& v) override {
    check(MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_INT64_T, MPI_SUM,
                        MPI_COMM_WORLD),
          "sum");
  }
  void exclusiveScanInPlace(std::vector<std::int64_t>& v) override {
    check(MPI_Exscan(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_INT64_T, MPI_SUM,
                     MPI_COMM_WORLD),
          "exclusive scan");
    // MPI leaves rank 0's buffer undefined.
    if (rank_ == 0) std::fill(v.begin(), v.end(), 0);
  }

  std::vector<ranks::Bytes> allToAll(const std::vector<ranks::Bytes>& send) override {
    std::vector<int> sendCounts(size_), recvCounts(size_);
    for (int r = 0; r < size_; ++r) sendCounts[r] = byteCount(send[r].size());
    check(
        MPI_Alltoall(sendCounts.data(), 1, MPI_INT, recvCounts.data(), 1, MPI_INT, MPI_COMM_WORLD),
        "all-to-all counts");
    std::vector<std::uint8_t> out, in;
    for (const ranks::Bytes& b : send) out.insert(out.end(), b.begin(), b.end());
    const std::vector<int> sendAt = displacements(sendCounts), recvAt = displacements(recvCounts);
    in.resize(static_cast<std::size_t>(recvAt.back()) + recvCounts.back());
    check(MPI_Alltoallv(out.data(), sendCounts.data(), sendAt.data(), MPI_BYTE, in.data(),
                        recvCounts.data(), recvAt.data(), MPI_BYTE, MPI_COMM_WORLD),
          "all-to-all");
    return split(in, recvCounts);
  }

  std::vector<ranks::Bytes> allGather(const ranks::Bytes& mine) override {
    std::vector<int> counts(size_);
    const int n = byteCount(mine.size());
    check(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD),
          "all-gather counts");
    const std::vector<int> at = displacements(counts);
    std::vector<std::uint8_t> in(static_cast<std::size_t>(at.back()) + counts.back());
    check(MPI_Allgatherv(mine.data(), n, MPI_BYTE, in.data(), counts.data(), at.data(), MPI_BYTE,
                         MPI_COMM_WORLD),
          "all-gather");
    return split(in, counts);
  }

  std::vector<ranks::Bytes> gatherToRoot(const ranks::Bytes& mine) override {
    std::vector<int> counts(size_);
    const int n = byteCount(mine.size());
    check(MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD),
          "gather counts");
    const std::vector<int> at = displacements(counts);
    std::vector<std::uint8_t> in(rank_ == 0 ? static_cast<std::size_t>(at.back()) + counts.back()
                                            : 0);
    check(MPI_Gatherv(mine.data(), n, MPI_BYTE, in.data(), counts.data(), at.data(), MPI_BYTE, 0,
                      MPI_COMM_WORLD),
          "gather");
    if (rank_ != 0) return {};
    return split(in, counts);
  }

  void broadcastFromRoot(ranks::Bytes& data) override {
    std::uint64_t n = data.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "broadcast size");
    data.resize(n);
    check(MPI_Bcast(data.data(), byteCount(n), MPI_BYTE, 0, MPI_COMM_WORLD), "broadcast");
  }

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace

MpiSession::MpiSession(int* argc, char*** argv) {
  int provided = 0;
  // OpenMP threads inside a rank; only the main thread calls MPI.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  world_ = std::make_unique<MpiCommunicator>();
}

MpiSession::~MpiSession() {
  if (world_) {
    world_.reset();
    MPI_Finalize();
  }
}

void MpiSession::abortAll(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::abort();
}

}  // namespace sph::job::distributed::mpi
