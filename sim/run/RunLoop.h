// A run through its output frames: the loop every way of running a scene shares (`sphsplat
// run`, a resumed run, the sweeps, tests that run, stop and resume in-process). It steps a
// Simulation to each output frame time, hands every finished frame to the sinks (the HDF5 cache,
// pictures) and stops at the end time, on request (Ctrl-C) or at a numerical blow-up. What is
// done with a frame, and what to tell the user, belongs to the caller.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "sim/run/Simulation.h"
#include "sim/StabilityError.h"

namespace sph::run {

// Receives each finished output frame (the simulation's state at that frame's time).
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void frame(const Simulation& sim, std::size_t index) = 0;
};

struct RunPlan {
  double endTime = 0;         // s
  double frameInterval = 0;   // s between output frames (1 / output.fps)
  std::size_t nextFrame = 1;  // index of the next frame to write (frame 0 is the initial state)
  // Checked between steps; true stops the run there (the frame in progress is not written).
  std::function<bool()> stopRequested;
  // Called after every step (progress).
  std::function<void(const Simulation&)> afterStep;
};

struct RunOutcome {
  enum class End { Finished, Stopped, BlowUp } end = End::Finished;
  std::size_t nextFrame = 0;  // the first frame not written
  std::optional<StabilityError> blowUp;
};

// Runs `sim` from its current time to plan.endTime. Frames are at exact multiples of the interval
// (the step is shortened to land on them) and at the end time.
RunOutcome runFrames(Simulation& sim, const RunPlan& plan, const std::vector<FrameSink*>& sinks);

// Output frames from t = 0 to `endTime` at `frameInterval`, the initial state included.
std::size_t plannedFrameCount(double endTime, double frameInterval);

}  // namespace sph::run
