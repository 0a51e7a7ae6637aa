// Names and numbers of the HDF5 cache layout (docs/cache-format.md), shared by the writer, the
// reader, the scene loader (which validates output.fields) and the tests. One place, so a name
// cannot drift between the file and its readers.
#pragma once

#include <bitset>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/Particles.h"
#include "sim/scene/Scene.h"
#include "sim/solver/SceneSetup.h"

namespace sph::io::cache {

// What identifies a sphsplat cache among HDF5 files (root attributes).
inline constexpr const char* kFormatAttr = "sphsplat_format";
inline constexpr const char* kFormatName = "sphsplat-cache";
inline constexpr const char* kFormatVersionAttr = "sphsplat_format_version";
inline constexpr std::int64_t kFormatVersion = 1;

// Root groups that are not frames. None starts with "Step": H5Part readers count every root
// group whose name starts with "Step" as a time step.
inline constexpr const char* kBoundaryGroup = "Boundary";

// Attributes of the root group.
inline constexpr const char* kStatusAttr = "run_status";  // rewritten in place, kStatusWidth bytes
inline constexpr std::size_t kStatusWidth = 512;

// H5Part names: the frame group and its time attribute (exactly these, ParaView looks them up).
inline constexpr const char* kStepPrefix = "Step#";
inline constexpr const char* kTimeAttr = "TimeValue";
inline std::string stepName(std::size_t frame) {
  return kStepPrefix + std::to_string(frame);
}
// The resume record of a frame, a root group beside its Step group.
inline std::string restartName(std::size_t frame) {
  return "Restart#" + std::to_string(frame);
}

// The rain's drops of a frame (io/cache/RainCache.h), a root group beside its Step group; only in the
// caches of scenes with a rain section.
inline std::string rainName(std::size_t frame) {
  return "Rain#" + std::to_string(frame);
}
inline constexpr const char* kRainDropsAttr = "drops";

// A rendered image of a frame: the root dataset Render#<renderer>#<frame>. Linked from the root,
// like every object the writer adds after the first commit: the root is the one group a reader
// loads when it opens the file, so a reader never meets a group the writer has changed since.
inline constexpr const char* kRenderPrefix = "Render#";
inline std::string renderedFrameName(const std::string& renderer, std::size_t frame) {
  return kRenderPrefix + renderer + "#" + std::to_string(frame);
}
// Caches written before that kept them as /Render/<renderer>/Frame#N; still read.
inline constexpr const char* kLegacyRenderGroup = "Render";
inline std::string legacyRenderedFrameName(std::size_t frame) {
  return "Frame#" + std::to_string(frame);
}

// The frame a root link records (Step#N, Vectors#N, Restart#N, Rain#N, Render#<renderer>#N),
// nothing for the root's other links (Boundary, the point indexes Index#L, ...).
std::optional<std::size_t> frameOfRootLink(const std::string& name);

// The per-particle arrays a frame can hold, in the order they are written and listed.
enum class Field : unsigned { X, Y, Z, VX, VY, VZ, AX, AY, AZ, Rho, P, CollideTime, Id, Count };
inline constexpr std::size_t kFieldCount = static_cast<std::size_t>(Field::Count);
using FieldSet = std::bitset<kFieldCount>;

// Dataset name of each field (H5Part: x y z vx vy vz rho p id).
const char* fieldName(Field f);
std::optional<Field> fieldByName(const std::string& name);
// The float array of Particles behind a float field (every field but Id).
using FloatArray = std::vector<float> Particles::*;
FloatArray floatMember(Field f);

// The group of [n][3] views of a frame's vectors: virtual datasets whose columns are the Step
// group's components (nothing is stored twice), what XDMF readers take geometry and vectors from
// (ParaView's Xdmf3 readers take neither separate components nor functions joining them).
inline std::string vectorsName(std::size_t frame) {
  return "Vectors#" + std::to_string(frame);
}
struct VectorView {
  const char* name;
  Field components[3];
};
// position (written for every frame that has particles; also /Boundary/position), velocity and
// acceleration (when the frame holds their three components).
inline constexpr VectorView kVectorViews[] = {
    {"position", {Field::X, Field::Y, Field::Z}},
    {"velocity", {Field::VX, Field::VY, Field::VZ}},
    {"acceleration", {Field::AX, Field::AY, Field::AZ}},
};
inline bool hasAll(const FieldSet& fields, const VectorView& view) {
  for (Field c : view.components)
    if (!fields[static_cast<std::size_t>(c)]) return false;
  return true;
}

// The point numbers 0, 1, ..., L-1 (uint32) as the root dataset Index#L, L a power of two of at
// least 1024. ParaView draws cells, not bare points, and its Xdmf3 readers (its default for
// .xdmf) make cells only from a topology's connectivity, which XDMF cannot count out by itself:
// the sidecar gives a point set of n points n vertex cells, the first n numbers of the index of
// pointIndexLength(n). Written once per length a cache needs (a few, of a few kB each).
inline std::size_t pointIndexLength(std::size_t points) {
  std::size_t length = 1024;
  while (length < points) length *= 2;
  return length;
}
inline std::string pointIndexName(std::size_t points) {
  return "Index#" + std::to_string(pointIndexLength(points));
}

// Datasets of a resume record beside the restart fields: the pressure solver's per-particle state
// (RunState's warmStart), each written only by the runs that have it: DFSPH's warm start, WCSPH's
// wall shares (solver.wall_pressure "extrapolated").
inline constexpr const char* kWarmDensityName = "dfsph_warm_density";
inline constexpr const char* kWarmDivergenceName = "dfsph_warm_divergence";
inline constexpr const char* kWallShareName = "wcsph_wall_share";

// x y z vx vy vz rho p id: what a scene writes unless its output section says otherwise.
FieldSet defaultFields();
// x y z vx vy vz id collide_time: what a resume needs. The other fields (acceleration, density,
// pressure) are recomputed by the first step before anything reads them.
FieldSet restartFields();
// Parses the scene's output.fields ("x", "position" = x y z, "velocity", "acceleration").
// Returns an error text for the first unknown name, in `error`.
FieldSet parseFields(const std::vector<std::string>& names, std::string& error);
// "x y z vx ..." in the canonical order.
std::string describeFields(const FieldSet& fields);

// One resolved solver parameter, recorded as a root attribute ("solver.spacing" = 0.005).
struct Parameter {
  std::string name;
  double number = 0;  // exact: every solver value is a float or an int
  std::string text;   // for the named choices ("tait"); then number is unused
  bool isText = false;
};
// The parameters the run actually used (automatic values resolved). A resume compares them with
// the scene it is given, to name what differs.
std::vector<Parameter> solverParameters(const sph::scene::Scene& scene,
                                        const solver::DerivedParams& derived);
// True for a parameter `scene` leaves automatic, computed from the rest of the scene: the speed
// of sound and stiffness (from the fluid's height) and the viscosity (from those).
bool isAutomaticParameter(const sph::scene::Scene& scene, const std::string& name);

// A hash of everything in a scene that changes the motion (solver, domain, fluids, boundaries,
// emitters; not the end time nor the output section), as 16 hex digits. A resume refuses a scene
// whose fingerprint differs from the cache's.
std::string dynamicsFingerprint(const sph::scene::Scene& scene);

}  // namespace sph::io::cache
