// A scene as the simulator sees it: plain data, already validated by the loader (io/SceneLoader).
// sim/ never reads files; the JSON format lives in io/ and docs/scene-format.md.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "sim/scene/CameraDesc.h"
#include "sim/scene/CollisionDesc.h"
#include "sim/scene/LightsDesc.h"
#include "sim/scene/RainDesc.h"
#include "sim/scene/RenderDesc.h"
#include "sim/scene/SolverParams.h"
#include "sim/Types.h"

namespace sph::scene {

// A block of fluid filled with particles on the lattice lo + (i + 1/2) spacing.
struct FluidBlock {
  enum class Shape { Box, Sphere } shape = Shape::Box;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // m, box corners (Box)
  Vec3 centre = Vec3::Zero();                 // m (Sphere)
  float radius = 0;                           // m (Sphere)
  Vec3 velocity = Vec3::Zero();               // m/s, initial velocity
};

// A static solid, sampled once with boundary particles (DESIGN.md, "Boundaries").
struct BoundaryShape {
  enum class Kind {
    Tank,    // box container, fluid inside [lo, hi]; open at max y unless closed
    Block,   // solid box obstacle [lo, hi], fluid outside
    Cup,     // open-top cylinder: inner radius, wall height above its bottom centre
    Plane,   // infinite plane through `point`, fluid on the side `normal` points to
    Sphere,  // solid sphere obstacle
  } kind = Kind::Tank;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // m (Tank, Block)
  bool openTop = true;                        // Tank: no lid at max y
  Vec3 centre = Vec3::Zero();                 // m: Cup bottom centre (inner floor), Sphere centre
  float radius = 0;                           // m: Cup inner radius, Sphere radius
  float height = 0;                           // m: Cup wall height above its floor
  Vec3 point = Vec3::Zero();                  // m (Plane)
  Vec3 normal = Vec3::UnitY();                // unit (Plane), points into the fluid side
};

// A nozzle: a disc of particles at `position` facing `direction`, emitted at `speed` between
// start and stop (DESIGN.md, "Emitters").
struct EmitterDesc {
  Vec3 position = Vec3::Zero();     // m, disc centre
  Vec3 direction = -Vec3::UnitY();  // unit
  float radius = 0;                 // m
  float speed = 1;                  // m/s
  double start = 0, stop = 1e30;    // s
  std::size_t maxParticles = 0;     // 0 = unlimited
};

// The HDF5 cache of a run (docs/cache-format.md); `sphsplat run --output` overrides the path.
struct OutputDesc {
  double fps = 30;   // output frames per simulated second
  std::string path;  // HDF5 cache file ("" = no cache)
  // Per-frame datasets, canonical names (x y z vx vy vz ax ay az rho p collide_time id); the
  // loader expands "position", "velocity", "acceleration". Only these are written.
  std::vector<std::string> fields = {"x", "y", "z", "vx", "vy", "vz", "rho", "p", "id"};
  int compression = 1;           // deflate level 0-9 (0 = none; 1 run-length), byte shuffle first
  bool restart = true;           // record each frame's resume state (what fields lack of it)
  bool doublePositions = false;  // x, y, z stored as float64 (converted from the solver's float32)
};

struct Scene {
  std::string name;  // from the file name unless given
  std::string description;
  std::string sourcePath;  // file the scene came from ("" when built in code)
  std::string sourceText;  // its full text (recorded in caches)
  SolverParams solver;
  Aabb domain;  // particles leaving it are removed; too many stop the run
  // s the starting fluid settles before t = 0, nothing joining it (run::Simulation::settle): a
  // fluid block's lattice is not water at rest, and takes seconds to become it.
  double settle = 0;
  std::vector<FluidBlock> fluids;
  std::vector<BoundaryShape> boundaries;
  std::vector<EmitterDesc> emitters;
  OutputDesc output;
  std::optional<CameraDesc> camera;
  CameraPath cameraPath;  // camera.path: key frames the camera follows over time (empty = still)
  std::optional<CollisionDesc> collision;  // the `collision` section; none = no collision pass
  std::optional<RenderDesc> render;        // draw frames while simulating
  std::optional<RainDesc> rain;            // view-dependent rain (seed 002); none = no rain
  std::optional<LightsDesc> lights;        // particles as lights (seed 004); none = no light code
};

}  // namespace sph::scene
