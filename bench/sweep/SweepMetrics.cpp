#include "bench/sweep/SweepMetrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

#include "io/scene/JsonReader.h"
#include "sim/run/Observables.h"

namespace sph::sweep {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string resolve(const std::string& folder, const std::string& path) {
  return path.empty() || path[0] == '/' ? path : folder + path;
}

// Dam break against Martin & Moyce (1952), Figure 3: the surge front Z = (max x - wall) / a at
// T = t sqrt(2 g / a), for the measured points with T <= max_T (tests/test_dam_break.cpp checks
// the same front). Columns: RMS and max of |Z - Z_ref| / Z_ref over those points, and their mean
// with sign (negative: the simulated front lags the experiment), in percent.
// Options for the gate study (docs/benchmarks.md, "The dam-break front: convergence, gate, walls
// and viscosity"):
//   time_offset  s: the experiment's clock started this long before the simulated column was let
//                go (a gate held shut that long, then gone): point k is compared with the
//                simulation at t_k - time_offset
//   edge         count the front at the water's edge, half a spacing ahead of the leading
//                particle's centre (what a photograph sees), not at the centre
//   per_point    one column per measured point: its signed deviation in percent
//   fit_offset   the time_offset in [-50, 100] ms that minimises the RMS, and that RMS, from the
//                front recorded after every step (linear between steps)
//   series       write the front after every step to PREFIX-front.csv (t, T, Z)
class SurgeFrontMetric : public SweepMetric {
 public:
  SurgeFrontMetric(io::scene::JsonReader& r, const std::string& folder) {
    const std::string path = resolve(folder, r.string("reference", std::nullopt));
    maxT_ = r.number("max_T", 3.0, "a positive number (dimensionless time)", io::scene::positive);
    fluid_ =
        static_cast<std::size_t>(r.number("fluid", 0.0, "an integer >= 0 (index in fluids[])",
                                          [](double v) { return v >= 0 && v == std::floor(v); }));
    offset_ = r.number("time_offset", 0.0, "a number of seconds in [0, 1]",
                       [](double v) { return v >= 0 && v <= 1; });
    edge_ = r.boolean("edge", false);
    perPoint_ = r.boolean("per_point", false);
    fit_ = r.boolean("fit_offset", false);
    series_ = r.boolean("series", false);
    std::ifstream in(path);
    if (!in) r.fail("reference", "cannot open " + path);
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#' || line[0] == 'T') continue;  // comments and the header
      double T = 0, Z = 0;
      char comma = 0;
      std::istringstream(line) >> T >> comma >> Z;
      if (comma == ',' && T <= maxT_) T_.push_back(T), Zref_.push_back(Z);
    }
    if (T_.empty()) r.fail("reference", path + ": no \"T,Z\" rows with T <= max_T");
  }

  std::vector<std::string> columns() const override {
    std::vector<std::string> c = {"front_rms_pct", "front_max_pct", "front_bias_pct"};
    if (perPoint_) {
      for (std::size_t k = 0; k < T_.size(); ++k)
        c.push_back("front_e" + std::to_string(k + 1) + "_pct");
    }
    if (fit_) c.insert(c.end(), {"front_fit_offset_ms", "front_fit_rms_pct"});
    return c;
  }

  void start(const run::Simulation& sim, const MetricContext& context) override {
    const scene::Scene& s = sim.scene();
    if (fluid_ >= s.fluids.size() || s.fluids[fluid_].shape != scene::FluidBlock::Shape::Box) {
      throw InputError(s.sourcePath + ": surge_front needs fluids[" + std::to_string(fluid_) +
                       "] to be the dam's box (the water column against the left wall)");
    }
    // The column the lattice holds: n = round(width / dx) particles wide (SceneSetup.cpp,
    // initialFluid), which is the box's width only when dx divides it.
    const double dx = s.solver.spacing;
    wall_ = s.fluids[fluid_].lo.x();
    a_ = dx * std::max(1L, std::lround((s.fluids[fluid_].hi.x() - wall_) / dx));
    shift_ = edge_ ? 0.5 * dx : 0.0;
    const double g = s.solver.gravity.norm();
    tScale_ = std::sqrt(2 * g / a_);
    times_.clear();
    for (double T : T_) times_.push_back(T / tScale_ - offset_);
    Z_.clear();
    seriesT_.clear(), seriesZ_.clear();
    recordStep(sim);
    // Points the experiment saw while the gate still held the column: the column at rest.
    while (Z_.size() < times_.size() && times_[Z_.size()] <= 1e-12) Z_.push_back(seriesZ_[0]);
    seriesPath_ = series_ ? context.seriesPrefix + "-front.csv" : "";
  }
  std::vector<double> sampleTimes() const override {
    std::vector<double> t;
    for (double x : times_)
      if (x > 1e-12) t.push_back(x);
    return t;
  }
  std::uint64_t stepInterval() const override { return fit_ || series_ ? 1 : 0; }
  void observe(const run::Simulation& sim) override {
    if (fit_ || series_) recordStep(sim);
    if (Z_.size() >= times_.size() || std::abs(sim.time() - times_[Z_.size()]) > 1e-9) return;
    Z_.push_back(front(sim));
  }
  void finish(const run::Simulation&) override {
    if (seriesPath_.empty()) return;
    std::ofstream out(seriesPath_);
    out << "t,T,Z\n";
    char line[96];
    for (std::size_t i = 0; i < seriesT_.size(); ++i) {
      std::snprintf(line, sizeof line, "%.9g,%.6g,%.6g\n", seriesT_[i], seriesT_[i] * tScale_,
                    seriesZ_[i]);
      out << line;
    }
  }
  std::vector<double> values() const override {
    std::vector<double> v;
    if (Z_.size() < Zref_.size()) {
      v.assign(columns().size(), kNaN);
      return v;
    }
    double sum = 0, worst = 0, bias = 0;
    std::vector<double> each;
    for (std::size_t k = 0; k < Z_.size(); ++k) {
      const double e = (Z_[k] - Zref_[k]) / Zref_[k];
      sum += e * e, worst = std::max(worst, std::abs(e)), bias += e;
      each.push_back(100 * e);
    }
    v = {100 * std::sqrt(sum / Z_.size()), 100 * worst, 100 * bias / Z_.size()};
    if (perPoint_) v.insert(v.end(), each.begin(), each.end());
    if (fit_) {
      const auto [offset, rms] = bestOffset();
      v.insert(v.end(), {1e3 * offset, 100 * rms});
    }
    return v;
  }

 private:
  double front(const run::Simulation& sim) const {
    return (run::surgeFront(sim.fluid()) + shift_ - wall_) / a_;
  }
  void recordStep(const run::Simulation& sim) {
    if (!seriesT_.empty() && sim.time() <= seriesT_.back()) return;  // a sample after its step
    seriesT_.push_back(sim.time()), seriesZ_.push_back(front(sim));
  }
  // The recorded front at time t (linear between steps; the initial front before the release);
  // NaN past the last step.
  double frontAt(double t) const {
    if (t <= seriesT_.front()) return seriesZ_.front();
    const auto it = std::lower_bound(seriesT_.begin(), seriesT_.end(), t);
    if (it == seriesT_.end()) return kNaN;
    const std::size_t j = static_cast<std::size_t>(it - seriesT_.begin());
    const double w = (t - seriesT_[j - 1]) / (seriesT_[j] - seriesT_[j - 1]);
    return seriesZ_[j - 1] + w * (seriesZ_[j] - seriesZ_[j - 1]);
  }
  // The time offset (s; 0.25 ms grid over [-50, 100] ms) whose RMS deviation is least.
  std::pair<double, double> bestOffset() const {
    double best = kNaN, bestRms = std::numeric_limits<double>::infinity();
    for (int i = -200; i <= 400; ++i) {
      const double d = 0.00025 * i;
      double sum = 0;
      for (std::size_t k = 0; k < T_.size(); ++k) {
        const double e = (frontAt(T_[k] / tScale_ - d) - Zref_[k]) / Zref_[k];
        sum += e * e;
      }
      const double rms = std::sqrt(sum / T_.size());
      if (rms < bestRms) best = d, bestRms = rms;  // NaN (past the run's end) never wins
    }
    return {best, std::isfinite(bestRms) ? bestRms : kNaN};
  }

  double maxT_ = 3, offset_ = 0;
  bool edge_ = false, perPoint_ = false, fit_ = false, series_ = false;
  std::size_t fluid_ = 0;
  std::vector<double> T_, Zref_;           // reference points
  std::vector<double> times_, Z_;          // their simulated times (s) and the measured fronts
  std::vector<double> seriesT_, seriesZ_;  // the front after every step (fit_offset, series)
  std::string seriesPath_;
  double wall_ = 0, a_ = 1, shift_ = 0, tScale_ = 1;
};

// Compression (rho - rho0) / rho0 of the fluid at every output frame, in percent: the mean over
// particles averaged over frames, and the largest value seen. Only compression counts: the
// density deficit of free-surface particles is the kernel's missing neighbours, not an error of
// the pressure solve, and would swamp the figure.
class DensityMetric : public SweepMetric {
 public:
  std::vector<std::string> columns() const override { return {"rho_mean_pct", "rho_max_pct"}; }
  void start(const run::Simulation&, const MetricContext&) override {
    sum_ = 0, worst_ = 0, frames_ = 0;
  }
  bool everyFrame() const override { return true; }
  void observe(const run::Simulation& sim) override {
    const run::DensityError e = run::densityError(sim.fluid(), sim.scene().solver.restDensity);
    sum_ += e.meanCompression, worst_ = std::max(worst_, e.maxCompression);
    ++frames_;
  }
  std::vector<double> values() const override {
    if (frames_ == 0) return {kNaN, kNaN};
    return {100 * sum_ / frames_, 100 * worst_};
  }

 private:
  double sum_ = 0, worst_ = 0;
  std::size_t frames_ = 0;
};

// Total energy of the fluid every N steps: kinetic, potential (above the lowest initial particle,
// half a spacing down: the floor it rests on) and the elastic energy the EOS stores, as the
// solver's forces see it (sum of m e(rho), e = integral of p / rho^2 d rho, scaled by the
// gradient correction that scales the pressure force). Writes the series to
// PREFIX-energy.csv; columns: drift of the total energy and of the mean density between the
// first sample after `settle` seconds and the last one.
class EnergyMetric : public SweepMetric {
 public:
  explicit EnergyMetric(io::scene::JsonReader& r) {
    every_ =
        static_cast<std::uint64_t>(r.number("every_steps", 100.0, "an integer >= 1",
                                            [](double v) { return v >= 1 && v == std::floor(v); }));
    settle_ = r.number("settle", 0.0, "a number >= 0 (s)", io::scene::nonNegative);
  }
  std::vector<std::string> columns() const override {
    return {"energy_drift_pct", "rho_drift_pct"};
  }
  void start(const run::Simulation& sim, const MetricContext& context) override {
    const Particles& p = sim.fluid();
    const Vec3 g = sim.scene().solver.gravity;
    floor_ = std::numeric_limits<double>::max();
    for (std::size_t i = 0; i < p.size(); ++i)
      floor_ = std::min(floor_, -static_cast<double>(p.position(i).dot(g)));
    if (p.empty()) floor_ = 0;
    floor_ -= 0.5 * sim.scene().solver.spacing * g.norm();
    settled_ = false;
    series_.close();
    series_.open(context.seriesPrefix + "-energy.csv");
    series_ << "step,time,kinetic,potential,elastic,total,mean_rho,max_rho,particles\n";
    sample(sim);
  }
  std::uint64_t stepInterval() const override { return every_; }
  void observe(const run::Simulation& sim) override { sample(sim); }
  void finish(const run::Simulation& sim) override {
    if (sim.stepCount() % every_ != 0) sample(sim);
    series_.close();
  }
  std::vector<double> values() const override {
    if (!settled_) return {kNaN, kNaN};
    return {100 * (last_.total - first_.total) / std::abs(first_.total),
            100 * (last_.meanRho - first_.meanRho) / first_.meanRho};
  }

 private:
  struct Sample {
    double total = 0, meanRho = 0;
  };

  void sample(const run::Simulation& sim) {
    const Particles& p = sim.fluid();
    const solver::DerivedParams& d = sim.params();
    const scene::SolverParams& s = sim.scene().solver;
    const double kinetic = run::kineticEnergy(p, d.mass);
    const double potential = run::potentialEnergy(p, d.mass, s.gravity, floor_);
    const double elastic = run::elasticEnergy(p, s, d.mass, d.stiffness) * sim.gradientCorrection();
    const run::DensityError density = run::densityError(p, s.restDensity);
    const double total = kinetic + potential + elastic;
    const double meanRho = density.meanDensity, rhoMax = density.maxDensity;
    char line[256];
    std::snprintf(line, sizeof line, "%llu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%zu\n",
                  static_cast<unsigned long long>(sim.stepCount()), sim.time(), kinetic, potential,
                  elastic, total, meanRho, rhoMax, p.size());
    series_ << line;
    if (sim.time() >= settle_ && sim.stepCount() > 0) {
      if (!settled_) first_ = {total, meanRho}, settled_ = true;
      last_ = {total, meanRho};
    }
  }

  std::uint64_t every_ = 100;
  double settle_ = 0, floor_ = 0;
  bool settled_ = false;
  Sample first_, last_;
  std::ofstream series_;
};

}  // namespace

std::vector<std::string> metricTypes() {
  return {"surge_front", "density", "energy"};
}

std::unique_ptr<SweepMetric> makeMetric(const nlohmann::json& config, const std::string& file,
                                        std::size_t index, const std::string& sweepFolder) {
  io::scene::JsonReader r(config, "metrics[" + std::to_string(index) + "]", file);
  const std::vector<std::string> types = metricTypes();
  const std::string type = r.string("type", std::nullopt, types);
  std::unique_ptr<SweepMetric> metric;
  if (type == "surge_front")
    metric = std::make_unique<SurgeFrontMetric>(r, sweepFolder);
  else if (type == "density")
    metric = std::make_unique<DensityMetric>();
  else
    metric = std::make_unique<EnergyMetric>(r);
  r.finish();
  return metric;
}

}  // namespace sph::sweep
