// The element-wise passes of a step: time integration, the wall safety net and the guard. Built
// without -ffast-math (sim/solver/SphPasses.cpp says why that matters for reproducibility).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/Parallel.h"
#include "sim/solver/SphPasses.h"
#include "sim/StabilityError.h"

namespace sph::solver {

// The paper's particles feel gravity only; they interact through the collision pass alone.
void applyGravityOnly(StepContext& c) {
  Particles& f = c.fluid;
  const Vec3 g = c.solver.gravity;
  parallelFor(f.size(), [&](std::size_t i) { f.ax[i] = g.x(), f.ay[i] = g.y(), f.az[i] = g.z(); });
}

MotionBounds motionBounds(const Particles& f) {
  const std::size_t n = f.size();
  // Largest speed and acceleration for the next step size. max is exact, so the split of the
  // reduction between threads does not change the result.
  float v2 = 0, a2 = 0;
#pragma omp parallel for reduction(max : v2, a2) schedule(static)
  for (long long i = 0; i < static_cast<long long>(n); ++i) {
    v2 = std::max(v2, f.vx[i] * f.vx[i] + f.vy[i] * f.vy[i] + f.vz[i] * f.vz[i]);
    a2 = std::max(a2, f.ax[i] * f.ax[i] + f.ay[i] * f.ay[i] + f.az[i] * f.az[i]);
  }
  return {std::sqrt(v2), std::sqrt(a2)};
}

// Symplectic Euler: velocities first, then positions with the new velocities.
MotionBounds integrate(StepContext& c) {
  Particles& f = c.fluid;
  const float dt = c.dt;
  parallelFor(f.size(), [&](std::size_t i) {
    f.vx[i] += dt * f.ax[i], f.vy[i] += dt * f.ay[i], f.vz[i] += dt * f.az[i];
    f.x[i] += dt * f.vx[i], f.y[i] += dt * f.vy[i], f.z[i] += dt * f.vz[i];
  });
  return motionBounds(f);
}

void predictVelocity(StepContext& c) {
  Particles& f = c.fluid;
  const float dt = c.dt;
  parallelFor(f.size(), [&](std::size_t i) {
    f.vx[i] += dt * f.ax[i], f.vy[i] += dt * f.ay[i], f.vz[i] += dt * f.az[i];
  });
}

MotionBounds integratePositions(StepContext& c) {
  Particles& f = c.fluid;
  const float dt = c.dt;
  parallelFor(f.size(), [&](std::size_t i) {
    f.x[i] += dt * f.vx[i], f.y[i] += dt * f.vy[i], f.z[i] += dt * f.vz[i];
  });
  return motionBounds(f);
}

void enforceBoundaries(StepContext& c) {
  if (c.boundary.solids().empty()) return;
  Particles& f = c.fluid;
  const float dt = c.dt;
  parallelFor(f.size(), [&](std::size_t i) {
    Vec3 x = f.position(i), v = f.velocity(i);
    const Vec3 xOld = x - dt * v;
    if (c.boundary.enforce(xOld, x, v)) f.setPosition(i, x), f.setVelocity(i, v);
  });
}

namespace {

// Keeps the particles (and their warm start) for which keep(i) holds, in their order.
template <class Keep>
void compact(Particles& f, PressureWarmStart& warm, Keep&& keep) {
  const std::size_t n = f.size();
  std::vector<std::uint8_t> kept(n);
  for (std::size_t i = 0; i < n; ++i) kept[i] = keep(i) ? 1 : 0;
  auto squeeze = [&](auto& field) {
    std::size_t to = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (kept[i]) field[to++] = field[i];
    }
    field.resize(to);
  };
  f.forEachField(squeeze);
  for (std::vector<float>* w : warm.fields()) {
    if (w->size() == n) squeeze(*w);
  }
}

}  // namespace

std::uint64_t checkStability(StepContext& c, const Aabb& d, std::uint64_t step, double time,
                             std::uint64_t lostBefore, std::uint64_t maxLost) {
  Particles& f = c.fluid;
  const std::size_t n = f.size();
  // Fast vectorisable screen; only when it fails do we look for the culprits.
  int bad = 0;
#pragma omp parallel for reduction(| : bad) schedule(static)
  for (long long i = 0; i < static_cast<long long>(n); ++i) {
    const bool finite = std::isfinite(f.x[i] + f.y[i] + f.z[i] + f.vx[i] + f.vy[i] + f.vz[i]);
    const bool inside = f.x[i] >= d.lo.x() && f.x[i] <= d.hi.x() && f.y[i] >= d.lo.y() &&
                        f.y[i] <= d.hi.y() && f.z[i] >= d.lo.z() && f.z[i] <= d.hi.z();
    bad |= (!finite || !inside) ? 1 : 0;
  }
  if (!bad) return 0;
  auto finiteAt = [&](std::size_t i) {
    return f.position(i).allFinite() && f.velocity(i).allFinite();
  };
  // Report the lowest particle id at fault, so the message does not depend on the sort; a
  // non-finite state first (it always stops the run), else a particle outside the domain.
  std::size_t worst = n, outside = 0;
  bool worstFinite = true;
  for (std::size_t i = 0; i < n; ++i) {
    const bool finite = finiteAt(i);
    if (finite && d.contains(f.position(i))) continue;
    if (finite) ++outside;
    const bool better =
        worst == n || (!finite && worstFinite) || (finite == worstFinite && f.id[i] < f.id[worst]);
    if (better) worst = i, worstFinite = finite;
  }
  // The screen sums six values: finite ones near FLT_MAX can overflow it with every particle
  // finite and inside. Nothing to report then (and no index n to read).
  if (worst == n) return 0;
  // Particles that left the domain (a splash over an open wall) are removed and counted, as
  // DualSPHysics excludes them, up to the scene's tolerance.
  if (worstFinite && lostBefore + outside <= maxLost) {
    compact(f, c.warmStart,
            [&](std::size_t i) { return !finiteAt(i) || d.contains(f.position(i)); });
    return outside;
  }
  const Vec3 x = f.position(worst), v = f.velocity(worst);
  std::ostringstream msg;
  msg.precision(6);
  msg << "numerical blow-up at step " << step << ", t = " << time << " s: particle " << f.id[worst];
  if (!worstFinite) {
    msg << " has a non-finite state";
  } else {
    msg << " left the domain [" << d.lo.x() << ", " << d.lo.y() << ", " << d.lo.z() << "] - ["
        << d.hi.x() << ", " << d.hi.y() << ", " << d.hi.z() << "]";
  }
  msg << " (position " << x.x() << ", " << x.y() << ", " << x.z() << " m; velocity " << v.x()
      << ", " << v.y() << ", " << v.z() << " m/s; last dt " << c.dt << " s)";
  if (worstFinite) {
    msg << "; " << (lostBefore + outside)
        << " particles lost, more than solver.max_lost_particles = " << maxLost;
  }
  throw StabilityError(
      worstFinite ? StabilityError::Kind::LeftDomain : StabilityError::Kind::NonFinite, step, time,
      f.id[worst], x, v, msg.str());
}

}  // namespace sph::solver
