// How bench_collision times the collision pass: ms per step of the collide pass inside a
// simulation step (any method), or of cdt-gl resident on the GPU as the paper runs it; least and
// median over the timed steps.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "bench/collision/Snapshot.h"
#include "sim/scene/CollisionDesc.h"

namespace sph::collisionbench {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point t);

// Milliseconds per step over the timed steps: the least (the machine is shared with other jobs;
// the least is what the method costs when it has the cores) and the median.
struct Timing {
  double minMs = 0, medianMs = 0;
};

Timing summarise(std::vector<double> ms);
// "least / median" with `decimals` digits.
std::string format(const Timing& t, int decimals = 1);
// The 1-minute load average (the machine is shared: printed before and after).
double loadAverage();

// Restores the snapshot, runs one untimed step (the CDT's first step finds an empty texture),
// then times the collide pass of each of `steps` steps.
Timing timeMethod(const Snapshot& snap, scene::CollisionMethod method, int steps,
                  const std::vector<std::string>& overrides = {});

// cdt-gl as the paper runs it: the particle system lives on the GPU (integrate in the shader),
// nothing crosses to the CPU between steps (glFinish after each step, for the clock).
Timing timeGlResident(const Snapshot& snap, int steps, bool rasterWrite = false);

}  // namespace sph::collisionbench
