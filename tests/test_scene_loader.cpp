// Every class of bad scene is refused before anything runs, with one line naming the file, the
// JSON path of the bad key and what was expected. The shipped scenes load.
#include <gtest/gtest.h>

#include <string>

#include "io/SceneLoader.h"
#include "tests/TestSupport.h"

namespace sph {
namespace {

const char* kMinimal = R"({"solver": {"spacing": 0.01},
  "fluids": [{"type": "box", "min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}]})";

// The message of the InputError that parsing `text` throws ("" if none).
std::string errorOf(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    io::parseScene(text, "bad.json", overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneLoader, LoadsEveryShippedScene) {
  for (const char* name : {"dam_break", "still_tank", "pour"}) {
    const Scene s = test::shippedScene(name);
    EXPECT_EQ(s.name, name);
    EXPECT_GT(s.solver.spacing, 0.0f);
    EXPECT_FALSE(s.domain.empty());
    EXPECT_EQ(s.sourcePath, test::sourcePath(std::string("scenes/") + name + ".json"));
  }
}

TEST(SceneLoader, MinimalSceneGetsDocumentedDefaults) {
  const Scene s = io::parseScene(kMinimal, "min.json");
  EXPECT_EQ(s.name, "min");
  EXPECT_EQ(s.solver.support, 2.0f);
  EXPECT_EQ(s.solver.restDensity, 1000.0f);
  EXPECT_EQ(s.solver.eos, EquationOfState::Tait);
  EXPECT_EQ(s.solver.densityKernel, DensityKernel::Spiky);
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
  EXPECT_EQ(e, "bad.json: solver.spacing: expected a positive number (m), got the string \"fine\"");
  const std::string v = errorOf(R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0,0], "max": [1,1,1]}]})");
  EXPECT_EQ(v, "bad.json: fluids[0].min: expected 3 numbers (m) [x, y, z], got the array [0,0]");
}

TEST(SceneLoader, NegativeSpacingIsRefused) {
  const std::string e = errorOf(kMinimal, {"solver.spacing=-0.01"});
  EXPECT_EQ(e, "bad.json: solver.spacing: expected a positive number (m), got -0.01");
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
    io::loadScene("/nonexistent/scene.json");
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
  const Scene s = io::parseScene(kMinimal, "min.json",
                                 {"solver.cfl=0.2", "fluids[0].velocity=[1,0,0]", "name=custom"});
  EXPECT_EQ(s.solver.cfl, 0.2f);
  EXPECT_EQ(s.fluids[0].velocity, Vec3(1, 0, 0));
  EXPECT_EQ(s.name, "custom");
  EXPECT_NE(errorOf(kMinimal, {"fluids[3].velocity=[1,0,0]"}).find("index 3 is out of range"),
            std::string::npos);
  EXPECT_NE(errorOf(kMinimal, {"nonsense"}).find("expected KEY.PATH=VALUE"), std::string::npos);
}

}  // namespace
}  // namespace sph
