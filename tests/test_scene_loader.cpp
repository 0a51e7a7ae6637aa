// Every class of bad scene is refused before anything runs, with one line naming the file, the
// JSON path of the bad key and what was expected. The shipped scenes load.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "io/scene/SceneLoader.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

const char* kMinimal = R"({"solver": {"spacing": 0.01},
  "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}]})";

// The message of the InputError that parsing `text` throws ("" if none).
std::string errorOf(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    io::scene::parseScene(text, "bad.json", overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneLoader, LoadsEveryShippedScene) {
  for (const char* name :
       {"dam_break", "still_tank", "pour", "jug_pour", "rain_pour", "rain_fill"}) {
    const scene::Scene s = test::shippedScene(name);
    EXPECT_EQ(s.name, name);
    EXPECT_GT(s.solver.spacing, 0.0f);
    EXPECT_FALSE(s.domain.empty());
    EXPECT_EQ(s.sourcePath, test::sourcePath(std::string("scenes/") + name + ".json"));
  }
}

TEST(SceneLoader, MinimalSceneGetsDocumentedDefaults) {
  const scene::Scene s = io::scene::parseScene(kMinimal, "min.json");
  EXPECT_EQ(s.name, "min");
  EXPECT_EQ(s.solver.support, 2.0f);
  EXPECT_EQ(s.solver.restDensity, 1000.0f);
  EXPECT_EQ(s.solver.eos, scene::EquationOfState::Tait);
  EXPECT_EQ(s.solver.densityKernel, scene::DensityKernel::Spiky);
  EXPECT_EQ(s.solver.cfl, 0.4f);
  EXPECT_EQ(s.solver.gravity, Vec3(0, -9.81f, 0));
  EXPECT_TRUE(s.solver.noSlipWalls);
  EXPECT_EQ(s.output.fps, 30.0);
  EXPECT_FALSE(s.camera.has_value());
}

TEST(SceneLoader, UnknownKeyNamesItsPathAndSuggestsTheNearMiss) {
  const std::string e = errorOf(R"({"solver": {"spacing": 0.01, "spacng": 2},
    "fluids": [{"min": [0,0,0], "max": [1,1,1]}]})");
  EXPECT_NE(e.find("bad.json: solver.spacng: unknown key (did you mean \"spacing\"?)"),
            std::string::npos)
      << e;
  const std::string top = errorOf(R"({"solver": {"spacing": 0.01}, "fluid": []})");
  EXPECT_NE(top.find("bad.json: fluid: unknown key (did you mean \"fluids\"?)"), std::string::npos)
      << top;
}

TEST(SceneLoader, WrongTypeNamesTheKeyAndWhatWasExpected) {
  const std::string e = errorOf(R"({"solver": {"spacing": "fine"}, "fluids": []})");
  EXPECT_EQ(e,
            "bad.json: solver.spacing: expected a positive number of at most 1000 (m), got the "
            "string \"fine\"");
  const std::string v = errorOf(R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0,0], "max": [1,1,1]}]})");
  EXPECT_EQ(v, "bad.json: fluids[0].min: expected 3 numbers (m) [x, y, z], got the array [0,0]");
}

TEST(SceneLoader, RenderSolidsChooseHowWallsAreDrawn) {
  const std::string camera = R"(, "camera": {"position": [0, 1, 1], "target": [0, 0, 0]})";
  auto with = [&](const std::string& render) {
    std::string text = kMinimal;
    text.insert(text.rfind('}'), camera + R"(, "render": )" + render);
    return text;
  };
  EXPECT_EQ(io::scene::parseScene(with("{}"), "s.json").render->solids,
            scene::RenderSolids::Points);
  EXPECT_EQ(io::scene::parseScene(with(R"({"solids": "opaque"})"), "s.json").render->solids,
            scene::RenderSolids::Opaque);
  EXPECT_EQ(io::scene::parseScene(with(R"({"show_boundary": false})"), "s.json").render->solids,
            scene::RenderSolids::None);
  EXPECT_NE(errorOf(with(R"({"solids": "glass"})")).find("render.solids"), std::string::npos);
}

// The `lights` section (seed 004): defaults, an emitter, and every bad key refused with its path.
TEST(SceneLoader, LightsSectionIsReadAndValidated) {
  auto with = [&](const std::string& lights) {
    std::string text = kMinimal;
    text.insert(text.rfind('}'), R"(, "lights": )" + lights);
    return text;
  };
  const std::string volume = R"("volume": {"min": [-1, -1, -1], "voxel_size": 0.25, "voxels": 8})";
  EXPECT_FALSE(io::scene::parseScene(kMinimal, "s.json").lights.has_value())
      << "no section, no lights";
  const scene::Scene s = io::scene::parseScene(with("{" + volume + "}"), "s.json");
  ASSERT_TRUE(s.lights);
  EXPECT_EQ(s.lights->source, scene::LightSource::Fluid);
  // Race-free by default: atomic on a GPU, cpu where GL draws in software (LightVolume decides).
  EXPECT_EQ(s.lights->accumulate, scene::LightAccumulate::Auto);
  EXPECT_TRUE(s.lights->cull) << "culled to the view by default";
  EXPECT_EQ(s.lights->filter, scene::LightFilter::Trilinear);
  EXPECT_EQ(s.lights->voxels, (std::array<int, 3>{8, 8, 8}));
  EXPECT_FLOAT_EQ(s.lights->extent().x(), 2.0f);
  const scene::Scene e = io::scene::parseScene(
      with(R"({"source": "emitter", "emitter": {"min": [0, 0, 0], "max": [1, 1, 1], "count": 64},
               "filter": "tricubic", "tension": 0.5, "accumulate": "paper", "oversampling": 2,
               "attenuation": [1, 0.5, 2], "range": 0.7, "volume": {"min": [0, 0, 0],
               "voxel_size": 0.1, "voxels": [10, 12, 14]}})"),
      "s.json");
  EXPECT_EQ(e.lights->emitter.count, 64u);
  EXPECT_EQ(e.lights->filter, scene::LightFilter::Tricubic);
  EXPECT_FLOAT_EQ(e.lights->tension, 0.5f);
  EXPECT_EQ(e.lights->accumulate, scene::LightAccumulate::Paper);
  EXPECT_EQ(e.lights->voxels, (std::array<int, 3>{10, 12, 14}));
  EXPECT_FLOAT_EQ(e.lights->attenuation[2], 2.0f);
  const scene::Scene c = io::scene::parseScene(
      with(R"({"accumulate": "cpu", "cull": false, )" + volume + "}"), "s.json");
  EXPECT_EQ(c.lights->accumulate, scene::LightAccumulate::Cpu);
  EXPECT_FALSE(c.lights->cull);
  // lights.shade: "auto" by default (LightVolume decides); "cpu" takes the volume onto the CPU.
  EXPECT_EQ(s.lights->shade, scene::LightShade::Auto);
  const scene::Scene sc = io::scene::parseScene(
      with(R"({"shade": "cpu", "pipeline": "deferred", "filter": "nearest", )" + volume + "}"),
      "s.json");
  EXPECT_EQ(sc.lights->shade, scene::LightShade::Cpu);
  EXPECT_EQ(sc.lights->accumulate, scene::LightAccumulate::Cpu) << "auto: the volume on the CPU";
  const std::pair<std::string, std::string> bad[] = {
      {R"({"source": "rain", )" + volume + "}", "lights.source"},
      {R"({"source": "emitter", )" + volume + "}", "lights.emitter"},
      {R"({"emitter": {}, )" + volume + "}", "lights.emitter"},
      {R"({"attenuation": [0, 1, 1], )" + volume + "}", "lights.attenuation"},
      {R"({"attenuation": [1, -1, 1], )" + volume + "}", "lights.attenuation"},
      {R"({"range": 0, )" + volume + "}", "lights.range"},
      {R"({"filter": "bicubic", )" + volume + "}", "lights.filter"},
      {R"({"tension": 0.5, )" + volume + "}", "lights.tension"},
      {R"({"filter": "tricubic", "tension": 2, )" + volume + "}", "lights.tension"},
      {R"({"oversampling": 9, )" + volume + "}", "lights.oversampling"},
      {R"({"accumulate": "racy", )" + volume + "}", "lights.accumulate"},
      {R"({"cull": "view", )" + volume + "}", "lights.cull"},
      {R"({"shade": "gpu", )" + volume + "}", "lights.shade"},
      {R"({"shade": "cpu", )" + volume + "}", "lights.shade"},  // forward
      {R"({"shade": "cpu", "pipeline": "deferred", "accumulate": "atomic", )" + volume + "}",
       "lights.shade"},
      {R"({"shade": "cpu", "pipeline": "deferred", "filter": "tricubic", )" + volume + "}",
       "lights.shade"},
      {R"({"colour": [2, 0, 0], )" + volume + "}", "lights.colour"},
      {R"({"fast_speed": 2, )" + volume + "}", "lights.fast_speed"},
      {R"({"volume": {"min": [0, 0, 0], "voxel_size": 1, "voxels": 0}})", "lights.volume.voxels"},
      {R"({"volume": {"min": [0, 0, 0], "voxel_size": 1, "voxels": [4, 4]}})",
       "lights.volume.voxels"},
      {R"({"volume": {"min": [0, 0, 0], "voxel_size": -1, "voxels": 4}})",
       "lights.volume.voxel_size"},
      {R"({"volume": {"min": [0, 0, 0], "voxel_size": 1, "voxels": 512}})", "lights.volume.voxels"},
      {R"({})", "lights.volume"},
      {R"({"colour_by": "speed", "glow": 1, )" + volume + "}", "lights.glow"},
  };
  for (const auto& [lights, key] : bad) {
    const std::string m = errorOf(with(lights));
    EXPECT_NE(m.find(key), std::string::npos) << lights << " -> " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  // 512^3 is 5 GiB with the atomic sums: the message names the size and the key to change.
  const std::string big =
      errorOf(with(R"({"volume": {"min": [0, 0, 0], "voxel_size": 1, "voxels": 512}})"));
  EXPECT_NE(big.find("512 x 512 x 512"), std::string::npos) << big;
  EXPECT_NE(big.find("max_memory_mib"), std::string::npos) << big;
}

TEST(SceneLoader, NegativeSpacingIsRefused) {
  const std::string e = errorOf(kMinimal, {"solver.spacing=-0.01"});
  EXPECT_EQ(e,
            "bad.json: solver.spacing: expected a positive number of at most 1000 (m), got -0.01");
}

TEST(SceneLoader, FluidOutsideTheDomainIsRefused) {
  const std::string e = errorOf(R"({"solver": {"spacing": 0.01},
    "domain": {"min": [0,0,0], "max": [1,1,1]},
    "fluids": [{"min": [0.5,0.5,0.5], "max": [1.5,0.6,0.6]}]})");
  EXPECT_NE(e.find("bad.json: fluids[0]: fluid outside the domain"), std::string::npos) << e;
}

TEST(SceneLoader, ZeroSizeEmitterIsRefused) {
  const std::string e = errorOf(R"({"solver": {"spacing": 0.01},
    "emitters": [{"position": [0,1,0], "direction": [0,-1,0], "radius": 0.001, "speed": 1}]})");
  EXPECT_NE(e.find("bad.json: emitters[0].radius: expected a nozzle radius of at least half the "
                   "particle spacing"),
            std::string::npos)
      << e;
  const std::string d = errorOf(R"({"solver": {"spacing": 0.01},
    "emitters": [{"position": [0,1,0], "direction": [0,0,0], "radius": 0.02, "speed": 1}]})");
  EXPECT_EQ(d, "bad.json: emitters[0].direction: expected a non-zero vector, got [0, 0, 0]");
}

TEST(SceneLoader, SceneWithoutFluidIsRefused) {
  EXPECT_NE(
      errorOf(R"({"solver": {"spacing": 0.01}})").find("bad.json: fluids: the scene has no fluid"),
      std::string::npos);
}

TEST(SceneLoader, MissingAndUnreadableFilesAreRefused) {
  try {
    io::scene::loadScene("/nonexistent/scene.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "/nonexistent/scene.json: cannot open the scene file (No such file or directory)");
  }
}

TEST(SceneLoader, InvalidJsonNamesLineAndColumn) {
  const std::string e = errorOf("{\n  \"solver\": {\"spacing\": 0.01,}\n}");
  EXPECT_EQ(e.rfind("bad.json:2:", 0), 0u) << e;
  EXPECT_NE(e.find("invalid JSON"), std::string::npos) << e;
}

TEST(SceneLoader, OverridesEditNestedKeysAndArrays) {
  const scene::Scene s = io::scene::parseScene(
      kMinimal, "min.json", {"solver.cfl=0.2", "fluids[0].velocity=[1,0,0]", "name=custom"});
  EXPECT_EQ(s.solver.cfl, 0.2f);
  EXPECT_EQ(s.fluids[0].velocity, Vec3(1, 0, 0));
  EXPECT_EQ(s.name, "custom");
  EXPECT_NE(errorOf(kMinimal, {"fluids[3].velocity=[1,0,0]"}).find("index 3 is out of range"),
            std::string::npos);
  EXPECT_NE(errorOf(kMinimal, {"nonsense"}).find("expected KEY.PATH=VALUE"), std::string::npos);
}

// --set key paths are read strictly: read loosely (stoul) they gave "internal error" for a long
// index, index 0 for "0.5", accepted "solver..spacing" and wrapped -1 to 18446744073709551615.
TEST(SceneLoader, SetKeyPathsAreStrict) {
  auto set = [](const std::string& edit) { return errorOf(kMinimal, {edit}); };
  EXPECT_EQ(set("fluids[99999999999999999999].min=[0,0,0]"),
            "--set fluids[99999999999999999999].min: expected an array index 0, 1, 2, ... inside "
            "[ ], got '99999999999999999999'");
  EXPECT_EQ(set("fluids[0.5].min=[0,0,0]"),
            "--set fluids[0.5].min: expected an array index 0, 1, 2, ... inside [ ], got '0.5'");
  EXPECT_EQ(set("fluids[-1].min=[0,0,0]"),
            "--set fluids[-1].min: expected an array index 0, 1, 2, ... inside [ ], got '-1'");
  EXPECT_EQ(set("solver..spacing=0.02"),
            "--set solver..spacing: empty key before '.'; expected KEY.PATH such as "
            "solver.spacing or fluids[0].min");
  EXPECT_EQ(set("solver.=0.02"), "--set solver.: a key path cannot end with '.'");
  EXPECT_EQ(set(".solver=0.02").rfind("--set .solver: empty key before '.'", 0), 0u);
  EXPECT_EQ(set("fluids[0]x=1"), "--set fluids[0]x: expected '.' or '[' after ']'");
  EXPECT_EQ(set("fluids[1].min=[0,0,0]"),
            "bad.json: --set fluids[1].min: index 1 is out of range (the array has 1 entries)");
  // A value nested too deep, or with a duplicate key, is refused rather than taken as a string.
  EXPECT_EQ(set("solver=" + std::string(100, '[')).rfind("--set solver:1:65: nested deeper", 0),
            0u);
  EXPECT_EQ(set("solver={\"spacing\": 0.01, \"spacing\": 0.02}")
                .rfind("--set solver:1:19: duplicate key spacing (first given at 1:2)", 0),
            0u);
  // A long key is quoted short (the rest of the line is the solver's ~30 known keys).
  const std::string longKey = errorOf(kMinimal, {"solver." + std::string(100000, 'k') + "=1"});
  EXPECT_LT(longKey.size(), 600u) << longKey.substr(0, 600);
  EXPECT_NE(longKey.find("unknown key"), std::string::npos);
}

// JSON parsers keep one of two equal keys silently: a second "solver" replaced the whole first.
TEST(SceneLoader, DuplicateKeysAreRefusedWithTheirPathAndLine) {
  EXPECT_EQ(errorOf("{\"solver\": {\"spacing\": 0.01},\n\"solver\": {\"cfl\": 0.3},\n"
                    "\"fluids\": [{\"min\": [0,0,0], \"max\": [0.1,0.1,0.1]}]}"),
            "bad.json:2:1: duplicate key solver (first given at 1:2); expected each key once "
            "(JSON keeps only one of the two)");
  EXPECT_EQ(errorOf("{\"solver\": {\"spacing\": 0.01}, \"fluids\": [{\"min\": [0,0,0],\n"
                    "  \"max\": [0.1,0.1,0.1], \"max\": [0.2,0.2,0.2]}]}")
                .rfind("bad.json:2:25: duplicate key fluids[0].max (first given at 2:3)", 0),
            0u);
}

// Numbers are bounded by what a run can use, and the messages print them readably: unbounded,
// output.fps = 1e308 crawled at 1e-304 s a step, and messages overflowed ("-9223372036854775808
// particles", 300-digit limits).
TEST(SceneLoader, WallPressureChoicesFollowTheSolver) {
  EXPECT_EQ(errorOf(kMinimal, {"solver.wall_pressure=none"}),
            "bad.json: solver.wall_pressure: expected \"extrapolated\" or \"summation\" with "
            "\"pressure\": \"wcsph\"");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.wall_pressure=summation"}),
            "bad.json: solver.wall_pressure: expected \"extrapolated\" or \"none\" with "
            "\"pressure\": \"dfsph\"");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.wall_pressure=none"}), "");
  EXPECT_EQ(errorOf(kMinimal, {"solver.wall_pressure=summation"}), "");
  EXPECT_EQ(errorOf(kMinimal, {"solver.wall_pressure=extrapolated"}), "");
  const std::string bad = errorOf(kMinimal, {"solver.pressure=dfsph", "solver.wall_pressure=x"});
  EXPECT_NE(bad.find("solver.wall_pressure"), std::string::npos) << bad;
  EXPECT_NE(bad.find("extrapolated"), std::string::npos) << bad;
}

// A support under 1.5 spacings leaves a particle at rest its six nearest neighbours or none.
TEST(SceneLoader, SupportHoldsMoreThanTheNearestNeighbours) {
  EXPECT_EQ(errorOf(kMinimal, {"solver.support=1.5"}), "");
  EXPECT_EQ(errorOf(kMinimal, {"solver.support=4"}), "");
  EXPECT_EQ(errorOf(kMinimal, {"solver.support=1.2"}),
            "bad.json: solver.support: expected a number in [1.5, 4] (kernel support radius / "
            "spacing), got 1.2");
}

TEST(SceneLoader, SettleIsSecondsBeforeTheStart) {
  EXPECT_EQ(io::scene::parseScene(kMinimal, "s.json").settle, 0.0);
  EXPECT_EQ(errorOf(kMinimal, {"settle=20"}), "");
  EXPECT_EQ(errorOf(kMinimal, {"settle=-1"}),
            "bad.json: settle: expected a number of seconds in [0, 1e4], got -1");
}

TEST(SceneLoader, DensityRelaxationAndWarmStartAreSharesForDfsphOnly) {
  const scene::SolverParams defaults = io::scene::parseScene(kMinimal, "s.json").solver;
  EXPECT_EQ(defaults.densityRelaxation, 1.0f);
  EXPECT_EQ(defaults.densityWarmStart, 0.5f);
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_relaxation=0.5",
                               "solver.density_warm_start=0.8"}),
            "");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_warm_start=0"}), "");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_warm_start=1"}),
            "bad.json: solver.density_warm_start: expected a number in [0, 1), got 1");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_warm_start=-0.1"}),
            "bad.json: solver.density_warm_start: expected a number in [0, 1), got -0.1");
  EXPECT_EQ(errorOf(kMinimal, {"solver.density_warm_start=0.5"}),
            "bad.json: solver.density_warm_start: only used with \"pressure\": \"dfsph\"");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_relaxation=0.5"}), "");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_relaxation=0"}),
            "bad.json: solver.density_relaxation: expected a number in (0, 1], got 0");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_relaxation=1.5"}),
            "bad.json: solver.density_relaxation: expected a number in (0, 1], got 1.5");
  EXPECT_EQ(errorOf(kMinimal, {"solver.density_relaxation=0.5"}),
            "bad.json: solver.density_relaxation: only used with \"pressure\": \"dfsph\"");
}

TEST(SceneLoader, DensityMomentumAfterIsAnIterationCountForDfsphOnly) {
  const auto dfsph = [](const std::string& edit) {
    return io::scene::parseScene(kMinimal, "s.json", {"solver.pressure=dfsph", edit}).solver;
  };
  EXPECT_EQ(io::scene::parseScene(kMinimal, "s.json").solver.densityMomentumAfter, 4);
  EXPECT_EQ(dfsph("solver.density_momentum_after=0").densityMomentumAfter, 0);
  EXPECT_EQ(dfsph("solver.density_momentum_after=100").densityMomentumAfter, 100);
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_momentum_after=2.5"}),
            "bad.json: solver.density_momentum_after: expected an integer in [0, 10000], got 2.5");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_momentum_after=-1"}),
            "bad.json: solver.density_momentum_after: expected an integer in [0, 10000], got -1");
  EXPECT_EQ(errorOf(kMinimal, {"solver.density_momentum_after=8"}),
            "bad.json: solver.density_momentum_after: only used with \"pressure\": \"dfsph\"");
}

TEST(SceneLoader, DensitySolveIsIncrementsOrProjectedForDfsphOnly) {
  const auto dfsph = [](const std::string& edit) {
    return io::scene::parseScene(kMinimal, "s.json", {"solver.pressure=dfsph", edit}).solver;
  };
  EXPECT_EQ(io::scene::parseScene(kMinimal, "s.json").solver.densitySolve,
            scene::DensitySolve::Increments);
  EXPECT_EQ(dfsph("solver.density_solve=projected").densitySolve, scene::DensitySolve::Projected);
  EXPECT_EQ(dfsph("solver.density_solve=increments").densitySolve, scene::DensitySolve::Increments);
  const std::string bad = errorOf(kMinimal, {"solver.pressure=dfsph", "solver.density_solve=cg"});
  EXPECT_NE(bad.find("solver.density_solve"), std::string::npos) << bad;
  EXPECT_NE(bad.find("projected"), std::string::npos) << bad;
  EXPECT_EQ(errorOf(kMinimal, {"solver.density_solve=projected"}),
            "bad.json: solver.density_solve: only used with \"pressure\": \"dfsph\"");
}

TEST(SceneLoader, DfsphLeastIterationsMayBeZeroItsCapsNot) {
  const auto dfsph = [](const std::string& edit) {
    return io::scene::parseScene(kMinimal, "s.json", {"solver.pressure=dfsph", edit}).solver;
  };
  EXPECT_EQ(dfsph("solver.cfl=0.2").minDivergenceIterations, 1);
  EXPECT_EQ(dfsph("solver.min_divergence_iterations=0").minDivergenceIterations, 0);
  EXPECT_EQ(dfsph("solver.min_density_iterations=0").minDensityIterations, 0);
  EXPECT_EQ(
      errorOf(kMinimal, {"solver.pressure=dfsph", "solver.min_divergence_iterations=-1"}),
      "bad.json: solver.min_divergence_iterations: expected an integer in [0, 10000], got -1");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.max_divergence_iterations=0"}),
            "bad.json: solver.max_divergence_iterations: expected an integer in [1, 10000], got 0");
  EXPECT_EQ(errorOf(kMinimal, {"solver.pressure=dfsph", "solver.min_divergence_iterations=5",
                               "solver.max_divergence_iterations=3"}),
            "bad.json: solver.min_divergence_iterations: expected at most "
            "max_divergence_iterations (3)");
  EXPECT_EQ(errorOf(kMinimal, {"solver.min_divergence_iterations=0"}),
            "bad.json: solver.min_divergence_iterations: only used with \"pressure\": \"dfsph\"");
}

TEST(SceneLoader, NumbersHaveSaneRangesAndReadableMessages) {
  auto set = [](const std::string& edit) { return errorOf(kMinimal, {edit}); };
  EXPECT_EQ(set("output.fps=1e308"),
            "bad.json: output.fps: expected a positive number (frames per simulated second) of "
            "magnitude at most 1e12, got 1e+308");
  const std::string fps = set("output.fps=1e6");
  EXPECT_EQ(fps.rfind("bad.json: output.fps: expected at most ", 0), 0u) << fps;
  EXPECT_NE(
      fps.find(" frames per simulated second (one frame per solver step; the step at rest is "),
      std::string::npos)
      << fps;
  // The limit follows the step: a smaller max_time_step allows more frames.
  EXPECT_EQ(errorOf(kMinimal, {"output.fps=5000", "solver.max_time_step=1e-4"}), "");
  EXPECT_NE(errorOf(kMinimal, {"output.fps=5000", "solver.max_time_step=1e-3"}), "");
  EXPECT_EQ(set("solver.end_time=1e300"),
            "bad.json: solver.end_time: expected a positive number of at most 1e6 (s), got 1e+300");
  EXPECT_EQ(set("solver.spacing=1e-9"),
            "bad.json: solver.spacing: the fluid blocks would hold 1e24 particles; expected at "
            "most 2e8 (raise the spacing)");
  EXPECT_EQ(set("fluids[0].velocity=[1e300,0,0]"),
            "bad.json: fluids[0].velocity: expected 3 numbers (m/s) [x, y, z], each between -1e6 "
            "and 1e6, got the array [1e+300,0,0]");
  EXPECT_EQ(set("render={\"every\": 1e11}")
                .rfind("bad.json: render.every: expected an integer in "
                       "[1, 1e6] (output frames)",
                       0),
            0u);
  EXPECT_EQ(errorOf(R"({"solver": {"spacing": 0.01}, "emitters": [{"position": [0,1,0],
      "direction": [0,-1,0], "radius": 0.1, "speed": 1, "start": 500000, "stop": 1}]})"),
            "bad.json: emitters[0].stop: expected a time after start (500000 s)");
}

TEST(SceneLoader, HostileFilesAreRefusedBeforeTheyAreRead) {
  const std::string dir = test::writeTempFile("", "") + ".d";
  ASSERT_EQ(std::system(("mkdir " + dir).c_str()), 0);
  auto loadError = [](const std::string& path) {
    try {
      io::scene::loadScene(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(loadError(dir), dir + ": is a directory; expected a scene file");
  EXPECT_EQ(loadError("/dev/zero"),
            "/dev/zero: is a character device, not a regular file; expected a scene file");
  const std::string utf16 = test::writeTempFile(std::string("\xFF\xFE{\0}\0", 6));
  EXPECT_EQ(loadError(utf16), utf16 +
                                  ": not UTF-8 text: it looks like UTF-16 little-endian "
                                  "(byte-order mark FF FE); save it as UTF-8");
}

}  // namespace
}  // namespace sph
