#include "sim/run/RunLoop.h"

#include <algorithm>
#include <cmath>

namespace sph::run {

RunOutcome runFrames(Simulation& sim, const RunPlan& plan, const std::vector<FrameSink*>& sinks) {
  RunOutcome outcome;
  std::size_t frame = plan.nextFrame;
  auto stop = [&] { return plan.stopRequested && plan.stopRequested(); };
  auto stopTime = [&](std::size_t k) {
    return plan.stopTime ? plan.stopTime(k) : static_cast<double>(k) * plan.frameInterval;
  };
  try {
    while (sim.time() < plan.endTime && !stop()) {
      const double nextTime = std::min(plan.endTime, stopTime(frame));
      while (sim.time() < nextTime && !stop()) {
        if (plan.beforeStep) plan.beforeStep(sim);
        sim.step(nextTime);
        if (plan.afterStep) plan.afterStep(sim);
      }
      if (sim.time() < nextTime) break;  // stopped within a frame: it is not written
      for (FrameSink* sink : sinks) sink->frame(sim, frame);
      ++frame;
    }
  } catch (const StabilityError& e) {
    outcome.end = RunOutcome::End::BlowUp;
    outcome.blowUp = e;
  }
  if (outcome.end != RunOutcome::End::BlowUp && sim.time() < plan.endTime)
    outcome.end = RunOutcome::End::Stopped;
  outcome.nextFrame = frame;
  return outcome;
}

std::size_t plannedFrameCount(double endTime, double frameInterval) {
  return static_cast<std::size_t>(std::ceil(endTime / frameInterval)) + 1;
}

}  // namespace sph::run
