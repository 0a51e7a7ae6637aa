#include "io/cache/CacheFormat.h"

#include <cstring>
#include <sstream>
#include <tuple>
#include <type_traits>

#include "sim/rain/RainStepper.h"

namespace sph::io::cache {
namespace {

template <class A, class B>
constexpr bool sameMember(A a, B b) {
  if constexpr (std::is_same_v<A, B>)
    return a == b;
  else
    return false;
}

using IdArray = std::vector<std::uint32_t> Particles::*;

struct FieldEntry {
  Field field;
  const char* name;
  FloatArray member;  // the Particles array behind a float field
  IdArray idMember;   // the one behind id
};

// The cache's datasets, in Field order, each with the Particles array it stores.
constexpr FieldEntry kFields[kFieldCount] = {
    {Field::X, "x", &Particles::x, nullptr},
    {Field::Y, "y", &Particles::y, nullptr},
    {Field::Z, "z", &Particles::z, nullptr},
    {Field::VX, "vx", &Particles::vx, nullptr},
    {Field::VY, "vy", &Particles::vy, nullptr},
    {Field::VZ, "vz", &Particles::vz, nullptr},
    {Field::AX, "ax", &Particles::ax, nullptr},
    {Field::AY, "ay", &Particles::ay, nullptr},
    {Field::AZ, "az", &Particles::az, nullptr},
    {Field::Rho, "rho", &Particles::rho, nullptr},
    {Field::P, "p", &Particles::p, nullptr},
    {Field::CollideTime, "collide_time", &Particles::collideTime, nullptr},
    {Field::Id, "id", nullptr, &Particles::id},
};

// Particles arrays the cache deliberately does not store, each with the reason. None today: every
// array is a dataset (output.fields chooses which a scene writes). A field added to Particles must
// be added to kFields or listed here, or the static_assert below fails the build.
constexpr std::tuple<> kNotCached{};

template <class Member>
constexpr bool isNotCached(Member member) {
  return std::apply([&](auto... skipped) { return (sameMember(member, skipped) || ... || false); },
                    kNotCached);
}

// Whether kFields lists the arrays of Particles::fields() in that order, skipping only those in
// kNotCached, and nothing else.
constexpr bool cacheListsEveryParticlesField() {
  std::size_t next = 0;
  bool ok = true;
  auto visit = [&](auto member) {
    if (isNotCached(member)) return;
    if (next >= kFieldCount) {
      ok = false;
      return;
    }
    const FieldEntry& e = kFields[next++];
    if constexpr (std::is_same_v<decltype(member), FloatArray>)
      ok = ok && e.member == member && e.idMember == nullptr;
    else
      ok = ok && e.idMember == member && e.member == nullptr;
  };
  std::apply([&](auto... member) { (visit(member), ...); }, Particles::fields());
  for (std::size_t f = 0; f < kFieldCount; ++f)
    ok = ok && static_cast<std::size_t>(kFields[f].field) == f;
  return ok && next == kFieldCount;
}
static_assert(cacheListsEveryParticlesField(),
              "io/cache/CacheFormat.cpp: kFields must list every array of Particles::fields(), in that "
              "order, except those in kNotCached");

FieldSet setOf(std::initializer_list<Field> fields) {
  FieldSet s;
  for (Field f : fields) s.set(static_cast<std::size_t>(f));
  return s;
}

// Mixes raw bytes into a 64-bit FNV-1a hash.
class Fingerprint {
 public:
  template <class T>
  void add(const T& v) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    for (unsigned char b : bytes) hash_ = (hash_ ^ b) * 1099511628211ull;
  }
  void add(const Vec3& v) { add(v.x()), add(v.y()), add(v.z()); }
  std::string hex() const {
    std::ostringstream s;
    s.width(16);
    s.fill('0');
    s << std::hex << hash_;
    return s.str();
  }

 private:
  std::uint64_t hash_ = 1469598103934665603ull;
};

}  // namespace

const char* fieldName(Field f) {
  return kFields[static_cast<std::size_t>(f)].name;
}

std::optional<Field> fieldByName(const std::string& name) {
  for (const FieldEntry& e : kFields) {
    if (name == e.name) return e.field;
  }
  return std::nullopt;
}

std::optional<std::size_t> frameOfRootLink(const std::string& name) {
  const std::size_t hash = name.rfind('#');
  if (hash == std::string::npos || hash + 1 == name.size()) return std::nullopt;
  // The records' names less their frame number ("Step#"), and the renderers' common prefix.
  const std::string kind = name.substr(0, name.find('#') + 1);
  bool record = kind == kRenderPrefix;
  for (const std::string& frameZero : {stepName(0), vectorsName(0), restartName(0), rainName(0)})
    record = record || kind == frameZero.substr(0, frameZero.size() - 1);
  if (!record) return std::nullopt;
  std::size_t frame = 0;
  for (std::size_t i = hash + 1; i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9') return std::nullopt;
    frame = frame * 10 + static_cast<std::size_t>(name[i] - '0');
  }
  return frame;
}

FloatArray floatMember(Field f) {
  return kFields[static_cast<std::size_t>(f)].member;
}

FieldSet defaultFields() {
  return setOf({Field::X, Field::Y, Field::Z, Field::VX, Field::VY, Field::VZ, Field::Rho, Field::P,
                Field::Id});
}

FieldSet restartFields() {
  return setOf({Field::X, Field::Y, Field::Z, Field::VX, Field::VY, Field::VZ, Field::CollideTime,
                Field::Id});
}

FieldSet parseFields(const std::vector<std::string>& names, std::string& error) {
  FieldSet set;
  error.clear();
  for (const std::string& name : names) {
    if (name == "position")
      set |= setOf({Field::X, Field::Y, Field::Z});
    else if (name == "velocity")
      set |= setOf({Field::VX, Field::VY, Field::VZ});
    else if (name == "acceleration")
      set |= setOf({Field::AX, Field::AY, Field::AZ});
    else if (auto f = fieldByName(name))
      set.set(static_cast<std::size_t>(*f));
    else {
      std::string known;
      for (const FieldEntry& e : kFields) known += std::string(known.empty() ? "" : ", ") + e.name;
      error =
          "unknown field \"" + name + "\"; known: " + known + ", position, velocity, acceleration";
      return set;
    }
  }
  const FieldSet xyz = setOf({Field::X, Field::Y, Field::Z});
  if ((set & xyz) != xyz) {
    error =
        "expected \"x\", \"y\" and \"z\" (or \"position\") among the fields: every frame needs "
        "positions";
  }
  return set;
}

std::string describeFields(const FieldSet& fields) {
  std::string out;
  for (const FieldEntry& e : kFields) {
    if (fields[static_cast<std::size_t>(e.field)])
      out += std::string(out.empty() ? "" : " ") + e.name;
  }
  return out;
}

std::vector<Parameter> solverParameters(const sph::scene::Scene& scene,
                                        const solver::DerivedParams& d) {
  const sph::scene::SolverParams& s = scene.solver;
  auto number = [](const char* name, double v) { return Parameter{name, v, "", false}; };
  auto text = [](const char* name, const char* v) { return Parameter{name, 0, v, true}; };
  return {
      number("solver.spacing", s.spacing),
      number("solver.support_radius", d.h),
      number("solver.particle_mass", d.mass),
      number("solver.rest_density", s.restDensity),
      number("solver.speed_of_sound", d.speedOfSound),
      number("solver.stiffness", d.stiffness),
      number("solver.viscosity", d.viscosity),
      number("solver.cfl", s.cfl),
      number("solver.max_time_step", s.maxTimeStep),
      number("solver.gravity_x", s.gravity.x()),
      number("solver.gravity_y", s.gravity.y()),
      number("solver.gravity_z", s.gravity.z()),
      number("solver.boundary_layers", d.boundaryLayers),
      text("solver.eos", enumName(s.eos)),
      text("solver.density_kernel", enumName(s.densityKernel)),
      text("solver.walls",
           enumName(s.noSlipWalls ? sph::scene::Walls::NoSlip : sph::scene::Walls::Slip)),
      text("solver.clamp_negative_pressure", s.clampNegativePressure ? "true" : "false"),
  };
}

bool isAutomaticParameter(const sph::scene::Scene& scene, const std::string& name) {
  const sph::scene::SolverParams& s = scene.solver;
  if (name == "solver.stiffness") return s.stiffness <= 0;
  if (name == "solver.speed_of_sound") return s.stiffness <= 0 && s.speedOfSound <= 0;
  if (name == "solver.viscosity") return s.viscosity < 0;
  return false;
}

std::string dynamicsFingerprint(const sph::scene::Scene& scene) {
  Fingerprint f;
  const sph::scene::SolverParams& s = scene.solver;
  f.add(static_cast<int>(s.model)), f.add(s.spacing), f.add(s.support), f.add(s.restDensity),
      f.add(s.viscosity), f.add(s.noSlipWalls);
  f.add(static_cast<int>(s.eos)), f.add(static_cast<int>(s.densityKernel)), f.add(s.speedOfSound);
  f.add(s.stiffness), f.add(s.clampNegativePressure), f.add(s.cfl), f.add(s.maxTimeStep),
      f.add(s.gravity);
  f.add(s.boundaryLayers);
  f.add(scene.domain.lo), f.add(scene.domain.hi);
  for (const sph::scene::FluidBlock& b : scene.fluids) {
    f.add(static_cast<int>(b.shape)), f.add(b.lo), f.add(b.hi), f.add(b.centre), f.add(b.radius),
        f.add(b.velocity);
  }
  for (const sph::scene::BoundaryShape& b : scene.boundaries) {
    f.add(static_cast<int>(b.kind)), f.add(b.lo), f.add(b.hi), f.add(b.openTop), f.add(b.centre),
        f.add(b.radius);
    f.add(b.height), f.add(b.point), f.add(b.normal);
  }
  for (const sph::scene::EmitterDesc& e : scene.emitters) {
    f.add(e.position), f.add(e.direction), f.add(e.radius), f.add(e.speed), f.add(e.start),
        f.add(e.stop);
    f.add(static_cast<std::uint64_t>(e.maxParticles));
  }
  // A feeding rain adds water where its drops land: all that decides where they are (the rain,
  // the camera that it follows, the pictures' aspect) is dynamics then. Nothing is added
  // otherwise, so caches without it keep their fingerprints.
  if (scene.rain && scene.rain->feedFluid && scene.camera) {
    const sph::scene::RainDesc& r = *scene.rain;
    f.add(static_cast<std::uint64_t>(r.count)), f.add(r.near), f.add(r.far), f.add(r.fallSpeed);
    f.add(r.wind), f.add(r.seed), f.add(static_cast<int>(r.spawn)),
        f.add(static_cast<int>(r.sampling));
    f.add(r.region.lo), f.add(r.region.hi), f.add(r.dropVolume);
    const sph::scene::CameraDesc& c = *scene.camera;
    f.add(c.position), f.add(c.target), f.add(c.up), f.add(c.fovYDegrees);
    for (const sph::scene::CameraKey& k : scene.cameraPath)
      f.add(k.time), f.add(k.position), f.add(k.target), f.add(k.fovYDegrees);
    f.add(rain::RainStepper::sceneAspect(scene));
  }
  return f.hex();
}

}  // namespace sph::io::cache
