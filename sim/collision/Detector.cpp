#include "sim/collision/Detector.h"

#include "sim/Parallel.h"

namespace sph::collision {

DetectorPass::DetectorPass(std::unique_ptr<Detector> detector, const scene::CollisionDesc& desc)
    : detector_(std::move(detector)), desc_(desc) {}

void DetectorPass::apply(Particles& p, const CollisionContext& context) {
  const std::size_t n = p.size();
  const double dt = context.dt;
  x0_.resize(n), y0_.resize(n), z0_.resize(n), searching_.resize(n);
  parallelFor(n, [&](std::size_t i) {
    const float P[3] = {p.x[i], p.y[i], p.z[i]}, V[3] = {p.vx[i], p.vy[i], p.vz[i]},
                A[3] = {p.ax[i], p.ay[i], p.az[i]};
    const StepState s = stepState(P, V, A, dt, false);
    x0_[i] = s.p0[0], y0_[i] = s.p0[1], z0_[i] = s.p0[2];
    searching_[i] = p.collideTime[i] < 0.0f ? 1 : 0;  // seed 000, line 8
  });
  detector_->detect(x0_.data(), y0_.data(), z0_.data(), n, desc_.range, searching_.data(), partner_,
                    nullptr);

  ResponseParams r;
  r.paper = desc_.response == scene::CollisionResponse::Paper;
  r.range = desc_.range;
  r.speedFactor = desc_.speedFactor;
  r.cooldown = desc_.cooldown;
  r.dt = dt;
  // Every particle reads only the start positions (x0_) and writes only itself.
  parallelFor(n, [&](std::size_t i) {
    const float P[3] = {p.x[i], p.y[i], p.z[i]}, V[3] = {p.vx[i], p.vy[i], p.vz[i]},
                A[3] = {p.ax[i], p.ay[i], p.az[i]};
    const StepState s = stepState(P, V, A, dt, false);
    const std::uint32_t j = partner_[i];
    Outcome o;
    if (j == kNone) {
      o = freeOutcome(s, p.collideTime[i], dt);
    } else {
      const float other[3] = {x0_[j], y0_[j], z0_[j]};
      o = collideOutcome(s, s.p0, other,
                         distance2(s.p0[0], s.p0[1], s.p0[2], other[0], other[1], other[2]),
                         p.id[i], p.id[j], p.collideTime[i], r);
    }
    p.x[i] = o.p[0], p.y[i] = o.p[1], p.z[i] = o.p[2];
    p.vx[i] = o.v[0], p.vy[i] = o.v[1], p.vz[i] = o.v[2];
    p.collideTime[i] = o.collideTime;
  });
}

}  // namespace sph::collision
