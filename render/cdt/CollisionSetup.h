// Builds the step's collision pass from the scene's `collision` section (DESIGN.md, "The CDT
// collision pass"): nothing without the section or with method "none"; cdt-gl is the only method
// that creates a GL context (headless EGL), so a scene that does not ask for it never gets one.
#pragma once

#include <memory>
#include <string>

#include "sim/CollisionPass.h"
#include "sim/scene/Scene.h"

namespace sph::render::cdt {

// Throws InputError with one line when cdt-gl cannot run here (no EGL, GL too old, a shader
// that does not compile), naming the failure and suggesting cdt-cpu.
std::unique_ptr<CollisionPass> makeCollisionPass(const scene::Scene& scene);

// One line for `run --verbose`: the method and its main parameters.
std::string describeCollision(const scene::Scene& scene);

}  // namespace sph::render::cdt
