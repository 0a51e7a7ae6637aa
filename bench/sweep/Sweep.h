// A sweep file (`sphsplat bench SWEEP.json`, docs/benchmarks.md): one base scene, the variants to
// run it in, what to measure and how to plot it. Variants are scene edits in the `--set` syntax
// (io/scene/SceneLoader.h), so any scene key can be an axis: resolution, CFL number, speed of sound,
// EOS, quality preset, a collision method. Every variant's scene is loaded and validated before
// anything runs, so a bad sweep costs nothing.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace sph::sweep {

// One axis of the cartesian product: the scene key it sets and its values (any JSON).
struct SweepAxis {
  std::string key;    // "solver.cfl", "collision", ...
  std::string label;  // column name in the CSV and table ("cfl"); default: the key's last part
  std::vector<nlohmann::json> values;
};

// One explicit case, for sweeps whose variants are not a product (stress cases, collision methods
// with their own options): a label, its own scene edits and optionally its own scene.
struct SweepCase {
  std::string label;
  std::string scene;               // scene file; "" = the sweep's
  nlohmann::json inlineScene;      // an inline scene object instead of a file (null if none)
  std::vector<std::string> edits;  // KEY.PATH=VALUE
  std::string note;                // free text carried into the table
};

// A fully resolved variant: the scene source and every edit, in order.
struct SweepVariant {
  std::string label;                    // "dx=0.0073 cfl=0.4 c_factor=10"
  std::vector<std::string> axisValues;  // one string per axis (CSV columns), in axis order
  std::string caseLabel, note;          // from the case (empty without cases)
  std::string scenePath;                // file, or "SWEEP.json#cases[2].scene" for an inline scene
  std::string sceneText;                // the scene's JSON text
  std::vector<std::string> edits;       // base edits, case edits, then axis edits
};

struct SweepSpec {
  std::string file;  // the sweep file (paths inside it are relative to its folder)
  std::string name, description;
  std::string scene;               // base scene file, resolved
  nlohmann::json inlineScene;      // or an inline base scene (null if none)
  std::vector<std::string> edits;  // edits applied to every variant (`set`)
  std::vector<SweepCase> cases;    // explicit cases (product with the axes); empty = one
  std::vector<SweepAxis> axes;
  std::vector<nlohmann::json> metrics;  // metric configurations, {"type": ..., options}
  int threads = 0;                      // worker threads (0 = all cores)
  double endTime = 0;                   // s, simulated time of each variant (0 = the scene's)
  std::uint64_t maxSteps = 0;           // stop after this many steps (0 = no limit)
  double maxWallSeconds = 0;            // give up on a variant after this wall time (0 = never)
  int repeats = 1;                      // runs per variant; the fastest is reported
  // The `plot` section: time against error with the Pareto front, in the table and as a PNG.
  // Without it (stress sweeps) there is neither.
  bool plot = false;
  std::string plotX = "wall_s", plotY;  // plot columns; plotY "" = the first metric column
  bool logY = true;                     // plot the error on a log axis
};

// Reads and checks a sweep file; `extraEdits` (`bench --set`) are appended to its `set`. Throws
// InputError naming the file and key path.
SweepSpec loadSweep(const std::string& path, const std::vector<std::string>& extraEdits = {});
SweepSpec parseSweep(const std::string& text, const std::string& path,
                     const std::vector<std::string>& extraEdits = {});

// Every variant of the sweep: cases x axes, the first axis varying slowest.
std::vector<SweepVariant> expandVariants(const SweepSpec& spec);

// A JSON value as a --set value and as a short label ("0.4", "tait", "{...}" for objects).
std::string editValue(const nlohmann::json& value);
std::string shortValue(const nlohmann::json& value);

}  // namespace sph::sweep
