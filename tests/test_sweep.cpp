// `sphsplat bench` sweeps (bench/sweep/Sweep.h, SweepRunner.h, SweepReport.h): sweep files are
// checked like scenes, variants expand as documented, a blow-up is recorded where the guard stopped
// it, the Pareto front is the non-dominated set, and a sweep of two tiny variants leaves a
// well-formed CSV, table and PNG. Also the `quality` presets the dam-break sweep chose
// (docs/scene-format.md, "quality").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/sweep/Sweep.h"
#include "bench/sweep/SweepReport.h"
#include "bench/sweep/SweepRunner.h"
#include "io/scene/SceneLoader.h"
#include "sim/solver/SceneSetup.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

using sweep::SweepSpec;

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::vector<std::string>> readCsv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::string field;
    bool quoted = false;
    for (char c : line) {
      if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        fields.push_back(field), field.clear();
      else
        field += c;
    }
    fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

// A 5-particle-wide dam break (a / dx = 5): a few hundred particles, a fraction of a second.
const char* kTinyDamBreak = R"({
  "solver": {"spacing": 0.0292, "end_time": 0.12},
  "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.146, 0.292, 0.0584]}],
  "boundaries": [{"type": "tank", "min": [0, 0, 0], "max": [0.584, 0.438, 0.0584]}],
  "output": {"fps": 60}
})";

std::string tinySweep(const std::string& extra = "") {
  return std::string(R"({"name": "tiny", "scene": )") + kTinyDamBreak + R"(, "threads": 1,
    "axes": [{"key": "solver.cfl", "values": [0.4, 0.8]}],
    "metrics": [{"type": "surge_front", "reference": ")" +
         test::sourcePath("tests/data/martin_moyce_1952.csv") +
         R"(", "max_T": 1.3}, {"type": "density"}],
    "plot": {"x": "cpu_s", "y": "front_rms_pct"})" +
         extra + "}";
}

void expectInputError(const std::string& text, const std::string& expected) {
  try {
    sweep::parseSweep(text, "sweep.json");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(Sweep, BadSweepFilesNameTheKey) {
  expectInputError(R"({"axes": []})", "sweep.json: scene: missing");
  expectInputError(R"({"scene": "x.json", "axis": []})",
                   "sweep.json: axis: unknown key (did you mean \"axes\"?)");
  expectInputError(R"({"scene": "x.json", "axes": [{"key": "solver.cfl", "values": []}]})",
                   "sweep.json: axes[0].values: expected a non-empty array");
  expectInputError(R"({"scene": "x.json", "threads": 1.5})",
                   "sweep.json: threads: expected an integer");
  expectInputError(R"({"scene": "x.json", "set": ["solver.cfl"]})",
                   "sweep.json: set: expected \"KEY.PATH=VALUE\"");
  // The sweep file is user input as a scene is: it goes through the same JSON checks.
  expectInputError(
      "{\"scene\": \"x.json\", \"axes\": " + std::string(100, '[') + std::string(100, ']') + "}",
      "sweep.json:1:92: nested deeper than 64 levels");
  expectInputError("{\"scene\": \"x.json\",\n \"repeats\": 2, \"repeats\": 3}",
                   "sweep.json:2:16: duplicate key repeats (first given at 2:2)");
  expectInputError(R"({"scene": "x.json", "threads": 100000})",
                   "sweep.json: threads: expected an integer in [0, ");
  expectInputError(R"({"scene": "x.json", "repeats": 1e11})",
                   "sweep.json: repeats: expected an integer in [1, 1000]");
  expectInputError(R"({"scene": "x.json", "end_time": 1e300})",
                   "sweep.json: end_time: expected a positive number of at most 1e6 (s)");
  // Metrics are checked when the sweep runs, before the first variant.
  const SweepSpec spec = sweep::parseSweep(
      tinySweep().replace(tinySweep().find("\"density\""), 9, "\"densty\""), "s.json");
  EXPECT_THROW(sweep::runSweep(spec, {}), InputError);
}

TEST(Sweep, EveryShippedSweepFileAndEveryVariantSceneLoads) {
  // The commands in docs/benchmarks.md run these files: a renamed key must fail here, not there.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::sourcePath("bench/sweeps"))) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    ++files;
    const SweepSpec spec = sweep::loadSweep(entry.path().string());
    for (const sweep::SweepVariant& v : sweep::expandVariants(spec)) {
      SCOPED_TRACE(v.label + " " + v.caseLabel);
      EXPECT_NO_THROW(io::scene::parseScene(v.sceneText, v.scenePath, v.edits));
    }
  }
  EXPECT_GE(files, 10);
}

TEST(Sweep, VariantsAreCasesTimesAxesFirstAxisSlowest) {
  const SweepSpec spec =
      sweep::parseSweep(R"({"scene": {"solver": {"spacing": 0.1}}, "set": ["solver.end_time=0.5"],
    "axes": [{"key": "solver.spacing", "label": "dx", "values": [0.02, 0.01]},
             {"key": "solver.eos", "values": ["tait", "linear"]}],
    "cases": [{"label": "A", "set": ["solver.cfl=0.2"]}, {"label": "B"}]})",
                        "dir/s.json");
  const std::vector<sweep::SweepVariant> v = sweep::expandVariants(spec);
  ASSERT_EQ(v.size(), 8u);
  EXPECT_EQ(v[0].label, "A dx=0.02 eos=tait");
  EXPECT_EQ(v[1].label, "A dx=0.02 eos=linear");
  EXPECT_EQ(v[2].label, "A dx=0.01 eos=tait");
  EXPECT_EQ(v[4].label, "B dx=0.02 eos=tait");
  EXPECT_EQ(v[1].edits, (std::vector<std::string>{"solver.end_time=0.5", "solver.cfl=0.2",
                                                  "solver.spacing=0.02", "solver.eos=linear"}));
  EXPECT_EQ(v[5].edits, (std::vector<std::string>{"solver.end_time=0.5", "solver.spacing=0.02",
                                                  "solver.eos=linear"}));
  EXPECT_EQ(v[1].axisValues, (std::vector<std::string>{"0.02", "linear"}));
  EXPECT_EQ(v[0].scenePath, "dir/s.json#scene");
  // A collision section as an axis value reads as its method.
  EXPECT_EQ(sweep::shortValue(nlohmann::json::parse(R"({"method": "exact", "range": 0.01})")),
            "exact");
  EXPECT_EQ(sweep::editValue(nlohmann::json::parse(R"({"method": "exact"})")),
            R"({"method":"exact"})");
}

TEST(Sweep, ParetoFrontIsTheNonDominatedStableRows) {
  sweep::SweepResult r;
  r.metricColumns = {"err"};
  const double rows[][2] = {{1, 10}, {2, 5}, {3, 6}, {4, 1}, {0.5, 20}, {2, 5}};
  for (const auto& xy : rows) {
    sweep::VariantResult v;
    v.wallSeconds = xy[0];
    v.metrics = {xy[1]};
    r.rows.push_back(v);
  }
  r.rows[4].status = sweep::RunStatus::Guard;  // fastest, but it blew up: not on the front
  const std::vector<bool> front = sweep::paretoFront(r, "wall_s", "err");
  EXPECT_EQ(front, (std::vector<bool>{true, true, false, true, false, true}));
}

TEST(Sweep, ABlowUpIsRecordedWithTheGuardStep) {
  // No walls and a domain that ends 5 cm below the water: it falls out, the guard stops it.
  const SweepSpec spec = sweep::parseSweep(R"({"scene": {"solver": {"spacing": 0.02, "end_time": 1},
      "domain": {"min": [-0.1, -0.05, -0.1], "max": [0.2, 0.2, 0.2]},
      "fluids": [{"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}]}, "threads": 1,
    "metrics": [{"type": "density"}]})",
                                           "s.json");
  const sweep::SweepResult result = sweep::runSweep(spec, {});
  ASSERT_EQ(result.rows.size(), 1u);
  const sweep::VariantResult& v = result.rows[0];
  EXPECT_EQ(v.status, sweep::RunStatus::Guard);
  // Free fall from 1 cm (the lowest particle centre) to -5 cm takes sqrt(2 0.06 / g) = 0.11 s.
  EXPECT_NEAR(v.guardTime, 0.11, 0.01);
  EXPECT_EQ(v.guardStep, v.steps);
  EXPECT_NE(v.message.find("left the domain"), std::string::npos) << v.message;
  ASSERT_EQ(v.metrics.size(), 2u);
  EXPECT_TRUE(std::isnan(v.metrics[0]));  // no error figure for a run that blew up
}

TEST(Sweep, TwoTinyVariantsWriteCsvTableAndPlot) {
  const std::string dir =
      std::filesystem::temp_directory_path() / ("sphsplat-sweep-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  const std::string sweep = test::writeTempFile(tinySweep());
  const auto r = test::runSphsplat("bench " + sweep + " --output " + dir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("[2/2] cfl=0.8: stable"), std::string::npos) << r.output;

  const auto csv = readCsv(dir + "/tiny.csv");
  ASSERT_EQ(csv.size(), 3u);  // header + 2 variants
  const std::vector<std::string>& header = csv[0];
  auto column = [&](const std::string& name) {
    for (std::size_t c = 0; c < header.size(); ++c)
      if (header[c] == name) return c;
    ADD_FAILURE() << "no column " << name;
    return std::size_t(0);
  };
  int onFront = 0;
  for (std::size_t row = 1; row < csv.size(); ++row) {
    ASSERT_EQ(csv[row].size(), header.size()) << "row " << row;
    EXPECT_EQ(csv[row][column("status")], "stable");
    EXPECT_EQ(csv[row][column("cfl")], row == 1 ? "0.4" : "0.8");
    EXPECT_GT(std::stod(csv[row][column("wall_s")]), 0);
    EXPECT_GT(std::stoi(csv[row][column("steps")]), 50);
    EXPECT_EQ(csv[row][column("particles")], "100");  // 5 wide (a / dx = 5), 10 high, 2 deep
    const double front = std::stod(csv[row][column("front_rms_pct")]);
    EXPECT_TRUE(front >= 0 && front < 50) << front;  // two points, T = 0.83 and 1.22
    EXPECT_LE(std::abs(std::stod(csv[row][column("front_bias_pct")])),
              front + 1e-6);                                                // |mean| <= RMS
    EXPECT_GE(std::stod(csv[row][column("front_max_pct")]), front - 1e-6);  // max >= RMS
    EXPECT_GE(std::stod(csv[row][column("rho_max_pct")]),
              std::stod(csv[row][column("rho_mean_pct")]));
    onFront += csv[row][column("pareto")] == "1";
  }
  EXPECT_GE(onFront, 1);
  // The CFL step halves the steps; the front barely moves (same physics).
  EXPECT_LT(std::stoi(csv[2][column("steps")]), std::stoi(csv[1][column("steps")]));

  const std::string md = readText(dir + "/tiny.md");
  EXPECT_NE(
      md.find(
          "| cfl | what happened | particles | steps | wall s | cpu s | ms/step | front_rms_pct"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("Command: `sphsplat bench " + sweep), std::string::npos) << md;
  EXPECT_NE(md.find("Machine: "), std::string::npos);
  EXPECT_NE(md.find("| 0.8 | stable | 100 |"), std::string::npos) << md;

  if (std::system("/usr/bin/python3 -c 'import matplotlib' 2>/dev/null") != 0) {
    GTEST_SKIP()
        << "no matplotlib for /usr/bin/python3 (scripts/setup installs python3-matplotlib)";
  }
  const std::string png = readText(dir + "/tiny.png");
  ASSERT_GT(png.size(), 5000u) << r.output;
  EXPECT_EQ(png.substr(1, 3), "PNG");
  std::filesystem::remove_all(dir);
}

// The presets (docs/scene-format.md, "quality"): "fast" takes larger steps with a softer EOS,
// "accurate" is DFSPH at its own step margin; an explicit key in the scene wins.
TEST(QualityPresets, ParseAndDifferAsDocumented) {
  const std::string base =
      R"({"solver": {"spacing": 0.01}, "fluids": [{"min": [0,0,0], "max": [0.1,0.1,0.1]}]})";
  // What the factors do: the automatic speed of sound is factor x the scene's speed bound.
  const float bound = solver::expectedMaxSpeed(io::scene::parseScene(base, "s.json"));
  const scene::Scene plain = io::scene::parseScene(base, "s.json");
  const scene::Scene fast = io::scene::parseScene(base, "s.json", {"quality=fast"});
  const scene::Scene accurate = io::scene::parseScene(base, "s.json", {"quality=accurate"});
  EXPECT_FLOAT_EQ(plain.solver.cfl, 0.4f);
  EXPECT_FLOAT_EQ(plain.solver.soundSpeedFactor, 10.0f);
  EXPECT_FLOAT_EQ(fast.solver.cfl, 0.8f);
  EXPECT_FLOAT_EQ(fast.solver.soundSpeedFactor, 5.0f);
  EXPECT_EQ(accurate.solver.pressure, scene::PressureSolver::Dfsph);
  EXPECT_EQ(plain.solver.pressure, scene::PressureSolver::Wcsph);
  EXPECT_EQ(fast.solver.pressure, scene::PressureSolver::Wcsph);
  EXPECT_FLOAT_EQ(accurate.solver.cfl, 0.3f);
  EXPECT_FLOAT_EQ(accurate.solver.soundSpeedFactor, 10.0f);
  // Its DFSPH solve for those steps (io/scene/SimulationSections.cpp, accurateDfsph()), against
  // the plain DFSPH's.
  const scene::SolverParams dfsph =
      io::scene::parseScene(base, "s.json", {"solver.pressure=dfsph"}).solver;
  EXPECT_FLOAT_EQ(dfsph.cfl, 0.2f);
  EXPECT_FLOAT_EQ(accurate.solver.densityWarmStart, 0.8f);
  EXPECT_FLOAT_EQ(dfsph.densityWarmStart, 0.5f);
  EXPECT_EQ(accurate.solver.densitySolve, scene::DensitySolve::Projected);
  EXPECT_EQ(dfsph.densitySolve, scene::DensitySolve::Increments);
  EXPECT_EQ(accurate.solver.viscosityForm, scene::ViscosityForm::Monaghan);
  EXPECT_EQ(dfsph.viscosityForm, scene::ViscosityForm::Laplacian);
  EXPECT_EQ(accurate.solver.minDivergenceIterations, 0);
  EXPECT_EQ(dfsph.minDivergenceIterations, 1);
  EXPECT_EQ(accurate.solver.minDensityIterations, 1);
  EXPECT_EQ(dfsph.minDensityIterations, 2);
  EXPECT_FLOAT_EQ(accurate.solver.maxDensityError, 0.045f);
  EXPECT_FLOAT_EQ(dfsph.maxDensityError, 0.05f);
  // Each of them a key the scene may give.
  const scene::SolverParams given =
      io::scene::parseScene(
          base, "s.json",
          {"quality=accurate", "solver.density_warm_start=0.5", "solver.density_solve=increments",
           "solver.viscosity_form=laplacian", "solver.min_divergence_iterations=1",
           "solver.min_density_iterations=2", "solver.max_density_error=0.05"})
          .solver;
  EXPECT_FLOAT_EQ(given.densityWarmStart, 0.5f);
  EXPECT_EQ(given.densitySolve, scene::DensitySolve::Increments);
  EXPECT_EQ(given.viscosityForm, scene::ViscosityForm::Laplacian);
  EXPECT_EQ(given.minDivergenceIterations, 1);
  EXPECT_EQ(given.minDensityIterations, 2);
  EXPECT_FLOAT_EQ(given.maxDensityError, 0.05f);
  EXPECT_NEAR(solver::deriveParams(fast).speedOfSound, 5 * bound, 1e-3 * bound);
  EXPECT_NEAR(solver::deriveParams(plain).speedOfSound, 10 * bound, 1e-3 * bound);
  EXPECT_NEAR(solver::deriveParams(accurate).speedOfSound, 10 * bound, 1e-3 * bound);
  // The preset's solver can be overridden like any key.
  EXPECT_EQ(io::scene::parseScene(base, "s.json", {"quality=accurate", "solver.pressure=wcsph"})
                .solver.pressure,
            scene::PressureSolver::Wcsph);
  // "default" is the built-in values.
  EXPECT_FLOAT_EQ(io::scene::parseScene(base, "s.json", {"quality=default"}).solver.cfl,
                  plain.solver.cfl);
  // Explicit keys win.
  const scene::Scene mixed =
      io::scene::parseScene(base, "s.json", {"quality=fast", "solver.cfl=0.3"});
  EXPECT_FLOAT_EQ(mixed.solver.cfl, 0.3f);
  EXPECT_FLOAT_EQ(mixed.solver.soundSpeedFactor, 5.0f);
  const scene::Scene explicitC =
      io::scene::parseScene(base, "s.json", {"quality=fast", "solver.speed_of_sound=40"});
  EXPECT_FLOAT_EQ(explicitC.solver.speedOfSound, 40.0f);

  EXPECT_THROW(io::scene::parseScene(base, "s.json", {"quality=medium"}), InputError);
  EXPECT_THROW(io::scene::parseScene(
                   base, "s.json", {"solver.speed_of_sound=40", "solver.speed_of_sound_factor=5"}),
               InputError);
  EXPECT_THROW(io::scene::parseScene(base, "s.json", {"solver.speed_of_sound_factor=0.5"}),
               InputError);
}

}  // namespace
}  // namespace sph
