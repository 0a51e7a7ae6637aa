// The terminal's side of `sphsplat run` (job/RunJob.h): the header, the progress bar or lines,
// and how the run ended, on stdout and stderr as the user reads them.
#pragma once

#include <memory>
#include <string>

#include "app/Progress.h"
#include "job/RunJob.h"

namespace sph::app {

class RunTerminal final : public job::RunObserver {
 public:
  void checked(const job::RunRequest& o, const scene::Scene& scene,
               const run::MemoryEstimate& memory) override;
  void nothingToDo(const std::string& cachePath, double time) override;
  void started(const job::RunStart& s) override;
  void resumed(const job::RunResume& r) override;
  void settling(const job::RunSample& s) override;
  void settled(const job::RunSample& s, double wallSeconds) override;
  void blewUpSettling(const StabilityError& e) override;
  void progress(const job::RunSample& s) override;
  void progressDone(const job::RunSample& s) override;
  void blewUp(const job::RunRequest& o, const StabilityError& e, const run::RunPlan& plan,
              const run::RunOutcome& outcome) override;
  void interrupted(const job::RunRequest& o, int signal, double time) override;
  void cacheStopped(const std::string& kept) override;
  void canContinue(const job::RunRequest& o, const std::string& cachePath) override;
  void finished(const job::RunRequest& o, const job::RunSummary& s) override;

 private:
  Progress& bar();
  std::string label_;  // the scene's name
  std::unique_ptr<Progress> progress_;
  std::unique_ptr<Progress> settling_;  // the scene's `settle`, before the run's own bar
};

}  // namespace sph::app
