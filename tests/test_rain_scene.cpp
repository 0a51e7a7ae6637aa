// How a scene asks for view-dependent rain (seed 002; docs/rain.md): the camera path its
// camera follows between keys, and the `rain` keys read or refused with one line. CPU only.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <string>

#include "io/scene/SceneLoader.h"
#include "sim/scene/Camera.h"
#include "tests/RainTestScenes.h"

namespace sph {
namespace {

using test::lookingAlongZ;

TEST(CameraPath, InterpolatesPoseAndFovAndTurnsEvenly) {
  scene::CameraDesc base = lookingAlongZ();
  const scene::CameraPath path = {{0.5, Vec3(0, 1, 4), Vec3(0, 1, 0), 40},
                                  {1.5, Vec3(2, 1, 4), Vec3(-2, 1, 4), 60}};
  // Before and after the keys: the end keys.
  EXPECT_EQ(cameraAt(base, path, 0).target, Vec3(0, 1, 0));
  EXPECT_EQ(cameraAt(base, path, 9).position, Vec3(2, 1, 4));
  EXPECT_EQ(cameraAt(base, path, 9).fovYDegrees, 60.0f);
  // Halfway: eye and fov linear, direction turned by half of the 90 degrees.
  const scene::CameraDesc mid = cameraAt(base, path, 1.0);
  EXPECT_NEAR((mid.position - Vec3(1, 1, 4)).norm(), 0, 1e-6f);
  EXPECT_FLOAT_EQ(mid.fovYDegrees, 50);
  const Vec3 dir = (mid.target - mid.position).normalized();
  EXPECT_NEAR(dir.dot(Vec3(0, 0, -1)), std::cos(M_PI / 4), 1e-6);
  EXPECT_NEAR(dir.dot(Vec3(-1, 0, 0)), std::cos(M_PI / 4), 1e-6);
  EXPECT_NEAR((mid.target - mid.position).norm(), 4, 1e-5);
  // A quarter of the way: a quarter of the turn.
  const scene::CameraDesc q = cameraAt(base, path, 0.75);
  EXPECT_NEAR((q.target - q.position).normalized().dot(Vec3(0, 0, -1)), std::cos(M_PI / 8), 1e-6);
  // No path: the base camera.
  EXPECT_EQ(cameraAt(base, {}, 3).position, base.position);
}

std::string errorOf(const std::string& rain, const std::string& camera = "") {
  const std::string text = R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}],
    "camera": {"position": [0, 0, 1], "target": [0, 0, 0])" +
                           camera + R"(}, "rain": )" + rain + "}";
  try {
    io::scene::parseScene(text, "r.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RainScene, KeysAreReadAndBadValuesRefusedWithOneLine) {
  const std::string text = R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}],
    "camera": {"position": [0, 0, 1], "target": [0, 0, 0],
               "path": [{"time": 0}, {"time": 2, "target": [1, 0, 1], "fov": 30}]},
    "rain": {"count": 500, "near": 0.2, "far": 8, "fall_speed": 4, "wind": [1, 0, 0],
             "exposure": 0.02, "seed": 9, "spawn": "region", "sampling": "paper", "lod_width": 0.5,
             "far_tier": "sums",
             "region": {"min": [-1, -1, -1], "max": [1, 1, 1]},
             "spotlight": {"position": [0, 2, 0], "colour": [1, 0, 0], "intensity": 2}}})";
  const scene::Scene s = io::scene::parseScene(text, "r.json");
  ASSERT_TRUE(s.rain.has_value());
  EXPECT_EQ(s.rain->count, 500u);
  EXPECT_EQ(s.rain->far, 8.0f);
  EXPECT_EQ(s.rain->spawn, scene::RainSpawn::Region);
  EXPECT_EQ(s.rain->sampling, scene::RainSampling::Paper);
  EXPECT_EQ(s.rain->occlusion, scene::RainOcclusion::DepthMap);  // the default
  EXPECT_EQ(s.rain->seed, 9u);
  EXPECT_EQ(s.rain->lodWidth, 0.5f);
  EXPECT_EQ(s.rain->farTier, scene::RainFarTier::Sums);
  ASSERT_TRUE(s.rain->spotlight.has_value());
  EXPECT_EQ(s.rain->spotlight->colour, Vec3(1, 0, 0));
  ASSERT_EQ(s.cameraPath.size(), 2u);
  EXPECT_EQ(s.cameraPath[0].position, Vec3(0, 0, 1));  // keys default to the camera's pose
  EXPECT_EQ(s.cameraPath[1].fovYDegrees, 30.0f);
  EXPECT_EQ(io::scene::parseScene(R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}],
    "camera": {"position": [0, 0, 1], "target": [0, 0, 0]}, "rain": {"occlusion": "none"}})",
                           "r.json")
                .rain->occlusion,
            scene::RainOcclusion::None);
  EXPECT_FALSE(io::scene::parseScene(R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}]})",
                                     "r.json")
                   .rain.has_value());
  // How the streaks are drawn by default: the sums at lod_width 8 on the CPU; each tier's widest
  // when only the tier is named; every streak exact with lod_width 0 or with the triangles.
  struct Drawing {
    const char* rain;
    float lodWidth;
    scene::RainFarTier farTier;
  };
  for (const Drawing& w : std::initializer_list<Drawing>{
           {"{}", 8, scene::RainFarTier::Sums},
           {R"({"far_tier": "lines"})", 1, scene::RainFarTier::Lines},
           {R"({"lod_width": 0})", 0, scene::RainFarTier::Sums},
           {R"({"lod_width": 0.5, "far_tier": "lines"})", 0.5f, scene::RainFarTier::Lines},
           {R"({"draw": "triangles"})", 0, scene::RainFarTier::Sums},
       }) {
    const std::string scene = R"({"solver": {"spacing": 0.01},
    "fluids": [{"min": [0, 0, 0], "max": [0.05, 0.05, 0.05]}],
    "camera": {"position": [0, 0, 1], "target": [0, 0, 0]}, "rain": )" +
                              std::string(w.rain) + "}";
    const scene::Scene parsed = io::scene::parseScene(scene, "r.json");
    EXPECT_EQ(parsed.rain->lodWidth, w.lodWidth) << w.rain;
    EXPECT_EQ(parsed.rain->farTier, w.farTier) << w.rain;
  }

  struct Bad {
    const char* rain;
    const char* expect;
  };
  for (const Bad& b : std::initializer_list<Bad>{
           {R"({"near": 2, "far": 1})", "r.json: rain.far: expected far > near"},
           {R"({"count": 0})", "r.json: rain.count: expected an integer in [1, 1e8]"},
           {R"({"count": 1e12})", "r.json: rain.count: expected an integer in [1, 1e8]"},
           {R"({"spawn": "sky"})", "r.json: rain.spawn:"},
           {R"({"sampling": "gauss"})", "r.json: rain.sampling:"},
           {R"({"occlusion": "rays"})",
            "r.json: rain.occlusion: expected one of \"depth_map\", \"none\", got the string "
            "\"rays\""},
           {R"({"occlusion": "none", "spawn": "box"})", "r.json: rain.occlusion: only used with"},
           {R"({"spawn": "region"})", "r.json: rain.region: missing"},
           {R"({"region": {"min": [0,0,0], "max": [1,1,1]}})", "r.json: rain.region: only used"},
           {R"({"fall_speed": -1})", "r.json: rain.fall_speed:"},
           {R"({"spotlight": {"position": [0, 1, 0], "base_radius": 0}})",
            "r.json: rain.spotlight.base_radius:"},
           {R"({"spotlight": {"position": [0, 1, 0], "colour": [2, 0, 0]}})",
            "r.json: rain.spotlight.colour:"},
           {R"({"lod_width": 9})",
            "r.json: rain.lod_width: expected a number in [0, 8] with \"far_tier\": \"sums\""},
           {R"({"lod_width": 1.5, "far_tier": "lines"})",
            "r.json: rain.lod_width: expected a number in [0, 1]"},
           {R"({"lod_width": 0.5, "draw": "triangles"})", "r.json: rain.lod_width: only used"},
           {R"({"lod_width": 1, "far_tier": "slabs"})", "r.json: rain.far_tier:"},
           {R"({"far_tier": "sums", "lod_width": 0})",
            "r.json: rain.far_tier: only used with a \"lod_width\" > 0"},
           {R"({"far_tier": "lines", "draw": "triangles"})",
            "r.json: rain.far_tier: only used with \"draw\": \"cpu\""},
           {R"({"far_tier": "sums", "lod_width": 9})",
            "r.json: rain.lod_width: expected a number in [0, 8] with \"far_tier\": \"sums\""},
           {R"({"far_tier": "lines", "lod_width": 2})",
            "r.json: rain.lod_width: expected a number in [0, 1]"},
           {R"({"raincount": 5})", "r.json: rain.raincount: unknown key"},
       }) {
    const std::string e = errorOf(b.rain);
    EXPECT_NE(e.find(b.expect), std::string::npos) << b.rain << " -> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  EXPECT_NE(errorOf("{}", R"(, "path": [{"time": 1}, {"time": 1}])")
                .find("r.json: camera.path[1].time: expected a time after"),
            std::string::npos);
}

}  // namespace
}  // namespace sph
