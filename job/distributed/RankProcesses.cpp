#include "job/distributed/RankProcesses.h"

#include <algorithm>
#include <cstring>

#include "job/distributed/CollectiveCacheSink.h"
#include "job/distributed/DistributedResume.h"
#include "job/distributed/DistributedRun.h"
#include "job/distributed/StatusRecorder.h"
#include "sim/ranks/Halo.h"

namespace sph::job::distributed {
namespace {

class RankProcesses final : public Processes {
 public:
  explicit RankProcesses(ranks::Communicator& ranks) : ranks_(ranks) {}

  bool root() const override { return ranks_.rank() == 0; }
  bool distributed() const override { return true; }
  int count() const override { return ranks_.size(); }
  ranks::Communicator* communicator() override { return &ranks_; }
  bool gathersFrames() const override { return !writeCacheTogether(); }

  void refuseUnsupported(const scene::Scene& scene) const override {
    distributed::refuseUnsupported(scene, ranks_.size());
  }
  [[noreturn]] void refuseOnAll(const InputError& error) override {
    refuseOnAllRanks(ranks_, error.what());
  }
  void followRoot() override { distributed::followRoot(ranks_); }
  void fromRoot(double& value) override {
    ranks::Bytes b(sizeof(double));
    std::memcpy(b.data(), &value, sizeof(double));
    ranks_.broadcastFromRoot(b);
    std::memcpy(&value, b.data(), sizeof(double));
  }
  // The halo's, once it exists: the same collective, counted in its statistics.
  bool any(bool local) override { return halo_->any(local); }
  std::uint64_t globalCount(std::uint64_t local) override { return halo_->globalCount(local); }
  void setLockstep(bool on) override { distributed::setLockstep(on); }

  bool agreeOnResume(bool& resumed, bool reachesEnd) override {
    std::vector<std::int64_t> resume{resumed ? 1 : 0, resumed && reachesEnd};
    ranks_.sumInPlace(resume);
    resumed = resume[0] != 0;
    return resume[1] != 0;
  }

  // The slabs exist before the fluid, so no rank holds the whole of it.
  std::unique_ptr<run::Simulation> makeSimulation(const scene::Scene& scene,
                                                  bool resumed) override {
    halo_ = std::make_unique<ranks::Halo>(ranks_, scene.domain, scene.solver.supportRadius());
    return std::make_unique<run::Simulation>(
        scene, *halo_, resumed ? run::Simulation::Start::Empty : run::Simulation::Start::Slab);
  }
  std::size_t startParticles(const run::Simulation& sim, const io::cache::CacheSession* cache,
                             bool resumed) override {
    const std::size_t all = halo_->globalCount(sim.fluid().size());
    if (!resumed || !root()) return all;
    return cache->reader().summary().frames.at(cache->resumeFrame()).particles;
  }
  ResumeRead resume(run::Simulation& sim, io::cache::CacheSession* cache,
                    std::size_t frame) override;
  void startStepping(run::Simulation& sim) override { sim.setHalo(halo_.get()); }

  std::vector<run::FrameSink*> frameSinks(run::Simulation& sim, io::cache::CacheSession* cache,
                                          const scene::Scene& scene,
                                          std::vector<run::FrameSink*> local, bool resumed,
                                          const io::cache::CacheProvenance& provenance,
                                          std::size_t plannedFrames) override;

  // A failure in a frame the ranks write together: the recorder writes the status once they
  // have ended (it is armed only then).
  void writingFailed(const std::string& reason) override {
    if (statusRecorderArmed()) startStatusRecorder(reason.c_str());
  }
  void statusRecorded() override { cancelStatusRecorder(); }

  Report report(const run::Simulation& sim, const scene::Scene& scene) const override;

 private:
  ranks::Communicator& ranks_;
  std::unique_ptr<ranks::Halo> halo_;
  std::unique_ptr<run::FrameSink> sink_;
  std::function<double()> frameSeconds_;  // rank 0's time handing frames out (run -v)
  bool framesTogether_ = false;
  const CollectiveCacheSink* collective_ = nullptr;  // run -v: the rain's water cells
};

// Every rank reads its slab of the cache's last frame (DistributedResume.h).
ResumeRead RankProcesses::resume(run::Simulation& sim, io::cache::CacheSession* cache,
                                 std::size_t last) {
  std::vector<std::int64_t> frame{static_cast<std::int64_t>(last)};  // 0 but on rank 0
  ranks_.sumInPlace(frame);
  ranks::Bytes path;
  if (root()) path.assign(cache->path().begin(), cache->path().end());
  ranks_.broadcastFromRoot(path);
  {
    std::unique_ptr<io::cache::CacheReader> own;
    if (!root())
      own = std::make_unique<io::cache::CacheReader>(std::string(path.begin(), path.end()));
    ResumePart part = readResumePart(*halo_, root() ? cache->reader() : *own,
                                     static_cast<std::size_t>(frame[0]), sim.params().h);
    io::cache::CacheSession::checkRecord(std::string(path.begin(), path.end()), part.state, sim);
    sim.restore(part.state, std::move(part.fluid), std::move(part.keys));
  }
  // Every rank's count (its reader is closed once it is in): the most any rank read.
  std::vector<std::int64_t> read(static_cast<std::size_t>(ranks_.size()), 0);
  read[static_cast<std::size_t>(ranks_.rank())] = static_cast<std::int64_t>(sim.fluid().size());
  ranks_.sumInPlace(read);
  ResumeRead r;
  r.frame = static_cast<std::uint64_t>(frame[0]);
  for (std::int64_t n : read) r.totalRead += n;
  r.mostRead = *std::max_element(read.begin(), read.end());
  return r;
}

// With parallel HDF5 every rank writes its part of each frame (CollectiveCacheSink.h), else rank
// 0 gathers the frames and writes them.
std::vector<run::FrameSink*> RankProcesses::frameSinks(
    run::Simulation& sim, io::cache::CacheSession* cache, const scene::Scene& scene,
    std::vector<run::FrameSink*> local, bool resumed, const io::cache::CacheProvenance& provenance,
    std::size_t plannedFrames) {
  // Rank 0 knows whether there is a cache.
  std::vector<std::int64_t> caching{cache ? 1 : 0};
  ranks_.sumInPlace(caching);
  // (The renderer is refused on K processes, refuseUnsupported: the root's only sink is the
  // cache.)
  framesTogether_ = caching[0] && !scene.render && writeCacheTogether();
  if (framesTogether_) {
    auto sink = std::make_unique<CollectiveCacheSink>(*halo_, cache, scene);
    frameSeconds_ = [p = sink.get()] { return p->seconds(); };
    collective_ = sink.get();
    sink_ = std::move(sink);
  } else if (caching[0]) {
    // (Without a cache no rank has a sink: nothing is gathered.)
    auto sink = std::make_unique<GatheringSink>(*halo_, sim, std::move(local));
    frameSeconds_ = [p = sink.get()] { return p->seconds(); };
    sink_ = std::move(sink);
  }
  if (caching[0] && !resumed) {
    // Frame 0 as every later frame (each rank holds its slab of it): rank 0 creates the file
    // under PATH.partial (its checks stop every rank), all ranks write the frame, and rank 0
    // publishes it as PATH once the frame is committed.
    onRootAgreeing(ranks_, [&] {
      if (cache) cache->create(sim, provenance, plannedFrames);
    });
    sink_->frame(sim, 0);
  }
  if (!sink_) return {};
  return {sink_.get()};
}

Report RankProcesses::report(const run::Simulation& sim, const scene::Scene& scene) const {
  Report r;
  r.ranks = ranks_.size();
  r.framesTogether = framesTogether_;
  if (framesTogether_) r.mpiIo = mpiIoChoice();
  if (frameSeconds_) r.frameSeconds = frameSeconds_();
  r.exchanges = describeExchanges(*halo_, sim.profile());
  r.haloStats = &halo_->stats();
  if (collective_ && scene.rain && collective_->frames() > 0)
    r.rainCellBytesPerFrame =
        static_cast<double>(collective_->cellBytesReceived()) / collective_->frames();
  return r;
}

}  // namespace

std::unique_ptr<Processes> onRanks(ranks::Communicator& ranks) {
  return std::make_unique<RankProcesses>(ranks);
}

}  // namespace sph::job::distributed
