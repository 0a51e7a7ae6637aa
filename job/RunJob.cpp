#include "job/RunJob.h"

#include "job/ExitCode.h"
#include "job/RunStages.h"

namespace sph::job {

int runJob(const RunRequest& request, RunObserver& observer) {
  RunContext c(request, observer);
  loadScene(c);
  if (StageResult end = checkMachine(c)) return *end;
  if (StageResult end = openCache(c)) return *end;
  if (StageResult end = startSimulation(c)) return *end;
  if (StageResult end = settleTheFluid(c)) return *end;
  setUpOutputs(c);
  if (StageResult end = runTheFrames(c)) return *end;
  finish(c);
  return kOk;
}

}  // namespace sph::job
