// Progress of a long run on stderr: a redrawn bar on a terminal, plain periodic lines otherwise
// (logs, CI), silent with --quiet.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "sim/HumanText.h"

namespace sph::app {

struct ProgressSample {
  double time = 0, endTime = 0;  // s simulated
  std::uint64_t steps = 0;
  std::size_t particles = 0;
  double particleStepsPerSecond = 0;
};

class Progress {
 public:
  enum class Mode { Quiet, Bar, Lines };
  // Bar if stderr is a terminal, Lines otherwise, Quiet if asked.
  static Mode detect(bool quiet);

  explicit Progress(Mode mode, std::string label);
  void update(const ProgressSample& s);  // cheap to call every step; redraws at most ~10 Hz
  void finish(const ProgressSample& s);  // draws the final state once and ends the bar's line

 private:
  void draw(const ProgressSample& s);
  Mode mode_;
  std::string label_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
  double lastLinedFraction_ = -1;
  double lastDrawnFraction_ = -1;
  bool drawn_ = false;
};

}  // namespace sph::app
