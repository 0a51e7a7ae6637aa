// What a sweep measures besides time (docs/benchmarks.md): pluggable error metrics. A metric
// observes the simulation at times or step counts it asks for and turns what it saw into CSV
// columns. Adding one = a class here (or in its own file) and a line in makeMetric().
//
// Built in:
//   surge_front  dam break against Martin & Moyce (1952): RMS and max relative deviation of the
//                surge front Z = x / a at the measured points with T <= max_T; options: a
//                time offset (a gate held shut), the front at the water's edge, per-point
//                deviations, the best-fitting offset, the front after every step as a CSV
//   density      compression (rho - rho0) / rho0 at every output frame: mean and max
//   energy       total energy (kinetic + potential + EOS elastic) and mean density every N steps,
//                written as a time series; their drift after a settling time
// Not yet metrics: collision recall against `exact` (bench_collision measures it), render PSNR /
// hole fraction.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/run/Simulation.h"

namespace sph::sweep {

// What a metric knows about the variant it measures.
struct MetricContext {
  std::string sweepFolder;   // paths in metric options are relative to it
  std::string seriesPrefix;  // "DIR/variant-3": where a metric may write per-variant files
};

class SweepMetric {
 public:
  virtual ~SweepMetric() = default;
  // Column names, in the order values() returns them.
  virtual std::vector<std::string> columns() const = 0;
  // Called once the simulation is built, before the first step; resets the metric's state.
  virtual void start(const run::Simulation& sim, const MetricContext& context) = 0;
  // Simulated times (s) at which observe() must see the state exactly (the run lands on them).
  virtual std::vector<double> sampleTimes() const { return {}; }
  // Also observe at every output frame of the scene (output.fps).
  virtual bool everyFrame() const { return false; }
  // Also observe every N steps (0 = no).
  virtual std::uint64_t stepInterval() const { return 0; }
  virtual void observe(const run::Simulation& sim) = 0;
  // Called after the last step of a run that ended normally.
  virtual void finish(const run::Simulation& sim) { (void)sim; }
  // One value per column; NaN for "no value" (written as an empty CSV field).
  virtual std::vector<double> values() const = 0;
};

// Builds the metric a sweep's `metrics[index]` entry describes; throws InputError naming
// `file` and the key path for an unknown type or a bad option.
std::unique_ptr<SweepMetric> makeMetric(const nlohmann::json& config, const std::string& file,
                                        std::size_t index, const std::string& sweepFolder);

// The metric types makeMetric() knows ("surge_front", "density", "energy").
std::vector<std::string> metricTypes();

}  // namespace sph::sweep
