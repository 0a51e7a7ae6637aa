// The scene's `rain` section (docs/scene-format.md, "rain"; docs/rain.md): view-dependent rain of
// seed 002 (Im & Sung 2021) and the two baselines it compares against. Plain data; the rain
// itself lives in sim/rain/ (no GL) and is drawn by render/rain/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "sim/Types.h"
#include "sim/scene/EnumNames.h"

namespace sph::scene {

// Where drops are placed (scene key rain.spawn; DESIGN.md, "View-dependent rain").
enum class RainSpawn {
  View,    // the paper: the camera's frustum near..far intersected with the sphere of eq. (5)
  Box,     // baseline (Tariq 2007): a box of the rain space's volume that follows the camera
  Region,  // baseline (Creus & Patow 2013): a fixed world box, rain.region
};
constexpr const char* nameOf(RainSpawn v) {
  switch (v) {
    case RainSpawn::View:
      return "view";
    case RainSpawn::Box:
      return "box";
    case RainSpawn::Region:
      return "region";
  }
  return nullptr;
}

// How a point in the sphere of eq. (5) is drawn (scene key rain.sampling).
enum class RainSampling {
  Uniform,  // uniform in the ball's volume: radius r cbrt(u), direction from eq. (6) (ours)
  Paper,    // eq. (7) literally: a separate random radius in (-r, r) for each axis
};
constexpr const char* nameOf(RainSampling v) {
  switch (v) {
    case RainSampling::Uniform:
      return "uniform";
    case RainSampling::Paper:
      return "paper";
  }
  return nullptr;
}

// What keeps a drop of spawn "view" besides the rain space (scene key rain.occlusion; docs/rain.md,
// "The visible budget").
enum class RainOcclusion {
  DepthMap,  // placed and kept only where the eye sees it: in front of the solids and the water of
             // a depth image from the rain camera (sim/rain/EyeDepth.h)
  None,      // the paper: anywhere in the rain space, also behind a solid or the water
};
constexpr const char* nameOf(RainOcclusion v) {
  switch (v) {
    case RainOcclusion::DepthMap:
      return "depth_map";
    case RainOcclusion::None:
      return "none";
  }
  return nullptr;
}

// How the streaks are drawn (scene key rain.draw; docs/rain.md, "Drawing"). Both draw the same
// quads into the same frame.
enum class RainDraw {
  Cpu,        // rasterised on the CPU (OpenMP) and blended in one full-screen pass: for llvmpipe,
              // whose per-triangle setup made 1,000,000 streaks cost seconds a frame
  Triangles,  // two GL triangles per streak: for a real GPU
};
constexpr const char* nameOf(RainDraw v) {
  switch (v) {
    case RainDraw::Cpu:
      return "cpu";
    case RainDraw::Triangles:
      return "triangles";
  }
  return nullptr;
}

// How the far tier - the streaks narrower than rain.lod_width pixels - is drawn (scene key
// rain.far_tier; docs/rain.md, "Level of detail").
enum class RainFarTier {
  Lines,  // one sample per row, blended in drop order with the rest (the level of detail's lines)
  Sums,   // each streak's light added once per column it crosses into running sums down the
          // columns: a cost per drop, not per row; the drop order within the tier is lost
};
constexpr const char* nameOf(RainFarTier v) {
  switch (v) {
    case RainFarTier::Lines:
      return "lines";
    case RainFarTier::Sums:
      return "sums";
  }
  return nullptr;
}

// The cone spotlight of seed 002 section 3.2 (eq. (10)-(13)): apex at `position`, axis
// `direction`, cone height `height` and base radius `baseRadius` (its half-angle is
// atan(baseRadius / height)).
struct SpotlightDesc {
  Vec3 position = Vec3(0, 3, 0);    // m, the apex
  Vec3 direction = -Vec3::UnitY();  // unit, D of eq. (10)
  float height = 3;                 // m, h_spotlight of eq. (11)
  float baseRadius = 1;             // m, base radius of eq. (11)
  Vec3 colour = Vec3(1, 1, 1);      // linear RGB
  float intensity = 1;              // eq. (13)
  float softEdge = 0;    // fraction of the cone radius blended at its rim (0 = the paper)
  bool falloff = false;  // 1 / (1 + (d / height)^2) distance falloff (false = the paper)
};

struct RainDesc {
  std::size_t count = 10000;   // drops: the constant budget
  float near = 0.1f, far = 5;  // m, the rain camera's own near and far (eq. (1)-(2))
  float fallSpeed = 6;         // m/s, along -y (terminal speed of a ~1 mm drop is ~4-6 m/s)
  Vec3 wind = Vec3::Zero();    // m/s, added to the fall velocity
  float exposure = 1.0f / 60;  // s: a streak is the drop's path over this time
  float dropWidth = 0.002f;    // m, streak width
  std::uint64_t seed = 1;      // drops are a pure function of (seed, drop, respawn count)
  RainSpawn spawn = RainSpawn::View;
  RainSampling sampling = RainSampling::Uniform;
  RainOcclusion occlusion = RainOcclusion::DepthMap;  // spawn "view" only
  Aabb region;                                        // m, the fixed rain box of spawn "region"
  int streakLayers = 8;  // procedurally generated streak images in the array texture
  RainDraw draw = RainDraw::Cpu;
  // rain.lod_width (docs/rain.md, "Level of detail"): with draw "cpu", streaks narrower than this
  // many pixels are drawn by the far tier; 0: every streak exact (the paper's textured quads, what
  // draw "triangles" draws). The default, 8 with the sums: nearer the streaks' true picture than
  // the exact path in most frames measured, never worse than its worst, ~10x faster at 10^6 drops;
  // it loses on near, wide streaks (docs/rain.md, "The default: the sums at lod_width 8").
  float lodWidth = 8;
  // rain.far_tier: how those streaks are drawn (needs lod_width > 0); "lines" takes lod_width up
  // to 1 pixel, "sums" up to 8 (wider streaks as several lines side by side).
  RainFarTier farTier = RainFarTier::Sums;
  std::optional<SpotlightDesc> spotlight;
  // rain.feed_fluid (docs/rain.md, "Rain that fills the pool"): false, the paper, a drop that
  // lands in the water vanishes; true, its water joins the SPH fluid (sim/rain/RainFeed.h).
  bool feedFluid = false;
  // m^3 of water a drop carries (feed_fluid). A real 2 mm drop: pi/6 (2e-3)^3 = 4.19e-9 m^3.
  double dropVolume = 4.18879e-9;
};

}  // namespace sph::scene
