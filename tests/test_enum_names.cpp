// The name tables of the user-visible choices (sim/scene/EnumNames.h): every enumerator has a name,
// the names are unique, and parsing a name gives its enumerator back; the scene loader's messages
// list exactly the table.
#include <gtest/gtest.h>

#include <set>

#include "bench/sweep/SweepRunner.h"
#include "io/scene/SceneLoader.h"
#include "render/splat/SplatBuilder.h"
#include "sim/scene/CollisionDesc.h"
#include "sim/scene/EnumNames.h"
#include "sim/scene/LightsDesc.h"
#include "sim/scene/RainDesc.h"
#include "sim/scene/RenderDesc.h"
#include "sim/scene/SolverParams.h"

namespace sph {
namespace {

template <class E>
class EnumNamesTest : public ::testing::Test {};
using AllChoices = ::testing::Types<
    scene::LightSource, scene::LightColouring, scene::LightFilter, scene::LightPipeline,
    scene::LightAccumulate, scene::LightShade, scene::CollisionMethod, scene::CollisionResponse,
    scene::CdtCameraMode, scene::CdtPositionSource, scene::EquationOfState, scene::DensityKernel,
    scene::SolverModel, scene::Walls, scene::PressureSolver, scene::WallPressure,
    scene::ViscosityForm, scene::DensitySolve, scene::SplatProjection, scene::RenderDesc::Splat,
    render::splat::SplatKind, io::scene::Quality, sweep::RunStatus, scene::RainSpawn,
    scene::RainSampling, scene::RainOcclusion, scene::RainDraw, scene::RainFarTier>;
TYPED_TEST_SUITE(EnumNamesTest, AllChoices);

TYPED_TEST(EnumNamesTest, EveryEnumeratorHasAUniqueNameThatParsesBack) {
  const std::vector<TypeParam> all = scene::enumerators<TypeParam>();
  ASSERT_GE(all.size(), 2u);
  std::set<std::string> seen;
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(static_cast<std::size_t>(all[i]), i);  // declaration order, dense from 0
    const std::string name = scene::enumName(all[i]);
    EXPECT_FALSE(name.empty());
    EXPECT_EQ(name.find_first_of(" \"\t"), std::string::npos) << name;  // one word, no quotes
    EXPECT_TRUE(seen.insert(name).second) << "duplicate name " << name;
    EXPECT_EQ(scene::parseEnum<TypeParam>(name), all[i]) << name;
  }
  const std::vector<std::string> names = scene::enumNames<TypeParam>();
  ASSERT_EQ(names.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(names[i], scene::enumName(all[i]));
  EXPECT_FALSE(scene::parseEnum<TypeParam>("no-such-choice").has_value());
  EXPECT_FALSE(scene::parseEnum<TypeParam>("").has_value());
  // One past the last enumerator has no name: what enumerators() stops at.
  EXPECT_STREQ(scene::enumName(static_cast<TypeParam>(all.size())), "?");
}

TEST(EnumNames, ListsForHelpTexts) {
  EXPECT_EQ(scene::enumNameList<scene::RenderDesc::Splat>(), "point, quad or both");
  EXPECT_EQ(scene::enumNameList<scene::DensityKernel>(), "spiky or poly6");
  EXPECT_EQ(scene::enumNames<scene::CollisionMethod>(),
            (std::vector<std::string>{"none", "exact", "octree", "cdt-cpu", "cdt-gl"}));
}

// The loader's error for a choice lists the table, in order: a name added to the table is
// accepted and offered without touching the loader.
TEST(EnumNames, TheSceneLoaderOffersExactlyTheTable) {
  const std::string scene = R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}],
    "camera": {"position": [0, 0, 1], "target": [0, 0, 0]}})";
  auto message = [&](const std::string& edit) {
    try {
      io::scene::parseScene(scene, "s.json", {edit});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  auto quoted = [](const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& n : names) text += (text.empty() ? "\"" : ", \"") + n + "\"";
    return text;
  };
  EXPECT_EQ(message("collision.method=teleport"),
            "s.json: collision.method: expected one of " +
                quoted(scene::enumNames<scene::CollisionMethod>()) +
                ", got the string \"teleport\"");
  EXPECT_EQ(message("render.splat=disc"), "s.json: render.splat: expected one of " +
                                              quoted(scene::enumNames<scene::RenderDesc::Splat>()) +
                                              ", got the string \"disc\"");
  EXPECT_EQ(message("quality=perfect"), "s.json: quality: expected one of " +
                                            quoted(scene::enumNames<io::scene::Quality>()) +
                                            ", got the string \"perfect\"");
  for (const std::string& name : scene::enumNames<scene::CollisionMethod>())
    EXPECT_EQ(message("collision.method=" + name), "accepted") << name;
}

}  // namespace
}  // namespace sph
