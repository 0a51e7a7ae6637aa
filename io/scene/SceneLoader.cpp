// A scene file read into a Scene: the JSON with its --set edits applied, the top level (each
// section handed to its reader: io/scene/SimulationSections.cpp, io/scene/ViewSections.cpp),
// and the checks that need the whole scene. Also the value checks the section readers share
// (SceneSections.h).
#include "io/scene/SceneLoader.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/scene/JsonReader.h"
#include "io/scene/JsonText.h"
#include "io/MessageText.h"
#include "io/scene/SceneSections.h"
#include "io/UserFiles.h"
#include "sim/solver/SceneSetup.h"
#include "sim/cdt/CdtCpu.h"

namespace sph::io::scene {

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

// Geometric checks that need the whole scene.
void validate(const sph::scene::Scene& s, const std::string& file) {
  auto fail = [&](const std::string& path, const std::string& msg) {
    throw InputError(file + ": " + path + ": " + msg);
  };
  if (s.fluids.empty() && s.emitters.empty()) {
    fail("fluids",
         "the scene has no fluid; expected at least one entry in \"fluids\" or \"emitters\"");
  }
  const float dx = s.solver.spacing;
  for (std::size_t i = 0; i < s.fluids.size(); ++i) {
    const sph::scene::FluidBlock& f = s.fluids[i];
    Aabb b;
    if (f.shape == sph::scene::FluidBlock::Shape::Box)
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
  for (const sph::scene::FluidBlock& f : s.fluids) {
    estimate += f.shape == sph::scene::FluidBlock::Shape::Box
                    ? (f.hi - f.lo).prod() / (dx * dx * dx)
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

sph::scene::Scene parseScene(const std::string& text, const std::string& path,
                             const std::vector<std::string>& overrides) {
  json doc = parseJson(text, path);
  for (const std::string& edit : overrides) applyOverride(doc, edit, path);

  JsonReader root(doc, "", path);
  sph::scene::Scene scene;
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
  scene.settle = root.number("settle", 0.0, "a number of seconds in [0, 1e4]",
                             [](double v) { return v >= 0 && v <= 1e4; });
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
    const bool cdt = scene.collision->method == sph::scene::CollisionMethod::CdtCpu ||
                     scene.collision->method == sph::scene::CollisionMethod::CdtGl;
    if (cdt && scene.collision->camera != sph::scene::CdtCameraMode::Fixed && !scene.camera) {
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

sph::scene::Scene loadScene(const std::string& path, const std::vector<std::string>& overrides) {
  return parseScene(readInputFile(path, "scene file"), path, overrides);
}

}  // namespace sph::io::scene
