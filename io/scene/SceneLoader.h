// Reads a scene file (JSON, docs/scene-format.md) into sph::Scene. Nothing runs on a bad scene:
// every problem is an InputError naming the file and the key path.
#pragma once

#include <string>
#include <vector>

#include "sim/InputError.h"
#include "sim/scene/Scene.h"

namespace sph::io::scene {

// Longest simulated time a scene may ask for (s): solver.end_time and `run --end`.
constexpr double kMaxEndTime = 1e6;
// Scene key `quality`: presets of solver defaults (docs/scene-format.md, "quality"; the values are
// in io/scene/SimulationSections.cpp).
enum class Quality { Default, Fast, Accurate };
constexpr const char* nameOf(Quality v) {
  switch (v) {
    case Quality::Default:
      return "default";
    case Quality::Fast:
      return "fast";
    case Quality::Accurate:
      return "accurate";
  }
  return nullptr;
}

// Loads and validates `path`. `overrides` are "key.path=value" edits applied to the JSON before
// validation (value parsed as JSON, else taken as a string), e.g. "solver.spacing=0.01".
sph::scene::Scene loadScene(const std::string& path,
                            const std::vector<std::string>& overrides = {});

// Same, from text already in memory; `path` is only used in messages and for the default name.
sph::scene::Scene parseScene(const std::string& text, const std::string& path,
                             const std::vector<std::string>& overrides = {});

}  // namespace sph::io::scene
