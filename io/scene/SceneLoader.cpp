#include "io/scene/SceneLoader.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/cache/CacheFormat.h"
#include "io/scene/JsonReader.h"
#include "io/scene/JsonText.h"
#include "io/MessageText.h"
#include "io/scene/SceneSections.h"
#include "io/UserFiles.h"
#include "sim/solver/SceneSetup.h"
#include "sim/cdt/CdtCpu.h"

namespace sph::io {

std::string formatVec(const Vec3& v) {
  std::ostringstream s;
  s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

bool integerIn(double v, double lo, double hi) {
  return v >= lo && v <= hi && v == std::floor(v);
}

void requireOrdered(JsonReader& r, const Vec3& lo, const Vec3& hi) {
  if (!(lo.array() < hi.array()).all()) {
    r.fail("max", "expected max > min on every axis, got min " + formatVec(lo) + " and max " +
                      formatVec(hi));
  }
}

namespace {

using nlohmann::json;

// One step of a --set key path: an object key or an array index.
struct PathStep {
  std::string key;        // "" for an index
  std::size_t index = 0;  // when key is ""
};

// "fluids[0].min" -> fluids, [0], min. Keys are non-empty; indices are plain decimal integers.
std::vector<PathStep> parseKeyPath(const std::string& keyPath) {
  const std::string quoted = "--set " + printable(keyPath);
  std::vector<PathStep> steps;
  std::size_t pos = 0;
  while (pos < keyPath.size()) {
    if (keyPath[pos] == '[') {
      const std::size_t close = keyPath.find(']', pos);
      if (close == std::string::npos) throw InputError(quoted + ": missing ']'");
      const std::string digits = keyPath.substr(pos + 1, close - pos - 1);
      const bool number = !digits.empty() && digits.size() <= 9 &&
                          digits.find_first_not_of("0123456789") == std::string::npos;
      if (!number) {
        throw InputError(quoted + ": expected an array index 0, 1, 2, ... inside [ ], got '" +
                         printable(digits) + "'");
      }
      steps.push_back({"", static_cast<std::size_t>(std::stoul(digits))});
      pos = close + 1;
      if (pos < keyPath.size() && keyPath[pos] != '.' && keyPath[pos] != '[')
        throw InputError(quoted + ": expected '.' or '[' after ']'");
      if (pos < keyPath.size() && keyPath[pos] == '.') {
        ++pos;
        if (pos == keyPath.size()) throw InputError(quoted + ": a key path cannot end with '.'");
      }
      continue;
    }
    const std::size_t end = std::min(keyPath.find_first_of(".[", pos), keyPath.size());
    if (end == pos) {
      throw InputError(quoted + ": empty key before '" + keyPath[pos] +
                       "'; expected KEY.PATH such as solver.spacing or fluids[0].min");
    }
    steps.push_back({keyPath.substr(pos, end - pos), 0});
    pos = end;
    if (pos < keyPath.size() && keyPath[pos] == '.') {
      ++pos;
      if (pos == keyPath.size()) throw InputError(quoted + ": a key path cannot end with '.'");
    }
  }
  return steps;
}

// Applies one "a.b[2].c=value" override to the document.
void applyOverride(json& doc, const std::string& edit, const std::string& file) {
  const std::size_t eq = edit.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError("--set " + printable(edit) +
                     ": expected KEY.PATH=VALUE, e.g. solver.spacing=0.01");
  }
  const std::string keyPath = edit.substr(0, eq), text = edit.substr(eq + 1);
  requireUtf8(keyPath, "--set");
  const std::vector<PathStep> steps = parseKeyPath(keyPath);
  // JSON if it reads as JSON (0.01, [1,0,0], {"method": "exact"}), else the text as a string.
  std::optional<json> parsed = parseJsonIfJson(text, "--set " + printable(keyPath));
  json value = parsed ? std::move(*parsed) : json(text);
  json* node = &doc;
  for (const PathStep& step : steps) {
    if (!step.key.empty()) {
      if (node->is_null()) *node = json::object();  // --set may create a section the file lacks
      if (!node->is_object()) {
        throw InputError(file + ": --set " + printable(keyPath) + ": '" + printable(step.key) +
                         "' is not inside an object");
      }
      node = &(*node)[step.key];
    } else {
      if (!node->is_array() || step.index >= node->size()) {
        throw InputError(file + ": --set " + printable(keyPath) + ": index " +
                         std::to_string(step.index) + " is out of range" +
                         (node->is_array()
                              ? " (the array has " + std::to_string(node->size()) + " entries)"
                              : " (not an array)"));
      }
      node = &(*node)[step.index];
    }
  }
  *node = std::move(value);
}

// Solver defaults of a `quality` preset (docs/scene-format.md, "quality"). The values come from
// the dam-break sweep (bench/sweeps/dam_break.json, docs/benchmarks.md): "fast" is a point on its
// Pareto front of wall time against surge-front error; "accurate" is DFSPH (issue 15). A preset
// only changes defaults, so keys the scene gives explicitly still win.
struct QualityPreset {
  double cfl;               // see SolverParams::cfl
  double soundSpeedFactor;  // see SolverParams::soundSpeedFactor
  scene::PressureSolver pressure = scene::PressureSolver::Wcsph;
};

QualityPreset qualityPreset(Quality quality) {
  const scene::SolverParams defaults;
  switch (quality) {
    case Quality::Fast:
      return {0.8, 5.0};
    case Quality::Accurate:
      // DFSPH (issue 15): at a / dx = 10-20 of the dam break it holds the mean compression to
      // 0.02-0.05% (max 0.1-0.6%) with the surge front as close as the default's, where the
      // stiffer Tait EOS this preset used to be ran the front further off (docs/benchmarks.md).
      // c stays the default's: the automatic viscosity derives from it.
      return {0.2, defaults.soundSpeedFactor, scene::PressureSolver::Dfsph};
    case Quality::Default:
      break;
  }
  return {defaults.cfl, defaults.soundSpeedFactor};
}

scene::SolverParams readSolver(JsonReader r, Quality quality) {
  scene::SolverParams s;
  const QualityPreset preset = qualityPreset(quality);
  s.spacing =
      static_cast<float>(r.number("spacing", std::nullopt, "a positive number of at most 1000 (m)",
                                  [](double v) { return v > 0 && v <= 1e3; }));
  s.model = r.choice("model", std::optional(scene::SolverModel::Sph));
  s.support = static_cast<float>(r.number("support", 2.0,
                                          "a number in [1, 4] (kernel support radius / spacing)",
                                          [](double v) { return v >= 1 && v <= 4; }));
  s.restDensity =
      static_cast<float>(r.number("rest_density", 1000.0, "a positive number (kg/m^3)", positive));
  s.viscosity =
      static_cast<float>(r.number("viscosity", -1.0, "a number >= 0 (m^2/s)", nonNegative));
  s.noSlipWalls = r.choice("walls", std::optional(scene::Walls::NoSlip)) == scene::Walls::NoSlip;
  s.eos = r.choice("eos", std::optional(scene::EquationOfState::Tait));
  s.densityKernel = r.choice("density_kernel", std::optional(scene::DensityKernel::Spiky));
  s.pressure = r.choice("pressure", std::optional(preset.pressure));
  const bool dfsph = s.pressure == scene::PressureSolver::Dfsph;
  for (const char* key : {"max_density_error", "max_divergence_error", "min_density_iterations",
                          "max_density_iterations", "max_divergence_iterations"}) {
    if (!dfsph && r.has(key)) r.fail(key, "only used with \"pressure\": \"dfsph\"");
  }
  if (dfsph) {
    if (s.densityKernel != scene::DensityKernel::Spiky) {
      r.fail("density_kernel",
             "\"pressure\": \"dfsph\" needs \"spiky\" (its solvers use the exact gradient of the "
             "density sum)");
    }
  }
  auto percent = [&](const char* key, float fallback) {
    return static_cast<float>(r.number(key, fallback, "a number in (0, 10] (%)",
                                       [](double v) { return v > 0 && v <= 10; }));
  };
  auto iterations = [&](const char* key, int fallback) {
    return static_cast<int>(r.number(key, fallback, "an integer in [1, 10000]",
                                     [](double v) { return integerIn(v, 1, 10000); }));
  };
  s.maxDensityError = percent("max_density_error", s.maxDensityError);
  s.maxDivergenceError = percent("max_divergence_error", s.maxDivergenceError);
  s.minDensityIterations = iterations("min_density_iterations", s.minDensityIterations);
  s.maxDensityIterations = iterations("max_density_iterations", s.maxDensityIterations);
  s.maxDivergenceIterations = iterations("max_divergence_iterations", s.maxDivergenceIterations);
  if (s.minDensityIterations > s.maxDensityIterations) {
    r.fail("min_density_iterations", "expected at most max_density_iterations (" +
                                         std::to_string(s.maxDensityIterations) + ")");
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
                                                   : scene::SolverParams().cfl;
  s.cfl = static_cast<float>(r.number("cfl", cfl, "a positive number", positive));
  // DFSPH's step is bound by the flow speed and gravity (sim/solver/SceneSetup.cpp, timeStep()); its cap
  // is the peer's (SPlisHSPlasH, ../shared/reference/peers.md).
  s.maxTimeStep = static_cast<float>(r.number(
      "max_time_step",
      s.pressure == scene::PressureSolver::Dfsph ? scene::kDfsphMaxTimeStep : s.maxTimeStep,
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

scene::FluidBlock readFluid(JsonReader r) {
  scene::FluidBlock f;
  const std::string type = r.string("type", std::string("box"), {"box", "sphere"});
  if (type == "box") {
    f.shape = scene::FluidBlock::Shape::Box;
    f.lo = r.vec3("min", std::nullopt, "3 numbers (m)");
    f.hi = r.vec3("max", std::nullopt, "3 numbers (m)");
    requireOrdered(r, f.lo, f.hi);
  } else {
    f.shape = scene::FluidBlock::Shape::Sphere;
    f.centre = r.vec3("centre", std::nullopt, "3 numbers (m)");
    f.radius =
        static_cast<float>(r.number("radius", std::nullopt, "a positive number (m)", positive));
  }
  f.velocity = r.vec3("velocity", Vec3::Zero(), "3 numbers (m/s)");
  r.finish();
  return f;
}

scene::BoundaryShape readBoundary(JsonReader r) {
  scene::BoundaryShape b;
  const std::string type =
      r.string("type", std::nullopt, {"tank", "block", "cup", "plane", "sphere"});
  if (type == "tank" || type == "block") {
    b.kind = type == "tank" ? scene::BoundaryShape::Kind::Tank : scene::BoundaryShape::Kind::Block;
    b.lo = r.vec3("min", std::nullopt, "3 numbers (m)");
    b.hi = r.vec3("max", std::nullopt, "3 numbers (m)");
    requireOrdered(r, b.lo, b.hi);
    if (type == "tank") b.openTop = r.boolean("open_top", true);
  } else if (type == "cup") {
    b.kind = scene::BoundaryShape::Kind::Cup;
    b.centre = r.vec3("centre", std::nullopt, "3 numbers (m): the centre of the cup's inner floor");
    b.radius = static_cast<float>(
        r.number("radius", std::nullopt, "a positive number (m): inner radius", positive));
    b.height = static_cast<float>(
        r.number("height", std::nullopt, "a positive number (m): wall height", positive));
  } else if (type == "plane") {
    b.kind = scene::BoundaryShape::Kind::Plane;
    b.point = r.vec3("point", Vec3::Zero(), "3 numbers (m)");
    b.normal = r.vec3("normal", Vec3::UnitY(), "3 numbers, not all zero");
    if (b.normal.norm() == 0) r.fail("normal", "expected a non-zero vector, got [0, 0, 0]");
    b.normal.normalize();
  } else {
    b.kind = scene::BoundaryShape::Kind::Sphere;
    b.centre = r.vec3("centre", std::nullopt, "3 numbers (m)");
    b.radius =
        static_cast<float>(r.number("radius", std::nullopt, "a positive number (m)", positive));
  }
  r.finish();
  return b;
}

scene::EmitterDesc readEmitter(JsonReader r, float spacing) {
  scene::EmitterDesc e;
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

scene::OutputDesc readOutput(JsonReader r) {
  scene::OutputDesc o;
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
scene::CollisionDesc readCollision(JsonReader r, const scene::SolverParams& solver) {
  scene::CollisionDesc c;
  c.method = r.choice<scene::CollisionMethod>("method", std::nullopt);
  c.range = static_cast<float>(
      r.number("range", 0.5 * solver.spacing, "a positive number (m)", positive));
  c.response = r.choice("response", std::optional(scene::CollisionResponse::Separate));
  const bool paper = c.response == scene::CollisionResponse::Paper;
  c.speedFactor = static_cast<float>(r.number("speed_factor", 0.2, "a number in [0, 1]",
                                              [](double v) { return v >= 0 && v <= 1; }));
  c.cooldown = static_cast<float>(
      r.number("cooldown", paper ? 0.05 : 0.0, "a number >= 0 (s)", nonNegative));
  c.positionSource = r.choice(
      "position_source",
      std::optional(paper ? scene::CdtPositionSource::Texel : scene::CdtPositionSource::Particle));
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
  c.camera = r.choice("camera", std::optional(scene::CdtCameraMode::Render));
  c.offset = static_cast<float>(r.number("offset", 0.0, "a number (m, along the camera's z axis)"));
  if (auto pose = r.optionalObject("pose")) c.pose = readCamera(*pose), c.hasPose = true;
  if (c.camera == scene::CdtCameraMode::Fixed && !c.hasPose)
    r.fail("pose", "missing; camera \"fixed\" needs its pose {position, target, ...}");
  if (c.camera != scene::CdtCameraMode::Offset && r.has("offset"))
    r.fail("offset", "only used with \"camera\": \"offset\"");
  c.octreeDepth = static_cast<int>(r.number("octree_depth", 3.0, "an integer in [1, 6]",
                                            [](double v) { return integerIn(v, 1, 6); }));
  c.octreeRootSize =
      static_cast<float>(r.number("octree_root", 0.0, "a positive number (m)", positive));
  r.finish();
  return c;
}

// Geometric checks that need the whole scene.
void validate(const scene::Scene& s, const std::string& file) {
  auto fail = [&](const std::string& path, const std::string& msg) {
    throw InputError(file + ": " + path + ": " + msg);
  };
  if (s.fluids.empty() && s.emitters.empty()) {
    fail("fluids",
         "the scene has no fluid; expected at least one entry in \"fluids\" or \"emitters\"");
  }
  const float dx = s.solver.spacing;
  for (std::size_t i = 0; i < s.fluids.size(); ++i) {
    const scene::FluidBlock& f = s.fluids[i];
    Aabb b;
    if (f.shape == scene::FluidBlock::Shape::Box)
      b.lo = f.lo, b.hi = f.hi;
    else
      b.lo = f.centre - Vec3::Constant(f.radius), b.hi = f.centre + Vec3::Constant(f.radius);
    const std::string path = "fluids[" + std::to_string(i) + "]";
    if (!s.domain.contains(b.lo) || !s.domain.contains(b.hi)) {
      fail(path, "fluid outside the domain: expected it inside " + formatVec(s.domain.lo) + " - " +
                     formatVec(s.domain.hi) + " (m)");
    }
    if ((b.hi - b.lo).minCoeff() < dx) {
      fail(path,
           "expected a block at least one particle spacing (" + readableNumber(dx) + " m) across");
    }
  }
  for (std::size_t i = 0; i < s.emitters.size(); ++i) {
    if (!s.domain.contains(s.emitters[i].position)) {
      fail("emitters[" + std::to_string(i) + "].position",
           "nozzle outside the domain " + formatVec(s.domain.lo) + " - " + formatVec(s.domain.hi));
    }
  }
  // Refuse runs that would not fit in memory before allocating anything (~100 B per particle).
  double estimate = 0;
  for (const scene::FluidBlock& f : s.fluids) {
    estimate += f.shape == scene::FluidBlock::Shape::Box ? (f.hi - f.lo).prod() / (dx * dx * dx)
                                                         : 4.18879 * std::pow(f.radius / dx, 3.0);
  }
  if (!(estimate <= 2e8)) {
    fail("solver.spacing", "the fluid blocks would hold " + readableCount(estimate) +
                               " particles; expected at most 2e8 (raise the spacing)");
  }
  // Frames no closer than the solver's step at rest (its largest): a shorter frame interval would
  // only cut every step short, and output.fps = 1e308 would crawl at 1e-308 s a step.
  const float restStep = solver::timeStep(s, solver::deriveParams(s), 0, 0);
  if (s.output.fps * restStep > 1.0) {
    fail("output.fps",
         "expected at most " + readableNumber(1.0 / restStep, 4) +
             " frames per simulated second (one frame per solver step; the step at rest is " +
             readableNumber(restStep, 3) + " s, a smaller solver.max_time_step allows more), got " +
             readableNumber(s.output.fps));
  }
  cdt::requireIdsInRange(s);
}

}  // namespace

scene::Scene parseScene(const std::string& text, const std::string& path,
                        const std::vector<std::string>& overrides) {
  json doc = parseJson(text, path);
  for (const std::string& edit : overrides) applyOverride(doc, edit, path);

  JsonReader root(doc, "", path);
  scene::Scene scene;
  scene.sourcePath = path;
  scene.sourceText = text;
  std::string stem = path.substr(path.find_last_of('/') + 1);
  stem = stem.substr(0, stem.rfind('.'));
  scene.name = root.string("name", stem);
  // A name is printed in every progress line and names the run's files.
  if (hasControlBytes(scene.name)) {
    root.fail("name", "expected a name without control characters or bytes that are not UTF-8, "
                      "got \"" + oneLine(scene.name) + "\"");
  }
  scene.description = root.string("description", std::string(""));
  const Quality quality = root.choice("quality", std::optional(Quality::Default));
  scene.solver = readSolver(root.object("solver"), quality);
  for (JsonReader& f : root.objectArray("fluids")) scene.fluids.push_back(readFluid(f));
  for (JsonReader& b : root.objectArray("boundaries")) scene.boundaries.push_back(readBoundary(b));
  for (JsonReader& e : root.objectArray("emitters"))
    scene.emitters.push_back(readEmitter(e, scene.solver.spacing));
  if (auto o = root.optionalObject("output")) scene.output = readOutput(*o);
  if (auto c = root.optionalObject("camera")) scene.camera = readCamera(*c, &scene.cameraPath);
  if (auto rd = root.optionalObject("render")) {
    scene.render = readRender(*rd);
    if (!scene.camera)
      root.fail("render", "needs a \"camera\" section at the top level too (where to look from)");
  }
  if (auto rn = root.optionalObject("rain")) {
    scene.rain = readRain(*rn);
    if (!scene.camera)
      root.fail("rain",
                "needs a \"camera\" section at the top level too (rain falls where it looks)");
    // A landing makes at most one particle (sim/rain/RainFeed.h): no two new particles coincide.
    const double particle =
        static_cast<double>(scene.solver.spacing) * scene.solver.spacing * scene.solver.spacing;
    if (scene.rain->feedFluid && scene.rain->dropVolume > particle) {
      rn->fail("drop_volume", "expected at most one particle's water, solver.spacing^3 = " +
                                  readableNumber(particle) + " m^3, got " +
                                  readableNumber(scene.rain->dropVolume));
    }
  }
  if (auto l = root.optionalObject("lights")) scene.lights = readLights(*l);
  if (auto c = root.optionalObject("collision")) {
    scene.collision = readCollision(*c, scene.solver);
    const bool cdt = scene.collision->method == scene::CollisionMethod::CdtCpu ||
                     scene.collision->method == scene::CollisionMethod::CdtGl;
    if (cdt && scene.collision->camera != scene::CdtCameraMode::Fixed && !scene.camera) {
      c->fail("camera",
              "the collision camera follows the scene's camera, but the scene has no \"camera\"; "
              "add one or use \"camera\": \"fixed\" with a \"pose\"");
    }
  }
  if (auto d = root.optionalObject("domain")) {
    scene.domain.lo = d->vec3("min", std::nullopt, "3 numbers (m)");
    scene.domain.hi = d->vec3("max", std::nullopt, "3 numbers (m)");
    requireOrdered(*d, scene.domain.lo, scene.domain.hi);
    d->finish();
  } else {
    scene.domain = solver::defaultDomain(scene);
  }
  root.finish();
  validate(scene, path);
  return scene;
}

scene::Scene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
  return parseScene(readInputFile(path, "scene file"), path, overrides);
}

}  // namespace sph::io
