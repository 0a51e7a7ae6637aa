// The response half of every collision method (cdt-cpu, exact, octree; shaders/cdt_collide.vert
// is the GLSL copy): where a particle started the step, where it ends without a collision, and
// what a collision with its nearest partner does to it. Seed 000, section 3.2, pseudo-code lines
// 20-30, with the readings of docs/collision.md.
//
// Arithmetic: double on float inputs, rounded to float once, in the order the GLSL uses.
#pragma once

#include <cmath>
#include <cstdint>

namespace sph::collision {

// Start of the step (p0, v0) and its end without a collision (pf, vf).
struct StepState {
  float p0[3], v0[3], pf[3], vf[3];
};

// integrate = true: P, V are the start; the particle integrates with A (the paper's free branch,
// lines 26-30: temp = v + g tick; pos += temp tick). integrate = false: P, V were already
// integrated over dt (the SPH step); the start is P - V dt, V - A dt.
inline StepState stepState(const float P[3], const float V[3], const float A[3], double dt,
                           bool integrate) {
  StepState s;
  for (int k = 0; k < 3; ++k) {
    if (integrate) {
      s.p0[k] = P[k], s.v0[k] = V[k];
      s.vf[k] = static_cast<float>(static_cast<double>(V[k]) + static_cast<double>(A[k]) * dt);
      s.pf[k] = static_cast<float>(static_cast<double>(P[k]) + static_cast<double>(s.vf[k]) * dt);
    } else {
      s.pf[k] = P[k], s.vf[k] = V[k];
      s.p0[k] = static_cast<float>(static_cast<double>(P[k]) - static_cast<double>(V[k]) * dt);
      s.v0[k] = static_cast<float>(static_cast<double>(V[k]) - static_cast<double>(A[k]) * dt);
    }
  }
  return s;
}

struct ResponseParams {
  bool paper = false;  // seed 000's bounce; else our separation
  double range = 0;    // m
  float speedFactor = 0.2f;
  float cooldown = 0;  // s; 0 = no cooldown
  double dt = 0;       // s
};

struct Outcome {
  float p[3], v[3], collideTime;
};

// No partner: the free end; the cooldown runs down by the step (line 29).
inline Outcome freeOutcome(const StepState& s, float collideTime, double dt) {
  Outcome o;
  for (int k = 0; k < 3; ++k) o.p[k] = s.pf[k], o.v[k] = s.vf[k];
  o.collideTime = static_cast<float>(static_cast<double>(collideTime) - dt);
  return o;
}

// A partner at `partner`, distance^2 `distance2` (< range^2) from `cur` (curr_pos: the particle's
// own start, or its base texel in the paper's reading). Ids split coincident pairs.
inline Outcome collideOutcome(const StepState& s, const float cur[3], const float partner[3],
                              double distance2, std::uint32_t self, std::uint32_t other,
                              float collideTime, const ResponseParams& r) {
  // Line 22: direction away from the partner.
  const double len = std::sqrt(distance2);
  double dir[3];
  if (len > 0.0) {
    for (int k = 0; k < 3; ++k)
      dir[k] = (static_cast<double>(cur[k]) - static_cast<double>(partner[k])) / len;
  } else {
    dir[0] = 0, dir[1] = self > other ? 1.0 : -1.0, dir[2] = 0;
  }
  double np[3], nv[3];
  if (r.paper) {
    // Lines 21-24: speed x speed_factor (0.2 in the code; the text's "reduced by 20%" would be
    // 0.8), from the start of the step, times the step (the pseudo-code has no tick here).
    const double speed = static_cast<double>(r.speedFactor) *
                         std::sqrt(static_cast<double>(s.v0[0]) * static_cast<double>(s.v0[0]) +
                                   static_cast<double>(s.v0[1]) * static_cast<double>(s.v0[1]) +
                                   static_cast<double>(s.v0[2]) * static_cast<double>(s.v0[2]));
    for (int k = 0; k < 3; ++k) {
      nv[k] = dir[k] * speed;
      np[k] = static_cast<double>(s.p0[k]) + nv[k] * r.dt;
    }
  } else {
    // Separation: out to the range (half the overlap; the partner takes the other half when it
    // sees us) and no velocity towards the partner.
    const double push = 0.5 * (r.range - len);
    const double vn = static_cast<double>(s.vf[0]) * dir[0] +
                      static_cast<double>(s.vf[1]) * dir[1] + static_cast<double>(s.vf[2]) * dir[2];
    const double remove = vn < 0.0 ? vn : 0.0;
    for (int k = 0; k < 3; ++k) {
      np[k] = static_cast<double>(s.pf[k]) + dir[k] * push;
      nv[k] = static_cast<double>(s.vf[k]) - remove * dir[k];
    }
  }
  Outcome o;
  for (int k = 0; k < 3; ++k)
    o.p[k] = static_cast<float>(np[k]), o.v[k] = static_cast<float>(nv[k]);
  // Line 23: the cooldown starts (or, without one, keeps running down).
  o.collideTime =
      r.cooldown > 0.0f ? r.cooldown : static_cast<float>(static_cast<double>(collideTime) - r.dt);
  return o;
}

}  // namespace sph::collision
