// The simulation's sections of a scene: solver (with the defaults of its `quality` preset),
// fluids, boundaries, emitters, output and collision (docs/scene-format.md). What is seen is read
// in io/scene/ViewSections.cpp; the file as a whole, its --set edits and the checks that need the
// whole scene in io/scene/SceneLoader.cpp.
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "io/cache/CacheFormat.h"
#include "io/MessageText.h"
#include "io/scene/SceneSections.h"
#include "sim/cdt/CdtConstants.h"

namespace sph::io::scene {
namespace {

// Solver defaults of a `quality` preset (docs/scene-format.md, "quality"). The values come from
// the dam-break sweeps (docs/benchmarks.md): "fast" is a point on the Pareto front of wall time
// against surge-front error (bench/sweeps/dam_break.json, "Run time vs error: simulation");
// "accurate" is DFSPH, for the density it holds (below; "Pressure solvers: DFSPH against WCSPH").
// A preset only changes defaults, so keys the scene gives explicitly still win.
struct QualityPreset {
  double cfl;               // see SolverParams::cfl
  double soundSpeedFactor;  // see SolverParams::soundSpeedFactor
  sph::scene::PressureSolver pressure = sph::scene::PressureSolver::Wcsph;
};

QualityPreset qualityPreset(Quality quality) {
  const sph::scene::SolverParams defaults;
  switch (quality) {
    case Quality::Fast:
      return {0.8, 5.0};
    case Quality::Accurate:
      // DFSPH: at a / dx = 10-20 of the dam break it holds the mean compression to 0.02-0.05%
      // (max 0.1-0.6%) with the surge front as close as the default's, where the stiffer Tait
      // EOS this preset used to be ran the front further off (steps of up to 1 ms:
      // docs/notes/2026-11-25-dfsph-against-wcsph.md; with today's steps: docs/benchmarks.md).
      // c stays the default's: the automatic viscosity derives from it. Its steps are 1.5x the
      // plain DFSPH's; accurateDfsph() says what keeps them as accurate.
      return {0.3, defaults.soundSpeedFactor, sph::scene::PressureSolver::Dfsph};
    case Quality::Default:
      break;
  }
  return {defaults.cfl, defaults.soundSpeedFactor};
}

// The accurate preset's DFSPH solve, for its longer steps (CFL 0.3, where the papers' examples
// take 0.2): those need twice the density iterations, which a fuller warm start (0.8) saves; the
// projected solve takes that warm start back where the flow no longer needs it (the papers'
// increments, which only add, ran the front of a fine dam break 10% ahead with it); Monaghan's
// viscosity; a divergence solve that may skip a step's iteration and a density solve that may
// stop after one; and a threshold of 0.045%, which holds the compression measured on the state
// itself, not only the solver's prediction of it, to the peer's 0.05%. On the peer's dam break
// about 0.24x the peer's wall time, where the settings before read 0.35x; still tank, fronts and
// compression: docs/notes/2026-11-30-dfsph-accurate-preset.md.
void accurateDfsph(sph::scene::SolverParams& s) {
  s.densityWarmStart = 0.8f;
  s.densitySolve = sph::scene::DensitySolve::Projected;
  s.viscosityForm = sph::scene::ViscosityForm::Monaghan;
  s.minDivergenceIterations = 0;
  s.minDensityIterations = 1;
  s.maxDensityError = 0.045f;
}

}  // namespace

sph::scene::SolverParams readSolver(JsonReader r, Quality quality) {
  sph::scene::SolverParams s;
  const QualityPreset preset = qualityPreset(quality);
  s.spacing =
      static_cast<float>(r.number("spacing", std::nullopt, "a positive number of at most 1000 (m)",
                                  [](double v) { return v > 0 && v <= 1e3; }));
  s.model = r.choice("model", std::optional(sph::scene::SolverModel::Sph));
  // Below 1.5 spacings a particle of the rest lattice sees its six nearest neighbours or none: the
  // still tank then collapsed by a fifth under WCSPH (1.2) and blew up under DFSPH (1-1.4).
  s.support = static_cast<float>(r.number("support", 2.0,
                                          "a number in [1.5, 4] (kernel support radius / spacing)",
                                          [](double v) { return v >= 1.5 && v <= 4; }));
  s.restDensity =
      static_cast<float>(r.number("rest_density", 1000.0, "a positive number (kg/m^3)", positive));
  s.viscosity =
      static_cast<float>(r.number("viscosity", -1.0, "a number >= 0 (m^2/s)", nonNegative));
  s.noSlipWalls =
      r.choice("walls", std::optional(sph::scene::Walls::NoSlip)) == sph::scene::Walls::NoSlip;
  s.eos = r.choice("eos", std::optional(sph::scene::EquationOfState::Tait));
  s.densityKernel = r.choice("density_kernel", std::optional(sph::scene::DensityKernel::Spiky));
  s.pressure = r.choice("pressure", std::optional(preset.pressure));
  const bool dfsph = s.pressure == sph::scene::PressureSolver::Dfsph;
  if (dfsph && quality == Quality::Accurate) accurateDfsph(s);  // keys the scene gives still win
  for (const char* key : {"max_density_error", "max_divergence_error", "min_density_iterations",
                          "min_divergence_iterations", "max_density_iterations",
                          "max_divergence_iterations", "density_relaxation", "density_warm_start",
                          "density_momentum_after", "density_solve", "viscosity_form"}) {
    if (!dfsph && r.has(key)) r.fail(key, "only used with \"pressure\": \"dfsph\"");
  }
  if (dfsph) {
    if (s.densityKernel != sph::scene::DensityKernel::Spiky) {
      r.fail("density_kernel",
             "\"pressure\": \"dfsph\" needs \"spiky\" (its solvers use the exact gradient of the "
             "density sum)");
    }
  }
  auto percent = [&](const char* key, float fallback) {
    return static_cast<float>(r.number(key, fallback, "a number in (0, 10] (%)",
                                       [](double v) { return v > 0 && v <= 10; }));
  };
  // The least iterations may be 0, the caps not.
  auto least = [&](const char* key, int fallback) {
    return static_cast<int>(r.number(key, fallback, "an integer in [0, 10000]",
                                     [](double v) { return integerIn(v, 0, 10000); }));
  };
  auto cap = [&](const char* key, int fallback) {
    return static_cast<int>(r.number(key, fallback, "an integer in [1, 10000]",
                                     [](double v) { return integerIn(v, 1, 10000); }));
  };
  s.maxDensityError = percent("max_density_error", s.maxDensityError);
  s.maxDivergenceError = percent("max_divergence_error", s.maxDivergenceError);
  s.minDensityIterations = least("min_density_iterations", s.minDensityIterations);
  s.minDivergenceIterations = least("min_divergence_iterations", s.minDivergenceIterations);
  s.maxDensityIterations = cap("max_density_iterations", s.maxDensityIterations);
  s.maxDivergenceIterations = cap("max_divergence_iterations", s.maxDivergenceIterations);
  s.densityRelaxation =
      static_cast<float>(r.number("density_relaxation", s.densityRelaxation, "a number in (0, 1]",
                                  [](double v) { return v > 0 && v <= 1; }));
  s.densityWarmStart =
      static_cast<float>(r.number("density_warm_start", s.densityWarmStart, "a number in [0, 1)",
                                  [](double v) { return v >= 0 && v < 1; }));
  s.densityMomentumAfter = static_cast<int>(
      r.number("density_momentum_after", s.densityMomentumAfter, "an integer in [0, 10000]",
               [](double v) { return integerIn(v, 0, 10000); }));
  s.densitySolve = r.choice("density_solve", std::optional(s.densitySolve));
  s.viscosityForm = r.choice("viscosity_form", std::optional(s.viscosityForm));
  s.wallPressure = r.choice("wall_pressure", std::optional(s.wallPressure));
  if (dfsph && s.wallPressure == sph::scene::WallPressure::Summation)
    r.fail("wall_pressure", "expected \"extrapolated\" or \"none\" with \"pressure\": \"dfsph\"");
  if (!dfsph && s.wallPressure == sph::scene::WallPressure::None)
    r.fail("wall_pressure",
           "expected \"extrapolated\" or \"summation\" with \"pressure\": \"wcsph\"");
  if (s.minDensityIterations > s.maxDensityIterations) {
    r.fail("min_density_iterations", "expected at most max_density_iterations (" +
                                         std::to_string(s.maxDensityIterations) + ")");
  }
  if (s.minDivergenceIterations > s.maxDivergenceIterations) {
    r.fail("min_divergence_iterations", "expected at most max_divergence_iterations (" +
                                            std::to_string(s.maxDivergenceIterations) + ")");
  }
  if (r.has("speed_of_sound") && r.has("stiffness")) {
    r.fail("stiffness", "give either speed_of_sound or stiffness, not both");
  }
  if (r.has("speed_of_sound_factor") && (r.has("speed_of_sound") || r.has("stiffness"))) {
    r.fail("speed_of_sound_factor",
           std::string("only used when the speed of sound is automatic; the scene also gives ") +
               (r.has("speed_of_sound") ? "speed_of_sound" : "stiffness"));
  }
  s.soundSpeedFactor = static_cast<float>(
      r.number("speed_of_sound_factor", preset.soundSpeedFactor,
               "a number >= 1 (automatic speed of sound / largest expected speed)",
               [](double v) { return v >= 1; }));
  s.speedOfSound =
      static_cast<float>(r.number("speed_of_sound", 0.0, "a positive number (m/s)", positive));
  s.stiffness = static_cast<float>(
      r.number("stiffness", 0.0, "a positive number (Pa for tait, m^2/s^2 for linear)", positive));
  s.clampNegativePressure = r.boolean("clamp_negative_pressure", true);
  // DFSPH's step is bound by the flow speed alone: dt <= cfl h / v_max; 0.2 at h = 2 spacings is
  // the 0.4 spacing / v_max of Bender & Koschier's examples (and SPlisHSPlasH's default).
  constexpr double kDfsphCfl = 0.2;
  // A preset's cfl is for its own solver; with the other one, that solver's default.
  const double cfl = preset.pressure == s.pressure ? preset.cfl
                     : dfsph                       ? kDfsphCfl
                                                   : sph::scene::SolverParams().cfl;
  s.cfl = static_cast<float>(r.number("cfl", cfl, "a positive number", positive));
  // DFSPH's step is bound by the flow speed and gravity (sim/solver/SceneSetup.cpp, timeStep()); its cap
  // is the peer's (SPlisHSPlasH, ../shared/reference/peers.md).
  s.maxTimeStep = static_cast<float>(r.number("max_time_step",
                                              s.pressure == sph::scene::PressureSolver::Dfsph
                                                  ? sph::scene::kDfsphMaxTimeStep
                                                  : s.maxTimeStep,
                                              "a positive number (s)", positive));
  s.gravity = r.vec3("gravity", s.gravity, "3 numbers (m/s^2)");
  s.endTime = r.number("end_time", 1.0, "a positive number of at most 1e6 (s)",
                       [](double v) { return v > 0 && v <= kMaxEndTime; });
  s.boundaryLayers =
      static_cast<int>(r.number("boundary_layers", 0.0, "an integer in [0, 8] (0 = automatic)",
                                [](double v) { return v >= 0 && v <= 8 && v == std::floor(v); }));
  s.maxLostParticles =
      static_cast<long long>(r.number("max_lost_particles", -1.0, "an integer in [0, 1e12]",
                                      [](double v) { return integerIn(v, 0, 1e12); }));
  r.finish();
  return s;
}

sph::scene::FluidBlock readFluid(JsonReader r) {
  sph::scene::FluidBlock f;
  const std::string type = r.string("type", std::string("box"), {"box", "sphere"});
  if (type == "box") {
    f.shape = sph::scene::FluidBlock::Shape::Box;
    f.lo = r.vec3("min", std::nullopt, "3 numbers (m)");
    f.hi = r.vec3("max", std::nullopt, "3 numbers (m)");
    requireOrdered(r, f.lo, f.hi);
  } else {
    f.shape = sph::scene::FluidBlock::Shape::Sphere;
    f.centre = r.vec3("centre", std::nullopt, "3 numbers (m)");
    f.radius =
        static_cast<float>(r.number("radius", std::nullopt, "a positive number (m)", positive));
  }
  f.velocity = r.vec3("velocity", Vec3::Zero(), "3 numbers (m/s)");
  r.finish();
  return f;
}

sph::scene::BoundaryShape readBoundary(JsonReader r) {
  sph::scene::BoundaryShape b;
  const std::string type =
      r.string("type", std::nullopt, {"tank", "block", "cup", "plane", "sphere"});
  if (type == "tank" || type == "block") {
    b.kind = type == "tank" ? sph::scene::BoundaryShape::Kind::Tank
                            : sph::scene::BoundaryShape::Kind::Block;
    b.lo = r.vec3("min", std::nullopt, "3 numbers (m)");
    b.hi = r.vec3("max", std::nullopt, "3 numbers (m)");
    requireOrdered(r, b.lo, b.hi);
    if (type == "tank") b.openTop = r.boolean("open_top", true);
  } else if (type == "cup") {
    b.kind = sph::scene::BoundaryShape::Kind::Cup;
    b.centre = r.vec3("centre", std::nullopt, "3 numbers (m): the centre of the cup's inner floor");
    b.radius = static_cast<float>(
        r.number("radius", std::nullopt, "a positive number (m): inner radius", positive));
    b.height = static_cast<float>(
        r.number("height", std::nullopt, "a positive number (m): wall height", positive));
  } else if (type == "plane") {
    b.kind = sph::scene::BoundaryShape::Kind::Plane;
    b.point = r.vec3("point", Vec3::Zero(), "3 numbers (m)");
    b.normal = r.vec3("normal", Vec3::UnitY(), "3 numbers, not all zero");
    if (b.normal.norm() == 0) r.fail("normal", "expected a non-zero vector, got [0, 0, 0]");
    b.normal.normalize();
  } else {
    b.kind = sph::scene::BoundaryShape::Kind::Sphere;
    b.centre = r.vec3("centre", std::nullopt, "3 numbers (m)");
    b.radius =
        static_cast<float>(r.number("radius", std::nullopt, "a positive number (m)", positive));
  }
  r.finish();
  return b;
}

sph::scene::EmitterDesc readEmitter(JsonReader r, float spacing) {
  sph::scene::EmitterDesc e;
  r.string("type", std::string("nozzle"), {"nozzle"});
  e.position = r.vec3("position", std::nullopt, "3 numbers (m)");
  e.direction = r.vec3("direction", std::nullopt, "3 numbers, not all zero");
  if (e.direction.norm() == 0) r.fail("direction", "expected a non-zero vector, got [0, 0, 0]");
  e.direction.normalize();
  e.radius =
      static_cast<float>(r.number("radius", std::nullopt, "a positive number (m)", positive));
  if (e.radius < 0.5f * spacing) {
    std::ostringstream m;
    m << "expected a nozzle radius of at least half the particle spacing (" << 0.5f * spacing
      << " m) so it emits particles, got " << e.radius;
    r.fail("radius", m.str());
  }
  e.speed =
      static_cast<float>(r.number("speed", std::nullopt, "a positive number (m/s)", positive));
  e.start = r.number("start", 0.0, "a number >= 0 (s)", nonNegative);
  e.stop = r.number("stop", std::numeric_limits<double>::infinity(), "a number > start (s)");
  if (r.has("stop") && e.stop <= e.start)
    r.fail("stop", "expected a time after start (" + readableNumber(e.start) + " s)");
  e.maxParticles = static_cast<std::size_t>(
      r.number("max_particles", 0.0, "an integer >= 0 (0 = no limit)", nonNegative));
  r.finish();
  return e;
}

sph::scene::OutputDesc readOutput(JsonReader r) {
  sph::scene::OutputDesc o;
  o.fps = r.number("fps", o.fps, "a positive number (frames per simulated second)", positive);
  o.path = r.string("path", std::string(""));
  // The cache's per-frame datasets (docs/cache-format.md): names checked and put in canonical
  // order.
  const std::vector<std::string> names =
      r.stringArray("fields", o.fields, "an array of field names, e.g. [\"x\", \"y\", \"z\"]");
  std::string error;
  const cache::FieldSet fields = cache::parseFields(names, error);
  if (!error.empty()) r.fail("fields", printable(error, 240));
  o.fields.clear();
  for (std::size_t f = 0; f < cache::kFieldCount; ++f) {
    if (fields[f]) o.fields.push_back(cache::fieldName(static_cast<cache::Field>(f)));
  }
  o.compression = static_cast<int>(
      r.number("compression", o.compression, "an integer deflate level 0-9 (0 = none)",
               [](double v) { return v >= 0 && v <= 9 && v == std::floor(v); }));
  o.restart = r.boolean("restart", o.restart);
  o.doublePositions = r.boolean("double_positions", o.doublePositions);
  r.finish();
  return o;
}

// The `collision` section (docs/scene-format.md, "collision"; DESIGN.md, "The CDT collision pass").
sph::scene::CollisionDesc readCollision(JsonReader r, const sph::scene::SolverParams& solver) {
  sph::scene::CollisionDesc c;
  c.method = r.choice<sph::scene::CollisionMethod>("method", std::nullopt);
  c.range = static_cast<float>(
      r.number("range", 0.5 * solver.spacing, "a positive number (m)", positive));
  c.response = r.choice("response", std::optional(sph::scene::CollisionResponse::Separate));
  const bool paper = c.response == sph::scene::CollisionResponse::Paper;
  c.speedFactor = static_cast<float>(r.number("speed_factor", 0.2, "a number in [0, 1]",
                                              [](double v) { return v >= 0 && v <= 1; }));
  c.cooldown = static_cast<float>(
      r.number("cooldown", paper ? 0.05 : 0.0, "a number >= 0 (s)", nonNegative));
  c.positionSource =
      r.choice("position_source", std::optional(paper ? sph::scene::CdtPositionSource::Texel
                                                      : sph::scene::CdtPositionSource::Particle));
  const int resolution =
      static_cast<int>(r.number("resolution", 500.0, "an integer in [16, 8192] (texels per side)",
                                [](double v) { return integerIn(v, 16, 8192); }));
  c.resolution = {resolution, resolution};
  // The CDT's own limits (sim/cdt/CdtConstants.h), so that no scene reaches its bug checks.
  const std::string texelRanges = "an integer in [0, " + std::to_string(cdt::kMaxTexelRange) + "]";
  c.texelRange = static_cast<int>(r.number("texel_range", 1.0, texelRanges.c_str(), [](double v) {
    return integerIn(v, 0, cdt::kMaxTexelRange);
  }));
  c.adaptiveTexelRange = r.boolean("adaptive_texel_range", false);
  const std::string maxRanges = "an integer in [1, " + std::to_string(cdt::kMaxTexelRange) + "]";
  c.maxTexelRange =
      static_cast<int>(r.number("max_texel_range", 4.0, maxRanges.c_str(),
                                [](double v) { return integerIn(v, 1, cdt::kMaxTexelRange); }));
  const std::string layerCounts = "an integer in [1, " + std::to_string(cdt::kMaxLayers) + "]";
  c.layers = static_cast<int>(r.number("layers", 1.0, layerCounts.c_str(),
                                       [](double v) { return integerIn(v, 1, cdt::kMaxLayers); }));
  c.camera = r.choice("camera", std::optional(sph::scene::CdtCameraMode::Render));
  c.offset = static_cast<float>(r.number("offset", 0.0, "a number (m, along the camera's z axis)"));
  if (auto pose = r.optionalObject("pose")) c.pose = readCamera(*pose), c.hasPose = true;
  if (c.camera == sph::scene::CdtCameraMode::Fixed && !c.hasPose)
    r.fail("pose", "missing; camera \"fixed\" needs its pose {position, target, ...}");
  if (c.camera != sph::scene::CdtCameraMode::Offset && r.has("offset"))
    r.fail("offset", "only used with \"camera\": \"offset\"");
  c.octreeDepth = static_cast<int>(r.number("octree_depth", 3.0, "an integer in [1, 6]",
                                            [](double v) { return integerIn(v, 1, 6); }));
  c.octreeRootSize =
      static_cast<float>(r.number("octree_root", 0.0, "a positive number (m)", positive));
  r.finish();
  return c;
}

}  // namespace sph::io::scene
