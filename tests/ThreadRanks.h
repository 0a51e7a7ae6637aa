// K ranks of sim/ranks in one process, one thread each: a ranks::Communicator whose collectives
// meet at a barrier and read each other's contributions (the same semantics as
// job/distributed/mpi/MpiCommunicator.cpp, no MPI). For the unit tests of sim/ranks that need
// several ranks (ghost sets, migration) in the default suite; the MPI transport itself is tested
// through mpirun by tests/test_mpi.cpp.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "sim/ranks/Communicator.h"

namespace sph::test {

class ThreadRanks {
 public:
  explicit ThreadRanks(int ranks)
      : ranks_(ranks),
        barrier_(ranks),
        doubles_(ranks),
        ints_(ranks),
        parcels_(ranks, std::vector<ranks::Bytes>(ranks)),
        single_(ranks) {}

  // Runs body(comm) on every rank, each in its own thread, and waits for all.
  void run(const std::function<void(ranks::Communicator&)>& body) {
    std::vector<Rank> comms;
    for (int r = 0; r < ranks_; ++r) comms.emplace_back(*this, r);
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks_; ++r) threads.emplace_back([&, r] { body(comms[r]); });
    for (std::thread& t : threads) t.join();
  }

 private:
  class Rank final : public ranks::Communicator {
   public:
    Rank(ThreadRanks& all, int rank) : all_(all), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return all_.ranks_; }
    void maxInPlace(std::vector<double>& v) override {
      reduce(all_.doubles_, v, [](double a, double b) { return std::max(a, b); });
    }
    void minInPlace(std::vector<double>& v) override {
      reduce(all_.doubles_, v, [](double a, double b) { return std::min(a, b); });
    }
    void sumInPlace(std::vector<std::int64_t>& v) override {
      reduce(all_.ints_, v, [](std::int64_t a, std::int64_t b) { return a + b; });
    }
    void exclusiveScanInPlace(std::vector<std::int64_t>& v) override {
      all_.ints_[rank_] = v;
      all_.barrier_.wait();
      std::fill(v.begin(), v.end(), 0);
      for (int r = 0; r < rank_; ++r)
        for (std::size_t i = 0; i < v.size(); ++i) v[i] += all_.ints_[r][i];
      all_.barrier_.wait();
    }
    std::vector<ranks::Bytes> allToAll(const std::vector<ranks::Bytes>& send) override {
      all_.parcels_[rank_] = send;
      all_.barrier_.wait();
      std::vector<ranks::Bytes> received(all_.ranks_);
      for (int r = 0; r < all_.ranks_; ++r) received[r] = all_.parcels_[r][rank_];
      all_.barrier_.wait();
      return received;
    }
    std::vector<ranks::Bytes> allGather(const ranks::Bytes& mine) override {
      all_.single_[rank_] = mine;
      all_.barrier_.wait();
      std::vector<ranks::Bytes> all = all_.single_;
      all_.barrier_.wait();
      return all;
    }
    std::vector<ranks::Bytes> gatherToRoot(const ranks::Bytes& mine) override {
      std::vector<ranks::Bytes> all = allGather(mine);
      if (rank_ != 0) all.clear();
      return all;
    }
    void broadcastFromRoot(ranks::Bytes& data) override {
      if (rank_ == 0) all_.single_[0] = data;
      all_.barrier_.wait();
      data = all_.single_[0];
      all_.barrier_.wait();
    }

   private:
    template <class T, class Op>
    void reduce(std::vector<std::vector<T>>& slots, std::vector<T>& v, Op op) {
      slots[rank_] = v;
      all_.barrier_.wait();
      for (int r = 0; r < all_.ranks_; ++r)
        for (std::size_t i = 0; i < v.size(); ++i)
          v[i] = r == 0 ? slots[0][i] : op(v[i], slots[r][i]);
      all_.barrier_.wait();
    }
    ThreadRanks& all_;
    int rank_;
  };

  int ranks_;
  // Every rank waits until all have arrived (the tests build as C++17: no std::barrier).
  class Barrier {
   public:
    explicit Barrier(int count) : count_(count) {}
    void wait() {
      std::unique_lock<std::mutex> lock(mutex_);
      const unsigned long generation = generation_;
      if (++arrived_ == count_) {
        arrived_ = 0, ++generation_;
        all_.notify_all();
        return;
      }
      all_.wait(lock, [&] { return generation_ != generation; });
    }

   private:
    std::mutex mutex_;
    std::condition_variable all_;
    int count_, arrived_ = 0;
    unsigned long generation_ = 0;
  };
  Barrier barrier_;
  std::vector<std::vector<double>> doubles_;
  std::vector<std::vector<std::int64_t>> ints_;
  std::vector<std::vector<ranks::Bytes>> parcels_;
  std::vector<ranks::Bytes> single_;
};

}  // namespace sph::test
