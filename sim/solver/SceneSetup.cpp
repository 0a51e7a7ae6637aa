#include "sim/solver/SceneSetup.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "sim/solver/Boundary.h"
#include "sim/InputError.h"
#include "sim/solver/LatticeSums.h"

namespace sph::solver {

float expectedMaxSpeed(const scene::Scene& scene) {
  const Vec3 g = scene.solver.gravity;
  const float gNorm = g.norm();
  const Vec3 down = gNorm > 0 ? Vec3(g / gNorm) : Vec3(-Vec3::UnitY());
  // Height of a point above the domain's lowest corner along gravity.
  float floor = std::numeric_limits<float>::max();
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) ? scene.domain.hi.x() : scene.domain.lo.x(),
                 (corner & 2) ? scene.domain.hi.y() : scene.domain.lo.y(),
                 (corner & 4) ? scene.domain.hi.z() : scene.domain.lo.z());
    floor = std::min(floor, -p.dot(down));
  }
  float top = floor, speed = 0;
  for (const scene::FluidBlock& f : scene.fluids) {
    const Vec3 hi = f.shape == scene::FluidBlock::Shape::Box
                        ? Vec3(f.hi)
                        : Vec3(f.centre + Vec3::Constant(f.radius));
    const Vec3 lo = f.shape == scene::FluidBlock::Shape::Box
                        ? Vec3(f.lo)
                        : Vec3(f.centre - Vec3::Constant(f.radius));
    top = std::max({top, -hi.dot(down), -lo.dot(down)});
    speed = std::max(speed, f.velocity.norm());
  }
  for (const scene::EmitterDesc& e : scene.emitters) {
    top = std::max(top, -e.position.dot(down));
    speed = std::max(speed, e.speed);
  }
  // rain.feed_fluid: the rain's water enters the fluid at the rain's velocity.
  if (scene.rain && scene.rain->feedFluid)
    speed = std::max(speed, Vec3(scene.rain->wind - scene.rain->fallSpeed * Vec3::UnitY()).norm());
  // Energy bound: a particle starting at the top with the largest initial speed.
  return std::max(std::sqrt(speed * speed + 2.0f * gNorm * std::max(0.0f, top - floor)), 0.1f);
}

DerivedParams deriveParams(const scene::Scene& scene) {
  const scene::SolverParams& s = scene.solver;
  DerivedParams d;
  d.h = s.supportRadius();
  d.kernels = Kernels(d.h);
  const double cell = static_cast<double>(s.spacing) * s.spacing * s.spacing;
  d.mass = static_cast<float>(s.restDensity * cell);
  d.densityNormalisation =
      static_cast<float>(1.0 / (cell * latticeKernelSum(d.kernels, s.densityKernel, s.spacing)));
  d.gradientCorrection =
      static_cast<float>(1.0 / latticeGradientMoment(d.kernels, s.spacing, cell));
  if (s.pressure == scene::PressureSolver::Dfsph && s.support > 2.0f) {
    const double atTwo = latticeJacobiEigenvalue(Kernels(2.0f * s.spacing), s.spacing);
    d.jacobiStep = static_cast<float>(atTwo / latticeJacobiEigenvalue(d.kernels, s.spacing));
  }
  const float gamma = s.eos == scene::EquationOfState::Tait ? 7.0f : 1.0f;
  if (s.stiffness > 0) {
    d.stiffness = s.stiffness;
    d.speedOfSound = s.eos == scene::EquationOfState::Tait
                         ? std::sqrt(gamma * s.stiffness / s.restDensity)
                         : std::sqrt(s.stiffness);
  } else {
    d.speedOfSound =
        s.speedOfSound > 0 ? s.speedOfSound : s.soundSpeedFactor * expectedMaxSpeed(scene);
    const float c2 = d.speedOfSound * d.speedOfSound;
    d.stiffness = s.eos == scene::EquationOfState::Tait ? s.restDensity * c2 / gamma : c2;
  }
  d.viscosity = s.viscosity >= 0 ? s.viscosity : 0.002f * d.h * d.speedOfSound;
  d.boundaryLayers = s.wallLayers();
  d.maxLostParticles = s.maxLostParticles >= 0 ? static_cast<std::uint64_t>(s.maxLostParticles)
                                               : particleBudget(scene).total() / 100;
  return d;
}

float timeStep(const scene::Scene& scene, const DerivedParams& d, float maxSpeed,
               float maxAcceleration) {
  const scene::SolverParams& s = scene.solver;
  // The paper's particle system advances by a fixed tick (seed 000, pseudo-code g_tick).
  if (s.model == scene::SolverModel::Particles) return s.maxTimeStep;
  float dt;
  if (s.pressure == scene::PressureSolver::Dfsph) {
    // DFSPH: the CFL condition on the flow speed only (Bender & Koschier 2017, sec. 4). Not on
    // the acceleration: the solvers' velocity corrections over dt read as accelerations ~ 1/dt,
    // and a bound on them would shrink the step without end.
    dt = maxSpeed > 0 ? s.cfl * d.h / maxSpeed : s.maxTimeStep;
    // And gravity's compression per step: a particle at rest falls g dt^2 within a step, and the
    // constant-density solver must hold that within its mean error. With g dt^2 <= 0.0081 dx
    // (0.09 below) the narrowed still tank of tests/test_dfsph.cpp (dx = 0.01 m, 2.9 ms) settles;
    // at 3.5 ms (1.2%) its mean compression doubled past the threshold and at 4 ms (1.6%) it blew
    // up (docs/notes/2026-11-26-dfsph-peer-dam-break.md, "third session"). 4.1 ms at the peer's
    // dx = 0.02 m.
    const float gravity = s.gravity.norm();
    if (gravity > 0) dt = std::min(dt, 0.09f * std::sqrt(s.spacing / gravity));
  } else {
    dt = s.cfl * d.h / (d.speedOfSound + maxSpeed);
    if (maxAcceleration > 0) dt = std::min(dt, 0.25f * std::sqrt(d.h / maxAcceleration));
  }
  if (d.viscosity > 0) dt = std::min(dt, 0.125f * d.h * d.h / d.viscosity);
  // Monaghan's form (DfsphViscosity.cpp) is explicit too, and stiffer than the Laplacian at close
  // range: its weight r / (r^2 + 0.01 h^2) meets the spiky gradient, which does not vanish as r
  // goes to 0. At nu' = 0.01 m^2/s (the peer's own viscosity) and h = 0.02 m the still tank blew
  // up within 0.6 s at steps of 1.7-2.5 ms and ran at 1.6 ms, 0.04 h^2 / nu'; 0.03 keeps a
  // quarter of margin. At the automatic viscosity it never binds (5.7 ms at spacing 0.01 m,
  // where gravity's bound is 2.9 ms).
  if (s.pressure == scene::PressureSolver::Dfsph &&
      s.viscosityForm == scene::ViscosityForm::Monaghan && d.viscosity > 0) {
    const float monaghanViscosity = scene::SolverParams::kMonaghanShare * d.viscosity;
    dt = std::min(dt, 0.03f * d.h * d.h / monaghanViscosity);
  }
  return std::min(dt, s.maxTimeStep);
}

Aabb defaultDomain(const scene::Scene& scene) {
  Aabb box;
  const float layers = std::max(1.0f, std::ceil(scene.solver.support));
  const float thickness = layers * scene.solver.spacing;
  for (const scene::FluidBlock& f : scene.fluids) {
    if (f.shape == scene::FluidBlock::Shape::Box) {
      box.grow(f.lo), box.grow(f.hi);
    } else {
      box.grow(f.centre - Vec3::Constant(f.radius)), box.grow(f.centre + Vec3::Constant(f.radius));
    }
  }
  for (const scene::EmitterDesc& e : scene.emitters) {
    box.grow(e.position - Vec3::Constant(e.radius)),
        box.grow(e.position + Vec3::Constant(e.radius));
  }
  for (const scene::BoundaryShape& b : scene.boundaries) {
    const Aabb sb = scene::Solid(b, thickness).bounds();
    if (!sb.empty()) box.grow(sb);
  }
  if (box.empty()) box.grow(Vec3::Zero());
  const float h = scene.solver.supportRadius();
  const Vec3 size = box.size();
  const Vec3 margin = (0.1f * size).cwiseMax(Vec3::Constant(4 * h));
  box.lo -= margin, box.hi += margin;
  // Headroom against gravity (splashes rise above the containers).
  const Vec3 g = scene.solver.gravity;
  for (int a = 0; a < 3; ++a) {
    if (g[a] < 0) box.hi[a] += size[a];
    if (g[a] > 0) box.lo[a] -= size[a];
  }
  return box;
}

FluidLattice fluidLattice(const scene::FluidBlock& f, float dx) {
  Vec3 lo = f.lo, hi = f.hi;
  if (f.shape == scene::FluidBlock::Shape::Sphere) {
    lo = f.centre - Vec3::Constant(f.radius), hi = f.centre + Vec3::Constant(f.radius);
  }
  FluidLattice l;
  l.lo = lo;
  for (int a = 0; a < 3; ++a)
    l.n[a] = std::max(0, static_cast<int>(std::lround((hi[a] - lo[a]) / dx)));
  return l;
}

__attribute__((noinline)) Vec3 latticePoint(const FluidLattice& l, float dx, int i, int j, int k) {
  return l.lo + dx * Vec3(i + 0.5f, j + 0.5f, k + 0.5f);
}

bool keepsStartPoint(const scene::FluidBlock& f, const Boundary& boundary, const Vec3& p,
                     float dx) {
  if (f.shape == scene::FluidBlock::Shape::Sphere && (p - f.centre).norm() > f.radius) return false;
  return boundary.distance(p) >= 0.4f * dx;
}

Particles initialFluid(const scene::Scene& scene, const Boundary& boundary, float restDensity) {
  Particles fluid;
  const float dx = scene.solver.spacing;
  std::uint32_t nextId = 0;
  for (const scene::FluidBlock& f : scene.fluids) {
    const FluidLattice l = fluidLattice(f, dx);
    for (int k = 0; k < l.n[2]; ++k)
      for (int j = 0; j < l.n[1]; ++j)
        for (int i = 0; i < l.n[0]; ++i) {
          const Vec3 p = latticePoint(l, dx, i, j, k);
          if (keepsStartPoint(f, boundary, p, dx))
            fluid.append(p, f.velocity, nextId++, restDensity);
        }
  }
  return fluid;
}

namespace {

// At least the lattice points of an emitter's disc of radius r spacings (Emitter's constructor,
// counted row by row without building it; its float test u^2 + w^2 <= r^2 (1 + 1e-6) is widened a
// little more so rounding cannot add a point), or for absurd radii the bound pi (r + 1/sqrt 2)^2
// (every point's unit square lies in the disc grown by half a diagonal).
double emitterLayerBound(double r) {
  const double grown = r * (1 + 1e-5);
  if (grown > 1e6) return kPi * (grown + 0.7072) * (grown + 0.7072);
  const long n = static_cast<long>(std::floor(grown));
  double count = 0;
  for (long i = -n; i <= n; ++i)
    count += 2 * std::floor(std::sqrt(std::max(0.0, grown * grown - double(i) * double(i)))) + 1;
  return count;
}

}  // namespace

std::uint64_t ParticleBudget::total() const {
  std::uint64_t n = blocks + rain;
  for (std::uint64_t e : emitters) n += e;
  return n;
}

ParticleBudget particleBudget(const scene::Scene& scene) {
  ParticleBudget b;
  const double dx = scene.solver.spacing;
  for (const scene::FluidBlock& f : scene.fluids) {
    // initialFluid's lattice: round(extent / dx) points per axis over the block's box.
    Vec3 lo = f.lo, hi = f.hi;
    if (f.shape == scene::FluidBlock::Shape::Sphere)
      lo = f.centre - Vec3::Constant(f.radius), hi = f.centre + Vec3::Constant(f.radius);
    std::uint64_t n = 1;
    for (int a = 0; a < 3; ++a)
      n *= static_cast<std::uint64_t>(std::max(0L, std::lround((hi[a] - lo[a]) / dx)));
    b.blocks += n;
  }
  for (const scene::EmitterDesc& e : scene.emitters) {
    // Emitter::emit: a first layer at `start`, then one for every spacing the jet travels.
    const double active = std::max(0.0, std::min(e.stop, scene.solver.endTime) - e.start);
    const double layers = 2 + std::floor(active * e.speed / dx);
    const double n = layers * emitterLayerBound(e.radius / dx);
    const double bound = e.maxParticles > 0 ? std::min(n, static_cast<double>(e.maxParticles)) : n;
    b.emitters.push_back(static_cast<std::uint64_t>(std::min(bound, 1e18)));
  }
  if (scene.rain && scene.rain->feedFluid) {
    const double ticks = std::floor(scene.solver.endTime * scene.output.fps + 1e-9);
    const double share = scene.rain->dropVolume / (dx * dx * dx);
    // Particles are made from whole particles' worth of landed water (the rest stays pending).
    const double n = std::floor(static_cast<double>(scene.rain->count) * ticks * share + 1e-9);
    b.rain = static_cast<std::uint64_t>(std::min(n, 1e18));
  }
  return b;
}

void requireIdsBelow(const scene::Scene& scene, std::uint64_t limit, const std::string& who,
                     const std::string& reason) {
  const ParticleBudget b = particleBudget(scene);
  if (b.total() <= limit) return;
  auto count = [](std::uint64_t n) {  // 16777216 -> "16,777,216"
    std::string digits = std::to_string(n), text;
    for (std::size_t i = 0; i < digits.size(); ++i) {
      if (i > 0 && (digits.size() - i) % 3 == 0) text += ',';
      text += digits[i];
    }
    return text;
  };
  const std::string limits =
      who + " handles particle ids below " + count(limit) + " (" + reason + ")";
  std::uint64_t largestEmitter = 0;
  for (std::uint64_t e : b.emitters) largestEmitter = std::max(largestEmitter, e);
  char end[32];
  std::snprintf(end, sizeof end, "%g", scene.solver.endTime);
  if (b.rain > 0 && b.blocks <= limit && b.rain >= largestEmitter) {
    throw InputError(scene.sourcePath +
                     ": rain.drop_volume: the rain that feeds the fluid could make up to " +
                     count(b.rain) + " particles by t = " + end + " s (" + count(b.total()) +
                     " in all; at most one landing per drop per output frame); " + limits +
                     ": lower rain.drop_volume or rain.count, end the run earlier, or choose "
                     "another collision.method");
  }
  if (b.blocks > limit || scene.emitters.empty()) {
    throw InputError(scene.sourcePath + ": solver.spacing: the fluid blocks would hold " +
                     count(b.blocks) + " particles; " + limits +
                     ": raise solver.spacing, shrink the fluids, or choose another "
                     "collision.method");
  }
  const std::size_t k = static_cast<std::size_t>(
      std::max_element(b.emitters.begin(), b.emitters.end()) - b.emitters.begin());
  throw InputError(scene.sourcePath + ": emitters[" + std::to_string(k) +
                   "].max_particles: the scene would make up to " + count(b.total()) +
                   " particles by t = " + end + " s (" + count(b.emitters[k]) +
                   " from this emitter); " + limits +
                   ": set max_particles, stop the emitter "
                   "earlier, end the run earlier, or choose another collision.method");
}

}  // namespace sph::solver
