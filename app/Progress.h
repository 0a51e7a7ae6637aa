// Progress of a long run on stderr: a redrawn bar on a terminal, plain periodic lines otherwise
// (logs, CI), silent with --quiet.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include "job/RunJob.h"
#include "sim/HumanText.h"

namespace sph::app {

using ProgressSample = job::RunSample;


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
  // "ETA 12.3 s", or "ETA estimating..." until the rate is known. The first steps cost more than
  // the rest (first touch of the arrays, threads starting, the first frame written), so the rate
  // is measured from the end of a warm-up second on: extrapolated from the start, a 30 s run
  // once said "ETA 51m51s" on its first line.
  std::string eta(double elapsed, double fraction) const;
  static constexpr double kWarmUpSeconds = 1.0;
  Mode mode_;
  std::string label_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
  double lastLinedFraction_ = -1;
  double lastDrawnFraction_ = -1;
  bool drawn_ = false;
  double warmSeconds_ = -1, warmFraction_ = 0;  // wall time and fraction at the warm-up's end
};

}  // namespace sph::app
