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
  void onRoot(const std::function<void()>& work) override { work(); }
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
  ResumeRead resume(run::Simulation& sim, io::cache::CacheSession* cache,
                    const io::cache::CacheProvenance& provenance) override {
    ResumeRead read;
    read.frame = cache->restore(sim, provenance);
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
