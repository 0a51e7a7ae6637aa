// The surge_front metric's gate-study options (bench/sweep/SweepMetrics.cpp): per-point signed
// deviations that add up to the RMS and the bias, the front at the water's edge half a spacing
// ahead of the centres, a time offset that compares the first points with the column at rest,
// and the best-fitting offset read from the front recorded after every step (also written as a
// CSV). A 5-particle-wide dam break (a / dx = 5), so each run takes a fraction of a second.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench/sweep/Sweep.h"
#include "bench/sweep/SweepMetrics.h"
#include "bench/sweep/SweepRunner.h"
#include "sim/InputError.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

// Martin & Moyce's first two points (T <= 1.3): T = 0.832, Z = 1.217 and T = 1.219, Z = 1.474.
const double kZref[] = {1.217, 1.474};

sweep::VariantResult runTiny(const std::string& options, const std::string& dir = "") {
  const std::string text =
      std::string(R"({"scene": {"solver": {"spacing": 0.0292, "end_time": 0.17},
      "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.146, 0.292, 0.0584]}],
      "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.584, 0.438, 0.0584]}],
      "output": {"fps": 60}}, "threads": 1,
    "metrics": [{"type": "surge_front", "reference": ")") +
      test::sourcePath("tests/data/martin_moyce_1952.csv") + R"(", "max_T": 1.3)" + options + "}]}";
  sweep::SweepRunOptions run;
  run.outputDir = dir.empty() ? std::filesystem::temp_directory_path().string() : dir;
  const sweep::SweepResult r = sweep::runSweep(sweep::parseSweep(text, "tiny.json"), run);
  EXPECT_EQ(r.rows.size(), 1u);
  EXPECT_EQ(r.rows[0].status, sweep::RunStatus::Stable);
  return r.rows[0];
}

TEST(SurgeFrontMetric, PerPointDeviationsMakeTheRmsAndTheBias) {
  const sweep::VariantResult v = runTiny(R"(, "per_point": true)");
  ASSERT_EQ(v.metrics.size(), 5u);  // rms, max, bias, e1, e2
  const double e1 = v.metrics[3], e2 = v.metrics[4];
  EXPECT_NEAR(v.metrics[0], std::sqrt((e1 * e1 + e2 * e2) / 2), 1e-9);
  EXPECT_NEAR(v.metrics[1], std::max(std::abs(e1), std::abs(e2)), 1e-9);
  EXPECT_NEAR(v.metrics[2], (e1 + e2) / 2, 1e-9);
  EXPECT_NE(e1, e2);
}

TEST(SurgeFrontMetric, EdgeMovesEveryPointHalfASpacingAhead) {
  const sweep::VariantResult centre = runTiny(R"(, "per_point": true)");
  const sweep::VariantResult edge = runTiny(R"(, "per_point": true, "edge": true)");
  // Same run (deterministic at 1 thread); Z grows by (dx / 2) / a = 0.1 at a / dx = 5.
  for (int k = 0; k < 2; ++k)
    EXPECT_NEAR(edge.metrics[3 + k] - centre.metrics[3 + k], 100 * 0.1 / kZref[k], 1e-4) << k;
}

TEST(SurgeFrontMetric, AGateHeldLongerThanAPointComparesTheColumnAtRest) {
  // T = 0.832 is t = 0.0718 s (a = 0.146 m): a gate held 80 ms still holds the column there, whose
  // leading centre is half a spacing inside it: Z = 1 - 0.1 = 0.9.
  const sweep::VariantResult v = runTiny(R"(, "per_point": true, "time_offset": 0.08)");
  EXPECT_NEAR(v.metrics[3], 100 * (0.9 - kZref[0]) / kZref[0], 1e-3);
  // The second point (t = 0.105 s) is compared with the run 25 ms after the release: the front
  // has moved, but less than without the gate.
  const sweep::VariantResult noGate = runTiny(R"(, "per_point": true)");
  EXPECT_GT(v.metrics[4], 100 * (0.9 - kZref[1]) / kZref[1]);
  EXPECT_LT(v.metrics[4], noGate.metrics[4]);
}

TEST(SurgeFrontMetric, FittedOffsetIsTheBestOnItsGridAndTheSeriesIsWritten) {
  const std::string dir =
      std::filesystem::temp_directory_path() / ("sphsplat-front-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const sweep::VariantResult v = runTiny(R"(, "fit_offset": true, "series": true)", dir);
  ASSERT_EQ(v.metrics.size(), 5u);  // rms, max, bias, offset (ms), its rms
  const double offsetMs = v.metrics[3], fitRms = v.metrics[4];
  EXPECT_LE(fitRms, v.metrics[0] + 1e-9);  // offset 0 is on the grid
  EXPECT_GE(offsetMs, -50);
  EXPECT_LE(offsetMs, 100);
  EXPECT_NEAR(4 * offsetMs, std::round(4 * offsetMs), 1e-6);  // on the 0.25 ms grid
  // A run with a gate held 10 ms lands on the shifted points exactly instead of interpolating
  // between steps; the fit cannot be worse than it by more than the front's motion in a step.
  const sweep::VariantResult shifted = runTiny(R"(, "time_offset": 0.01)");
  EXPECT_LE(fitRms, shifted.metrics[0] + 1.0);

  std::ifstream in(dir + "/variant-0-front.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,T,Z");
  int rows = 0;
  double lastT = -1, firstZ = 0, lastZ = 0;
  while (std::getline(in, line)) {
    double t = 0, T = 0, Z = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &T, &Z), 3) << line;
    EXPECT_GT(t, lastT);
    EXPECT_NEAR(T, t * std::sqrt(2 * 9.81 / 0.146), 1e-4 * (1 + T));
    if (rows++ == 0) firstZ = Z;
    lastT = t, lastZ = Z;
  }
  EXPECT_EQ(rows, static_cast<int>(v.steps) + 1);  // the start and every step
  EXPECT_NEAR(firstZ, 0.9, 1e-5);
  EXPECT_GT(lastZ, 1.5);  // the surge has moved by t = 0.17 s
  std::filesystem::remove_all(dir);
}

TEST(SurgeFrontMetric, BadOptionsNameTheKey) {
  const char* bad[][2] = {{"time_offset", "-1"}, {"edge", "1"}, {"fit_offset", "\"yes\""}};
  for (const auto& [key, value] : bad) {
    const nlohmann::json config =
        nlohmann::json::parse(std::string(R"({"type": "surge_front", "reference": ")") +
                              test::sourcePath("tests/data/martin_moyce_1952.csv") + "\", \"" +
                              key + "\": " + value + "}");
    try {
      sweep::makeMetric(config, "s.json", 0, "");
      ADD_FAILURE() << "accepted " << key << " = " << value;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("s.json: metrics[0].") + key),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace sph
