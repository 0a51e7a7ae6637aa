#include "job/distributed/CollectiveCacheSink.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <string>

#include "job/distributed/DistributedRun.h"
#include "job/distributed/StatusRecorder.h"
#include "sim/rain/RainStepper.h"

namespace sph::job::distributed {
namespace {

// Rank 0's cache file (the writer's: PATH.partial until frame 0 is published), the index of the
// frame to write and the run's lost-particle count, on every rank.
struct Target {
  std::string path;
  std::uint64_t frame = 0;
  std::uint64_t lost = 0;
};

Target broadcastTarget(ranks::Communicator& ranks, const io::cache::CacheSession* cache,
                       const run::Simulation& sim) {
  ranks::Bytes b;
  if (ranks.rank() == 0) {
    const std::uint64_t head[2] = {cache->writerFrameCount(), sim.lostParticles()};
    b.resize(sizeof head);
    std::memcpy(b.data(), head, sizeof head);
    const std::string& path = cache->writerPath();
    b.insert(b.end(), path.begin(), path.end());
  }
  ranks.broadcastFromRoot(b);
  Target t;
  std::uint64_t head[2];
  std::memcpy(head, b.data(), sizeof head);
  t.frame = head[0], t.lost = head[1];
  t.path.assign(b.begin() + sizeof head, b.end());
  return t;
}

}  // namespace

bool writeCacheTogether() {
  return io::cache::h5::haveParallel();
}

CollectiveCacheSink::CollectiveCacheSink(ranks::Halo& halo, io::cache::CacheSession* cache,
                                         const scene::Scene& scene)
    : halo_(halo),
      cache_(cache),
      // As rain::RainStepper::create: no drops without a camera.
      waterCell_(scene.rain && scene.camera ? rain::RainStepper::waterCell(scene) : 0.0f) {}

std::unique_ptr<rain::WaterCells> CollectiveCacheSink::gatherWater(const Particles& fluid) {
  // A water cell holds several particles (two spacings on a side): its key is fewer bytes than
  // one particle's position, let alone a particle.
  // The rank's cells' keys, ascending, as WaterCells::keys() gives them, without its hash set.
  std::vector<std::uint64_t> keys(fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i)
    keys[i] = rain::WaterCells::keyOf(Vec3(fluid.x[i], fluid.y[i], fluid.z[i]), waterCell_);
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  ranks::Bytes mine(keys.size() * sizeof(std::uint64_t));
  if (!keys.empty()) std::memcpy(mine.data(), keys.data(), mine.size());
  const std::vector<ranks::Bytes> all = halo_.comm().gatherToRoot(mine);
  if (halo_.rank() != 0) return nullptr;
  std::vector<std::uint64_t> union_;
  for (std::size_t r = 0; r < all.size(); ++r) {
    const std::size_t n = all[r].size() / sizeof(std::uint64_t);
    const std::size_t at = union_.size();
    union_.resize(at + n);
    if (n > 0) std::memcpy(union_.data() + at, all[r].data(), n * sizeof(std::uint64_t));
    if (r != 0) cellBytes_ += all[r].size();
  }
  return std::make_unique<rain::WaterCells>(rain::WaterCells::fromKeys(union_, waterCell_));
}

void CollectiveCacheSink::frame(const run::Simulation& sim, std::size_t) {
  const auto start = std::chrono::steady_clock::now();
  ranks::Communicator& ranks = halo_.comm();
  // This rank's particles in the single-process order (their keys'), and the runs of places
  // they fill in the frame's arrays.
  std::vector<std::uint64_t> places = halo_.globalPlaces();
  // One place per particle, or this rank's selection would not match its buffer and the
  // collective write would wait forever for it: stop this rank (the others are aborted with it).
  if (places.size() != sim.fluid().size())
    throw std::logic_error(std::to_string(places.size()) + " cache places for " +
                           std::to_string(sim.fluid().size()) + " particles on rank " +
                           std::to_string(halo_.rank()));
  // Before the frame's collectives: rank 0 steps the drops once the frame is in.
  const std::unique_ptr<rain::WaterCells> water =
      waterCell_ > 0 ? gatherWater(sim.fluid()) : nullptr;
  Particles mine = sim.fluid();
  run::RunState state = broadcastRunState(ranks, sim.runState());
  state.warmStart = sim.runState().warmStart;
  // The local arrays are in key order, so the places ascend, but for particles emitted or
  // migrated since the last sort.
  if (!std::is_sorted(places.begin(), places.end())) {
    std::vector<std::uint32_t> order(places.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return places[a] < places[b]; });
    std::vector<std::uint32_t> scratch;
    mine.permute(order, scratch);
    for (std::vector<float>* v : state.warmStart.fields()) {
      if (v->size() != order.size()) continue;
      std::vector<float> sorted(v->size());
      for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = (*v)[order[i]];
      v->swap(sorted);
    }
    std::sort(places.begin(), places.end());
  }
  io::cache::FrameSlice slice;
  slice.ranks = &ranks;
  slice.part.total = halo_.globalCount(mine.size());
  for (std::uint64_t place : places) {
    auto& runs = slice.part.runs;
    if (!runs.empty() && runs.back().first + runs.back().second == place)
      ++runs.back().second;
    else
      runs.emplace_back(place, 1);
  }
  const Target target = broadcastTarget(ranks, cache_, sim);
  state.lostParticles = target.lost;
  // Until the frame is written, a failure anywhere may end rank 0 before it records why
  // (job/distributed/StatusRecorder.h); left armed when this throws, for the run's failure path.
  armStatusRecorder(cache_ ? target.path : "",
                    "the run ended while its ranks wrote frame " + std::to_string(target.frame) +
                        " together (a rank's write failed, or the run was stopped; see its "
                        "messages)",
                    target.frame + 1);
  if (cache_)
    cache_->writeFrameTogether(sim, mine, state, slice, water.get());
  else
    io::cache::CacheWriter::joinFrame(target.path, target.frame, mine, state, slice);
  disarmStatusRecorder();
  ++frames_;
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace sph::job::distributed
