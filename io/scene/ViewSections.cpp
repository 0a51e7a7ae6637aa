// What is seen of a scene: the camera (and its path), render, rain and lights sections
// (docs/scene-format.md). The simulation's sections are read in io/scene/SimulationSections.cpp.
#include <cmath>
#include <optional>

#include "io/MessageText.h"
#include "io/scene/SceneSections.h"

namespace sph::io::scene {
namespace {

// camera.path[i]: one key frame; `previous` is the time of the key before (or none).
sph::scene::CameraKey readCameraKey(JsonReader r, const sph::scene::CameraDesc& camera,
                                    std::optional<double> previous) {
  sph::scene::CameraKey k;
  k.time = r.number("time", std::nullopt, "a number >= 0 (s)", nonNegative);
  if (previous && !(k.time > *previous)) {
    r.fail("time", "expected a time after the previous key's (" + readableNumber(*previous) +
                       " s); key frames are in increasing time order");
  }
  k.position = r.vec3("position", camera.position, "3 numbers (m)");
  k.target = r.vec3("target", camera.target, "3 numbers (m)");
  k.fovYDegrees = static_cast<float>(r.number("fov", camera.fovYDegrees,
                                              "a number in (0, 180) (degrees, vertical)",
                                              [](double v) { return v > 0 && v < 180; }));
  if ((k.position - k.target).norm() == 0)
    r.fail("target", "expected a target different from position");
  if (camera.up.cross(k.target - k.position).norm() == 0)
    r.fail("target", "expected a view direction not parallel to the camera's up");
  r.finish();
  return k;
}

// rain.spotlight (seed 002 section 3.2).
sph::scene::SpotlightDesc readSpotlight(JsonReader r) {
  sph::scene::SpotlightDesc l;
  l.position = r.vec3("position", std::nullopt, "3 numbers (m): the cone's apex");
  l.direction = r.vec3("direction", l.direction, "3 numbers, not all zero");
  if (l.direction.norm() == 0) r.fail("direction", "expected a non-zero vector, got [0, 0, 0]");
  l.direction.normalize();
  l.height = static_cast<float>(
      r.number("height", l.height, "a positive number (m): the cone's height", positive));
  l.baseRadius = static_cast<float>(r.number(
      "base_radius", l.baseRadius, "a positive number (m): the cone's base radius", positive));
  l.colour = r.vec3("colour", l.colour, "3 numbers in [0, 1] (linear RGB)");
  if ((l.colour.array() < 0).any() || (l.colour.array() > 1).any())
    r.fail("colour", "expected 3 numbers in [0, 1], got " + formatVec(l.colour));
  l.intensity = static_cast<float>(r.number("intensity", l.intensity, "a number in [0, 100]",
                                            [](double v) { return v >= 0 && v <= 100; }));
  l.softEdge = static_cast<float>(
      r.number("soft_edge", 0.0, "a number in [0, 1) (fraction of the cone radius; 0 = hard)",
               [](double v) { return v >= 0 && v < 1; }));
  l.falloff = r.boolean("falloff", false);
  r.finish();
  return l;
}

}  // namespace

// `path` non-null: the top-level camera, which may carry key frames (camera.path).
sph::scene::CameraDesc readCamera(JsonReader r, sph::scene::CameraPath* path) {
  sph::scene::CameraDesc c;
  c.position = r.vec3("position", std::nullopt, "3 numbers (m)");
  c.target = r.vec3("target", std::nullopt, "3 numbers (m)");
  c.up = r.vec3("up", c.up, "3 numbers, not all zero");
  c.fovYDegrees =
      static_cast<float>(r.number("fov", c.fovYDegrees, "a number in (0, 180) (degrees, vertical)",
                                  [](double v) { return v > 0 && v < 180; }));
  c.near = static_cast<float>(r.number("near", c.near, "a positive number (m)", positive));
  c.far = static_cast<float>(r.number("far", c.far, "a positive number (m)", positive));
  if ((c.position - c.target).norm() == 0)
    r.fail("target", "expected a target different from position");
  if (c.up.norm() == 0 || c.up.cross(c.target - c.position).norm() == 0)
    r.fail("up", "expected a vector not parallel to the view direction");
  if (c.far <= c.near) r.fail("far", "expected far > near");
  if (path) {
    std::optional<double> previous;
    for (JsonReader& k : r.objectArray("path")) {
      path->push_back(readCameraKey(k, c, previous));
      previous = path->back().time;
    }
  }
  r.finish();
  return c;
}

// The `render` section (docs/scene-format.md, "render"; docs/rendering.md).
sph::scene::RenderDesc readRender(JsonReader r) {
  sph::scene::RenderDesc d;
  d.splat = r.choice("splat", std::optional(sph::scene::RenderDesc::Splat::Quad));
  auto pixels = [](double v) { return v >= 16 && v <= 8192 && v == std::floor(v); };
  d.width =
      static_cast<int>(r.number("width", d.width, "an integer in [16, 8192] (pixels)", pixels));
  d.height =
      static_cast<int>(r.number("height", d.height, "an integer in [16, 8192] (pixels)", pixels));
  d.every = static_cast<int>(r.number("every", 1.0, "an integer in [1, 1e6] (output frames)",
                                      [](double v) { return integerIn(v, 1, 1e6); }));
  d.kernelRadius =
      static_cast<float>(r.number("kernel_radius", d.kernelRadius, "a number in [1, 5] (spacings)",
                                  [](double v) { return v >= 1 && v <= 5; }));
  if (r.has("surface_threshold") && (*r.raw())["surface_threshold"].is_string()) {
    r.string("surface_threshold", std::nullopt, {"auto"});
  } else {
    d.surfaceThreshold = static_cast<float>(
        r.number("surface_threshold", 0.0, "\"auto\" or a number in (0, 1.5) (SD / mean density)",
                 [](double v) { return v > 0 && v < 1.5; }));
  }
  d.splatSize =
      static_cast<float>(r.number("splat_size", d.splatSize, "a number in [0.5, 4] (spacings)",
                                  [](double v) { return v >= 0.5 && v <= 4; }));
  d.perVertexDensity = r.string("vertex_density", std::string("per-vertex"),
                                {"per-vertex", "per-particle"}) == "per-vertex";
  d.projection = r.choice("projection", std::optional(sph::scene::SplatProjection::Newton));
  d.environment = r.boolean("environment", true);
  d.alpha = static_cast<float>(
      r.number("alpha", 1.0, "a number in (0, 1]", [](double v) { return v > 0 && v <= 1; }));
  d.cullBackFaces = r.boolean("cull_back_faces", true);
  d.solids = r.choice("solids", std::optional(sph::scene::RenderSolids::Points));
  // The older switch: false draws no walls.
  if (!r.boolean("show_boundary", true)) d.solids = sph::scene::RenderSolids::None;
  d.directory = r.string("directory", std::string(""));
  d.toCache = r.boolean("to_cache", true);
  r.finish();
  return d;
}

// The `rain` section (docs/scene-format.md, "rain"; docs/rain.md).
sph::scene::RainDesc readRain(JsonReader r) {
  sph::scene::RainDesc d;
  d.count = static_cast<std::size_t>(r.number("count", static_cast<double>(d.count),
                                              "an integer in [1, 1e8] (drops)",
                                              [](double v) { return integerIn(v, 1, 1e8); }));
  d.near = static_cast<float>(
      r.number("near", d.near, "a positive number (m, the rain camera's near distance)", positive));
  d.far = static_cast<float>(r.number("far", d.far, "a number > near of at most 1e4 (m)",
                                      [](double v) { return v > 0 && v <= 1e4; }));
  if (d.far <= d.near) {
    r.fail("far",
           "expected far > near (" + readableNumber(d.near) + " m), got " + readableNumber(d.far));
  }
  d.fallSpeed = static_cast<float>(r.number("fall_speed", d.fallSpeed,
                                            "a number in (0, 100] (m/s, downwards)",
                                            [](double v) { return v > 0 && v <= 100; }));
  d.wind = r.vec3("wind", d.wind, "3 numbers (m/s)");
  if (d.wind.norm() > 100) r.fail("wind", "expected a wind of at most 100 m/s");
  d.exposure = static_cast<float>(r.number("exposure", d.exposure,
                                           "a number in (0, 1] (s, the streak's exposure time)",
                                           [](double v) { return v > 0 && v <= 1; }));
  d.dropWidth = static_cast<float>(r.number("drop_width", d.dropWidth,
                                            "a number in (0, 0.1] (m, streak width)",
                                            [](double v) { return v > 0 && v <= 0.1; }));
  d.seed =
      static_cast<std::uint64_t>(r.number("seed", 1.0, "an integer in [0, 2^32)",
                                          [](double v) { return integerIn(v, 0, 4294967295.0); }));
  d.spawn = r.choice("spawn", std::optional(sph::scene::RainSpawn::View));
  d.sampling = r.choice("sampling", std::optional(sph::scene::RainSampling::Uniform));
  d.occlusion = r.choice("occlusion", std::optional(sph::scene::RainOcclusion::DepthMap));
  // The baselines are the paper's comparisons, kept as it ran them.
  if (d.spawn != sph::scene::RainSpawn::View && r.has("occlusion"))
    r.fail("occlusion", "only used with \"spawn\": \"view\"");
  if (auto g = r.optionalObject("region")) {
    d.region.lo = g->vec3("min", std::nullopt, "3 numbers (m)");
    d.region.hi = g->vec3("max", std::nullopt, "3 numbers (m)");
    requireOrdered(*g, d.region.lo, d.region.hi);
    g->finish();
  }
  if (d.spawn == sph::scene::RainSpawn::Region && d.region.empty())
    r.fail("region", "missing; spawn \"region\" needs its box {\"min\": [...], \"max\": [...]}");
  if (d.spawn != sph::scene::RainSpawn::Region && r.has("region"))
    r.fail("region", "only used with \"spawn\": \"region\"");
  d.streakLayers = static_cast<int>(r.number("streak_images", d.streakLayers,
                                             "an integer in [1, 64] (array texture layers)",
                                             [](double v) { return integerIn(v, 1, 64); }));
  d.draw = r.choice("draw", std::optional(sph::scene::RainDraw::Cpu));
  // The far tier is the CPU rasteriser's: with "triangles" every streak is its two triangles.
  if (d.draw != sph::scene::RainDraw::Cpu) {
    if (r.has("far_tier")) r.fail("far_tier", "only used with \"draw\": \"cpu\"");
    if (r.number("lod_width", 0.0, "a number in [0, 8] (pixels)",
                 [](double v) { return v >= 0 && v <= 8; }) > 0)
      r.fail("lod_width", "only used with \"draw\": \"cpu\"");
    d.lodWidth = 0;
  } else {
    d.farTier = r.choice("far_tier", std::optional(d.farTier));
    // Each tier's widest is its default: the lines take one pixel a row, so streaks up to 1 pixel
    // wide; the sums draw wider ones as several lines side by side (render/rain/StreakSums.h), up
    // to 8. 0 draws every streak exact.
    if (d.farTier == sph::scene::RainFarTier::Lines) {
      d.lodWidth = static_cast<float>(r.number(
          "lod_width", 1.0,
          "a number in [0, 1] (pixels: narrower streaks are drawn as lines; 0 = none; up to 8 with "
          "\"far_tier\": \"sums\")",
          [](double v) { return v >= 0 && v <= 1; }));
    } else {
      d.lodWidth = static_cast<float>(r.number(
          "lod_width", d.lodWidth,
          "a number in [0, 8] with \"far_tier\": \"sums\" (pixels: narrower streaks are summed; "
          "0 = none, every streak exact)",
          [](double v) { return v >= 0 && v <= 8; }));
    }
    if (r.has("far_tier") && !(d.lodWidth > 0))
      r.fail("far_tier", "only used with a \"lod_width\" > 0 (the streaks it draws)");
  }
  if (auto l = r.optionalObject("spotlight")) d.spotlight = readSpotlight(*l);
  d.feedFluid = r.boolean("feed_fluid", false);
  // Up to a cubic metre: a "drop" that stands for many, to show the fill in a short run.
  d.dropVolume = r.number("drop_volume", d.dropVolume, "a number in (0, 1] (m^3 of water a drop)",
                          [](double v) { return v > 0 && v <= 1; });
  r.finish();
  return d;
}

// The `lights` section (docs/scene-format.md, "lights"; docs/lights.md; seed 004).
sph::scene::LightsDesc readLights(JsonReader r) {
  sph::scene::LightsDesc d;
  d.source = r.choice("source", std::optional(sph::scene::LightSource::Fluid));
  if (d.source == sph::scene::LightSource::Emitter) {
    JsonReader e = r.object("emitter");
    d.emitter.box.lo = e.vec3("min", std::nullopt, "3 numbers (m)");
    d.emitter.box.hi = e.vec3("max", std::nullopt, "3 numbers (m)");
    requireOrdered(e, d.emitter.box.lo, d.emitter.box.hi);
    d.emitter.count = static_cast<std::size_t>(
        e.number("count", std::nullopt, "an integer in [1, 16777216] (light particles)",
                 [](double v) { return integerIn(v, 1, 16777216); }));
    d.emitter.speed =
        static_cast<float>(e.number("speed", d.emitter.speed, "a number >= 0 (m/s)", nonNegative));
    d.emitter.seed = static_cast<std::uint32_t>(
        e.number("seed", 1.0, "an integer in [0, 4294967295]",
                 [](double v) { return integerIn(v, 0, 4294967295.0); }));
    e.finish();
  } else if (r.has("emitter")) {
    r.fail("emitter", "only used with \"source\": \"emitter\"");
  }
  auto colour = [&](const char* key, const Vec3& def) {
    const Vec3 c = r.vec3(key, def, "3 numbers in [0, 1] (linear RGB)");
    if (c.minCoeff() < 0 || c.maxCoeff() > 1)
      r.fail(key, "expected 3 numbers in [0, 1] (linear RGB), got " + formatVec(c));
    return c;
  };
  d.colour = colour("colour", d.colour);
  d.intensity = static_cast<float>(r.number("intensity", d.intensity, "a number in (0, 1000]",
                                            [](double v) { return v > 0 && v <= 1000; }));
  d.colouring = r.choice("colour_by", std::optional(sph::scene::LightColouring::Constant));
  d.fastColour = colour("fast_colour", d.fastColour);
  d.fastSpeed =
      static_cast<float>(r.number("fast_speed", d.fastSpeed, "a positive number (m/s)", positive));
  if (d.colouring != sph::scene::LightColouring::Speed) {
    for (const char* key : {"fast_colour", "fast_speed"})
      if (r.has(key)) r.fail(key, "only used with \"colour_by\": \"speed\"");
  }
  // constant >= 1e-4: a light is at most 10^4 times its colour at its own place, so the CPU
  // path's 64-bit fixed-point sums cannot overflow even with 16.7M lights in one voxel.
  const Vec3 att =
      r.vec3("attenuation", Vec3(1, 0, 1),
             "3 numbers [constant, linear, quadratic], constant >= 1e-4, the others >= 0");
  if (!(att.x() >= 1e-4f) || att.y() < 0 || att.z() < 0) {
    r.fail("attenuation",
           "expected [constant, linear, quadratic] with constant >= 1e-4 and the others >= 0, "
           "got " +
               formatVec(att));
  }
  d.attenuation = {att.x(), att.y(), att.z()};
  d.range = static_cast<float>(r.number("range", d.range, "a number in (0, 1000] (m)",
                                        [](double v) { return v > 0 && v <= 1000; }));
  {
    JsonReader v = r.object("volume");
    d.origin = v.vec3("min", std::nullopt, "3 numbers (m): the volume's lowest corner");
    d.voxelSize =
        static_cast<float>(v.number("voxel_size", std::nullopt, "a positive number (m)", positive));
    const char* voxelsExpected = "an integer or 3 integers in [1, 2048] (voxels per axis)";
    auto count = [](double n) { return integerIn(n, 1, 2048); };
    if (v.has("voxels") && (*v.raw())["voxels"].is_number()) {
      const int n = static_cast<int>(v.number("voxels", std::nullopt, voxelsExpected, count));
      d.voxels = {n, n, n};
    } else {
      const Vec3 n = v.vec3("voxels", std::nullopt, voxelsExpected);
      for (int a = 0; a < 3; ++a) {
        if (!count(n[a]))
          v.fail("voxels", std::string("expected ") + voxelsExpected + ", got " + formatVec(n));
        d.voxels[static_cast<std::size_t>(a)] = static_cast<int>(n[a]);
      }
    }
    v.finish();
  }
  // Each light visits (2 (int(range / voxel_size) + 1) + 1)^3 voxels (the paper's loop): a range
  // of 32 voxels is already 274,625 a light; more would make one frame take hours (and the CPU
  // path's bucket arrays huge), never what a user meant.
  if (d.range / d.voxelSize > 32) {
    r.fail("range", "expected at most 32 voxels (volume.voxel_size " +
                        readableNumber(d.voxelSize, 4) + " m) per light's range, got " +
                        readableNumber(d.range / d.voxelSize, 4) +
                        "; use a larger volume.voxel_size or a smaller range");
  }
  d.filter = r.choice("filter", std::optional(sph::scene::LightFilter::Trilinear));
  d.tension = static_cast<float>(
      r.number("tension", 0.0, "a number in [0, 1]", [](double v) { return v >= 0 && v <= 1; }));
  if (d.filter != sph::scene::LightFilter::Tricubic && r.has("tension"))
    r.fail("tension", "only used with \"filter\": \"tricubic\"");
  d.oversampling = static_cast<int>(r.number("oversampling", 1.0,
                                             "an integer in [1, 4] (samples per axis; 1 = off)",
                                             [](double v) { return integerIn(v, 1, 4); }));
  d.pipeline = r.choice("pipeline", std::optional(sph::scene::LightPipeline::Forward));
  d.accumulate = r.choice("accumulate", std::optional(sph::scene::LightAccumulate::Auto));
  d.shade = r.choice("shade", std::optional(sph::scene::LightShade::Auto));
  if (d.shade == sph::scene::LightShade::Cpu) {
    // The CPU pass reads the deferred G-buffer back and samples the volume the CPU accumulated
    // (docs/lights.md, "Shading on the CPU"); what it cannot do is refused, not changed.
    if (d.pipeline != sph::scene::LightPipeline::Deferred)
      r.fail("shade",
             "\"cpu\" shades the deferred pipeline's G-buffer; expected \"pipeline\": "
             "\"deferred\" (or \"shade\": \"gl\" or \"auto\")");
    if (d.accumulate == sph::scene::LightAccumulate::Atomic ||
        d.accumulate == sph::scene::LightAccumulate::Paper)
      r.fail("shade", std::string("\"cpu\" samples the volume the CPU accumulated; expected "
                                  "\"accumulate\": \"cpu\" or \"auto\", got \"") +
                          nameOf(d.accumulate) + "\"");
    if (d.filter == sph::scene::LightFilter::Tricubic)
      r.fail("shade",
             "\"cpu\" filters nearest or trilinear (tricubic's 64 texels a pixel stay "
             "on the GL path); use \"shade\": \"gl\" or \"auto\"");
    d.accumulate = sph::scene::LightAccumulate::Cpu;  // "auto": the volume must be on the CPU
  }
  d.cull = r.boolean("cull", true);
  d.diffuse = static_cast<float>(r.number("diffuse", d.diffuse, "a number in [0, 10]",
                                          [](double v) { return v >= 0 && v <= 10; }));
  d.specular = static_cast<float>(r.number("specular", d.specular, "a number in [0, 10]",
                                           [](double v) { return v >= 0 && v <= 10; }));
  d.shininess = static_cast<float>(r.number("shininess", d.shininess, "a number in [1, 1024]",
                                            [](double v) { return v >= 1 && v <= 1024; }));
  d.roomLight = static_cast<float>(
      r.number("room_light", 1.0, "a number in [0, 1]", [](double v) { return v >= 0 && v <= 1; }));
  d.maxMemoryMiB = r.number("max_memory_mib", d.maxMemoryMiB, "a positive number (MiB)", positive);
  if (d.memoryBytes() > d.maxMemoryMiB * 1048576.0) {
    r.fail("volume.voxels", "a volume of " + std::to_string(d.voxels[0]) + " x " +
                                std::to_string(d.voxels[1]) + " x " + std::to_string(d.voxels[2]) +
                                " voxels needs " + readableNumber(d.memoryBytes() / 1048576.0, 4) +
                                " MiB of GL memory, more than lights.max_memory_mib = " +
                                readableNumber(d.maxMemoryMiB, 4) +
                                "; use fewer voxels or a larger voxel_size");
  }
  r.finish();
  return d;
}

}  // namespace sph::io::scene
