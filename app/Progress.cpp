#include "app/Progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace sph::app {

Progress::Mode Progress::detect(bool quiet) {
  if (quiet) return Mode::Quiet;
  return isatty(STDERR_FILENO) ? Mode::Bar : Mode::Lines;
}

Progress::Progress(Mode mode, std::string label)
    : mode_(mode),
      label_(std::move(label)),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {}

void Progress::update(const ProgressSample& s) {
  if (mode_ == Mode::Quiet) return;
  const auto now = std::chrono::steady_clock::now();
  const double sinceDraw = std::chrono::duration<double>(now - lastDraw_).count();
  const double fraction = s.endTime > 0 ? s.time / s.endTime : 1;
  if (fraction >= 1) return;  // the final state is drawn by finish()
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (warmSeconds_ < 0 && elapsed >= kWarmUpSeconds)
    warmSeconds_ = elapsed, warmFraction_ = fraction;
  if (mode_ == Mode::Bar) {
    if (drawn_ && sinceDraw < 0.1) return;
  } else {
    // A line every 10% of the run or every 10 s, whichever comes first.
    if (drawn_ && fraction - lastLinedFraction_ < 0.1 && sinceDraw < 10) return;
    lastLinedFraction_ = fraction;
  }
  lastDraw_ = now;
  draw(s);
}

void Progress::draw(const ProgressSample& s) {
  drawn_ = true;
  lastDrawnFraction_ = s.endTime > 0 ? s.time / s.endTime : 1;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction = s.endTime > 0 ? std::min(1.0, s.time / s.endTime) : 1;
  char stats[256];
  const std::string tail = fraction >= 1 ? "in " + humanSeconds(elapsed) : eta(elapsed, fraction);
  std::snprintf(stats, sizeof stats,
                "t %.3f/%.3f s  step %llu  %s particles  %s particle-steps/s  %s", s.time,
                s.endTime, static_cast<unsigned long long>(s.steps),
                humanCount(static_cast<double>(s.particles)).c_str(),
                humanCount(s.particleStepsPerSecond).c_str(), tail.c_str());
  if (mode_ == Mode::Bar) {
    constexpr int width = 24;
    const int filled = static_cast<int>(std::lround(fraction * width));
    std::string bar(filled, '#');
    bar.resize(width, '.');
    std::fprintf(stderr, "\r%s [%s] %3d%%  %s\033[K", label_.c_str(), bar.c_str(),
                 static_cast<int>(fraction * 100), stats);
  } else {
    std::fprintf(stderr, "%s %3d%%  %s\n", label_.c_str(), static_cast<int>(fraction * 100), stats);
  }
  std::fflush(stderr);
}

std::string Progress::eta(double elapsed, double fraction) const {
  // The rate since the end of the warm-up, over at least as long again.
  const double span = elapsed - warmSeconds_, done = fraction - warmFraction_;
  if (warmSeconds_ < 0 || span < kWarmUpSeconds || done <= 0) return "ETA estimating...";
  return "ETA " + humanSeconds((1 - fraction) * span / done);
}

void Progress::finish(const ProgressSample& s) {
  if (mode_ == Mode::Quiet) return;
  if (lastDrawnFraction_ < 1 && s.endTime > 0 && s.time >= s.endTime) draw(s);
  if (mode_ == Mode::Bar && drawn_) std::fprintf(stderr, "\n");
}

}  // namespace sph::app
