// The scene loader's parts (io/scene/SimulationSections.cpp reads the simulation's sections,
// io/scene/ViewSections.cpp what is seen: camera, render, rain, lights; io/scene/SceneLoader.cpp
// the top level) and the value checks they share. Internal to io/.
#pragma once

#include <string>

#include "io/scene/JsonReader.h"
#include "io/scene/SceneLoader.h"
#include "sim/scene/Scene.h"

namespace sph::io::scene {

std::string formatVec(const Vec3& v);  // "[x, y, z]" for messages
bool integerIn(double v, double lo, double hi);
// Fails at "max" unless lo < hi on every axis.
void requireOrdered(JsonReader& r, const Vec3& lo, const Vec3& hi);

// `solver` (its defaults those of the `quality` preset), `fluids[i]`, `boundaries[i]`,
// `emitters[i]` (a nozzle at least half a particle `spacing` wide), `output`, `collision`
// (docs/scene-format.md).
sph::scene::SolverParams readSolver(JsonReader r, Quality quality);
sph::scene::FluidBlock readFluid(JsonReader r);
sph::scene::BoundaryShape readBoundary(JsonReader r);
sph::scene::EmitterDesc readEmitter(JsonReader r, float spacing);
sph::scene::OutputDesc readOutput(JsonReader r);
sph::scene::CollisionDesc readCollision(JsonReader r, const sph::scene::SolverParams& solver);

// `camera` (and its key frames into *path when given), `render`, `rain`, `lights`
// (docs/scene-format.md).
sph::scene::CameraDesc readCamera(JsonReader r, sph::scene::CameraPath* path = nullptr);
sph::scene::RenderDesc readRender(JsonReader r);
sph::scene::RainDesc readRain(JsonReader r);
sph::scene::LightsDesc readLights(JsonReader r);

}  // namespace sph::io::scene
