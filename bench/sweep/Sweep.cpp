#include "bench/sweep/Sweep.h"

#include <cmath>
#include <sstream>

#include "io/scene/JsonReader.h"
#include "io/scene/JsonText.h"
#include "io/MessageText.h"
#include "io/scene/SceneLoader.h"
#include "io/UserFiles.h"
#include "sim/Parallel.h"

namespace sph::sweep {
namespace {

using nlohmann::json;

std::string folderOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string resolve(const std::string& folder, const std::string& path) {
  return path.empty() || path[0] == '/' ? path : folder + path;
}

// The raw JSON under `key` of an object that a JsonReader has checked.
const json& raw(const json& object, const std::string& key) {
  return object.at(key);
}

// `scene`: a file name (relative to the sweep) or an inline scene object.
void readScene(io::scene::JsonReader& r, const json& object, const std::string& folder,
               std::string& file, json& inlineScene, bool required) {
  r.accept("scene");
  if (!object.contains("scene")) {
    if (required)
      r.fail("scene", "missing; expected a scene file name or an inline scene object {...}");
    return;
  }
  const json& v = raw(object, "scene");
  if (v.is_string() && !v.get<std::string>().empty())
    file = resolve(folder, v.get<std::string>());
  else if (v.is_object())
    inlineScene = v;
  else
    r.fail("scene", "expected a scene file name or an inline scene object {...}, got " +
                        io::scene::describeJson(v));
}

std::vector<std::string> readEdits(io::scene::JsonReader& r, const json& object,
                                   const std::string& key) {
  if (object.contains(key) && object.at(key).is_array() && object.at(key).empty()) {
    r.accept(key);  // "set": [] is fine, JsonReader's string arrays are non-empty
    return {};
  }
  std::vector<std::string> edits =
      r.stringArray(key, std::vector<std::string>{}, "an array of \"KEY.PATH=VALUE\" strings");
  for (const std::string& e : edits) {
    if (e.find('=') == std::string::npos || e[0] == '=')
      r.fail(key, "expected \"KEY.PATH=VALUE\", got \"" + io::printable(e) + "\"");
  }
  return edits;
}

bool positiveInteger(double v) {
  return v >= 1 && v == std::floor(v);
}
bool nonNegativeInteger(double v) {
  return v >= 0 && v == std::floor(v);
}

}  // namespace

std::string editValue(const json& value) {
  // Strings go in bare: applyOverride takes text that is not JSON as a string.
  return value.is_string() ? value.get<std::string>() : value.dump();
}

std::string shortValue(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_object() && value.contains("method") && value["method"].is_string()) {
    return value["method"].get<std::string>();  // a collision section reads as its method
  }
  if (value.is_number_float()) {
    std::ostringstream s;
    s << value.get<double>();  // 6 significant digits, no trailing zeros
    return s.str();
  }
  const std::string text = value.dump();
  return text.size() <= 24 ? text : text.substr(0, 21) + "...";
}

SweepSpec parseSweep(const std::string& text, const std::string& path,
                     const std::vector<std::string>& extraEdits) {
  json doc = io::scene::parseJson(text, path);
  io::scene::JsonReader root(doc, "", path);
  const std::string folder = folderOf(path);
  SweepSpec s;
  s.file = path;
  std::string stem = path.substr(path.find_last_of('/') + 1);
  s.name = root.string("name", stem.substr(0, stem.rfind('.')));
  s.description = root.string("description", std::string());
  readScene(root, doc, folder, s.scene, s.inlineScene, true);
  s.edits = readEdits(root, doc, "set");
  s.edits.insert(s.edits.end(), extraEdits.begin(), extraEdits.end());
  const std::string threads = "an integer in [0, " + std::to_string(maxThreadCount()) +
                              "] (0 = all cores; at most 4 x the " +
                              std::to_string(omp_get_num_procs()) + " cores here)";
  s.threads = static_cast<int>(root.number("threads", 0.0, threads.c_str(), [](double v) {
    return nonNegativeInteger(v) && v <= maxThreadCount();
  }));
  s.endTime = root.number("end_time", 0.0, "a positive number of at most 1e6 (s)",
                          [](double v) { return v > 0 && v <= io::scene::kMaxEndTime; });
  s.maxSteps = static_cast<std::uint64_t>(
      root.number("max_steps", 0.0, "an integer >= 0 (0 = no limit)", nonNegativeInteger));
  s.maxWallSeconds =
      root.number("max_wall_s", 0.0, "a number >= 0 (s, 0 = no limit)", io::scene::nonNegative);
  s.repeats = static_cast<int>(root.number("repeats", 1.0, "an integer in [1, 1000]", [](double v) {
    return positiveInteger(v) && v <= 1000;
  }));

  std::vector<io::scene::JsonReader> axes = root.objectArray("axes");
  for (std::size_t i = 0; i < axes.size(); ++i) {
    io::scene::JsonReader& a = axes[i];
    SweepAxis axis;
    axis.key = a.string("key", std::nullopt);
    if (axis.key.empty() || axis.key.find('=') != std::string::npos)
      a.fail("key", "expected a scene key path, e.g. \"solver.cfl\"");
    const std::size_t dot = axis.key.find_last_of('.');
    axis.label = a.string("label", dot == std::string::npos ? axis.key : axis.key.substr(dot + 1));
    a.accept("values");
    const json& values = doc["axes"][i].contains("values") ? doc["axes"][i]["values"] : json();
    if (!values.is_array() || values.empty()) {
      a.fail("values",
             "expected a non-empty array of values, got " + io::scene::describeJson(values));
    }
    for (const json& v : values) axis.values.push_back(v);
    a.finish();
    s.axes.push_back(std::move(axis));
  }

  std::vector<io::scene::JsonReader> cases = root.objectArray("cases");
  for (std::size_t i = 0; i < cases.size(); ++i) {
    io::scene::JsonReader& c = cases[i];
    SweepCase sc;
    sc.label = c.string("label", std::nullopt);
    readScene(c, doc["cases"][i], folder, sc.scene, sc.inlineScene, false);
    sc.edits = readEdits(c, doc["cases"][i], "set");
    sc.note = c.string("note", std::string());
    c.finish();
    s.cases.push_back(std::move(sc));
  }

  root.accept("metrics");
  if (doc.contains("metrics")) {
    const json& m = doc["metrics"];
    if (!m.is_array())
      root.fail("metrics",
                "expected an array of {\"type\": ...} objects, got " + io::scene::describeJson(m));
    for (std::size_t i = 0; i < m.size(); ++i) {
      if (!m[i].is_object() || !m[i].contains("type") || !m[i]["type"].is_string()) {
        root.fail("metrics[" + std::to_string(i) + "]",
                  "expected an object with a \"type\" string");
      }
      s.metrics.push_back(m[i]);
    }
  }
  if (auto plot = root.optionalObject("plot")) {
    s.plot = true;
    s.plotX = plot->string("x", s.plotX);
    s.plotY = plot->string("y", std::string());
    s.logY = plot->boolean("log_y", true);
    plot->finish();
  }
  root.finish();
  return s;
}

SweepSpec loadSweep(const std::string& path, const std::vector<std::string>& extraEdits) {
  return parseSweep(io::readInputFile(path, "sweep file"), path, extraEdits);
}

std::vector<SweepVariant> expandVariants(const SweepSpec& spec) {
  std::vector<SweepCase> cases = spec.cases;
  if (cases.empty()) cases.push_back(SweepCase{});
  std::size_t product = 1;
  for (const SweepAxis& a : spec.axes) product *= a.values.size();

  std::vector<SweepVariant> out;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const SweepCase& sc = cases[c];
    SweepVariant base;
    base.caseLabel = sc.label;
    base.note = sc.note;
    const json& inlineScene = !sc.inlineScene.is_null() ? sc.inlineScene : spec.inlineScene;
    const std::string file = !sc.scene.empty()          ? sc.scene
                             : sc.inlineScene.is_null() ? spec.scene
                                                        : std::string();
    if (!inlineScene.is_null() && file.empty()) {
      base.scenePath =
          spec.file +
          (sc.inlineScene.is_null() ? "#scene" : "#cases[" + std::to_string(c) + "].scene");
      base.sceneText = inlineScene.dump(2);
    } else {
      base.scenePath = file;
      base.sceneText = io::readInputFile(file, "scene file");
    }
    base.edits = spec.edits;
    base.edits.insert(base.edits.end(), sc.edits.begin(), sc.edits.end());

    for (std::size_t k = 0; k < product; ++k) {
      SweepVariant v = base;
      std::string label = sc.label;
      // Mixed-radix digits of k, the last axis fastest.
      std::size_t rest = k, stride = product;
      for (const SweepAxis& a : spec.axes) {
        stride /= a.values.size();
        const json& value = a.values[rest / stride];
        rest %= stride;
        v.edits.push_back(a.key + "=" + editValue(value));
        v.axisValues.push_back(shortValue(value));
        label += (label.empty() ? "" : " ") + a.label + "=" + shortValue(value);
      }
      v.label = label.empty() ? "base" : label;
      out.push_back(std::move(v));
    }
  }
  return out;
}

}  // namespace sph::sweep
