#include "job/distributed/Processes.h"

#include "job/distributed/DistributedRun.h"
#include "job/distributed/RankProcesses.h"

namespace sph::job::distributed {
namespace {

class SingleProcess final : public Processes {
 public:
  bool root() const override { return true; }
  bool distributed() const override { return false; }
  int count() const override { return 1; }
  ranks::Communicator* communicator() override { return nullptr; }
  bool gathersFrames() const override { return false; }

  void refuseUnsupported(const scene::Scene&) const override {}
  // Called in the handler of `error`: it goes on as it was thrown.
  [[noreturn]] void refuseOnAll(const InputError&) override { throw; }
  void followRoot() override {}
  void fromRoot(double&) override {}
  bool any(bool local) override { return local; }
  std::uint64_t globalCount(std::uint64_t local) override { return local; }
  void setLockstep(bool) override {}

  bool agreeOnResume(bool&, bool) override { return false; }
  std::unique_ptr<run::Simulation> makeSimulation(const scene::Scene& scene, bool) override {
    return std::make_unique<run::Simulation>(scene);
  }
  std::size_t startParticles(const run::Simulation& sim, const io::cache::CacheSession*,
                             bool) override {
    return sim.fluid().size();
  }
  // The whole frame, as CacheSession::restore reads it.
  ResumeRead resume(run::Simulation& sim, io::cache::CacheSession* cache,
                    std::size_t frame) override {
    auto [state, fluid] = cache->reader().readRestart(frame);
    io::cache::CacheSession::checkRecord(cache->path(), state, sim);
    sim.restore(state, std::move(fluid));
    ResumeRead read;
    read.frame = frame;
    return read;
  }
  void startStepping(run::Simulation&) override {}

  std::vector<run::FrameSink*> frameSinks(run::Simulation&, io::cache::CacheSession*,
                                          const scene::Scene&, std::vector<run::FrameSink*> local,
                                          bool, const io::cache::CacheProvenance&,
                                          std::size_t) override {
    return local;
  }

  // Only frames the ranks write together arm the recorder.
  void writingFailed(const std::string&) override {}
  void statusRecorded() override {}

  Report report(const run::Simulation&, const scene::Scene&) const override { return {}; }
};

}  // namespace

std::unique_ptr<Processes> Processes::ofThisRun() {
  if (ranks::Communicator* ranks = world()) return onRanks(*ranks);
  return std::make_unique<SingleProcess>();
}

}  // namespace sph::job::distributed
