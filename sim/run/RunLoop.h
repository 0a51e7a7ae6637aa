// A run through its stops: the loop every way of running a scene shares (`sphsplat run`, a
// resumed run, the sweeps of `sphsplat bench`, tests that run, stop and resume in-process). It
// steps a Simulation to each stop time, landing on it exactly, hands the state there to the
// sinks and stops at the end time, on request (Ctrl-C, a sweep's step or wall-time limit) or at a
// numerical blow-up. The stops of `sphsplat run` are its output frames (the HDF5 cache, pictures);
// a sweep's are its frames and its metrics' sample times (bench/sweep/SweepRunner.cpp). What is
// done at a stop, and what to tell the user, belongs to the caller.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "sim/run/Simulation.h"
#include "sim/StabilityError.h"

namespace sph::run {

// Receives the simulation's state at each stop the run lands on: for `sphsplat run` each
// finished output frame.
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void frame(const Simulation& sim, std::size_t index) = 0;
};

struct RunPlan {
  double endTime = 0;         // s
  double frameInterval = 0;   // s between output frames (1 / output.fps)
  std::size_t nextFrame = 1;  // index of the next frame to write (frame 0 is the initial state)
  // The time (s) of stop k, increasing in k; the run also stops at the end time. Unset: the output
  // frames at k * frameInterval, the times `sphsplat run` has always written and a resume
  // continues from. A sweep sets its own: frames at k / fps, which differs from k * (1 / fps) in
  // the last bit for some k, and its metrics' sample times between them. The step before a stop
  // is cut to land on it, so the stops shape the whole run: the sweeps' documented figures were
  // measured on theirs.
  std::function<double(std::size_t)> stopTime;
  // Checked between steps; true stops the run there (the frame in progress is not written).
  std::function<bool()> stopRequested;
  // Called just before and just after every step (progress; a sweep times the steps alone).
  std::function<void(const Simulation&)> beforeStep;
  std::function<void(const Simulation&)> afterStep;
};

struct RunOutcome {
  enum class End { Finished, Stopped, BlowUp } end = End::Finished;
  std::size_t nextFrame = 0;  // the first frame not written
  std::optional<StabilityError> blowUp;
};

// Runs `sim` from its current time to plan.endTime. Stops are at plan.stopTime(k) for k from
// plan.nextFrame (by default the exact multiples of the interval) and at the end time; the step
// before each is shortened to land on it.
RunOutcome runFrames(Simulation& sim, const RunPlan& plan, const std::vector<FrameSink*>& sinks);

// Output frames from t = 0 to `endTime` at `frameInterval`, the initial state included.
std::size_t plannedFrameCount(double endTime, double frameInterval);

}  // namespace sph::run
