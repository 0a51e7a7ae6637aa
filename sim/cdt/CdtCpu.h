// The CDT algorithm of seeds 000/001 (section 3.2) on the CPU: cdt-cpu, the reference that
// cdt-gl (render/cdt/CdtGl) must match - same texel addressing bit for bit, same colliding set,
// same outputs to rounding (tests/test_cdt_gl.cpp). One step:
//   1. each particle projects its position at the start of the step to its base texel and reads
//      the (2r+1)^2 texels around it in every layer of the texture the previous step wrote;
//   2. the nearest stored position within `range` (not its own) is its partner; it responds;
//   3. the new positions are written to the texture: per texel the nearest to the camera (depth
//      test), ties to the earlier particle (draw order); layer k holds the k-th nearest (peeling).
// The first step finds an empty texture and collides nothing, as in the paper.
//
// Per-particle arithmetic runs in double on float inputs and is rounded to float once, in the
// order the GLSL (shaders/cdt_collide.vert) uses, so FMA contraction on either side cannot change
// a texel or a partner.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "sim/scene/CollisionDesc.h"
#include "sim/CollisionPass.h"
#include "sim/Particles.h"
#include "sim/scene/Scene.h"
#include "sim/solver/SceneSetup.h"
#include "sim/cdt/CdtCamera.h"
#include "sim/cdt/CdtConstants.h"

namespace sph::cdt {

// The resolved parameters of one CDT pass (render/cdt/CdtGl.cpp packs them into the GLSL block
// CdtParams).
struct Settings {
  View view;
  float range = 0;  // m
  float speedFactor = 0.2f;
  float cooldown = 0;     // s
  int texelRange = 1;     // r (or the adaptive r's lower bound 1)
  int maxTexelRange = 4;  // adaptive r cap
  int layers = 1;
  std::uint32_t flags = 0;   // kFlagTexelPosition | kFlagAdaptiveRange | kFlagPaperResponse
  bool rasterWrite = false;  // cdt-gl: fill the texture by rasterising points (else atomics)
};
Settings makeSettings(const scene::CollisionDesc& collision,
                      const std::optional<scene::CameraDesc>& renderCamera);

// The CDT's one input limit: the texture stores particle ids as floats, exact below 2^24
// (kMaxId). For a scene whose collision method is cdt-cpu or cdt-gl, throws InputError naming the
// scene key to change when the scene could make more particles than that by its end time. The
// scene loader calls it, and render::cdt::makeCollisionPass again once `run --end` is applied,
// so a run never starts that would pass the limit.
inline void requireIdsInRange(const scene::Scene& scene) {
  if (!scene.collision) return;
  const scene::CollisionMethod m = scene.collision->method;
  if (m != scene::CollisionMethod::CdtCpu && m != scene::CollisionMethod::CdtGl) return;
  solver::requireIdsBelow(scene, kMaxId, std::string("the ") + enumName(m) + " collision pass",
                          "2^24: its texture stores them as floats");
}

// Per-particle record of one step, identical in cdt-cpu and cdt-gl (the GLSL output v_Diag).
struct Diagnostics {
  std::uint32_t partner = kNoPartner;  // id of the nearest particle found within range
  std::uint32_t candidates = 0;        // stored positions within range that it saw
  std::uint32_t texel = kOffscreen;    // base texel x | y << 16, if it searched
  std::uint32_t texelRange = 0;        // r it searched with (0 = did not search)
};
static_assert(sizeof(Diagnostics) == 16);

// The texture: one RGBA32F image per layer (xyz position in m, w id or kEmptyTexel), and per
// texel the (depth bits, draw index) key that put it there (the GL side's RG32UI image).
struct Texture {
  int width = 0, height = 0, layers = 0;
  std::vector<std::array<float, 4>> texels;  // layer-major: [layer][y][x]
  std::vector<std::uint64_t> keys;
  const std::array<float, 4>& at(int layer, int x, int y) const {
    return texels[(static_cast<std::size_t>(layer) * height + y) * width + x];
  }
};

// The key that orders particles within a texel: nearer first, then earlier in draw order. Depth
// is in [0, 1], where the float bit patterns order like the values.
std::uint64_t texelKey(float depth, std::uint32_t index);

class CdtCpu {
 public:
  explicit CdtCpu(const Settings& settings);

  // One step on `p`, in place. integrate = true: `p` is the state at the start of the step and an
  // uncollided particle integrates with its acceleration (the paper's particle system);
  // integrate = false: `p` was already integrated over dt (the SPH step) and the start is
  // reconstructed as x - v dt, v - a dt.
  void step(Particles& p, float dt, bool integrate);
  void reset();  // back to an empty texture

  const Settings& settings() const { return settings_; }
  const Texture& texture() const { return texture_; }
  bool textureValid() const { return valid_; }
  // Per particle of the last step, in that step's particle order.
  const std::vector<Diagnostics>& diagnostics() const { return diagnostics_; }
  // With recording on, every (searcher id, stored id) within range the last step saw.
  void setRecordPairs(bool on) { recordPairs_ = on; }
  const std::vector<std::pair<std::uint32_t, std::uint32_t>>& seenPairs() const { return pairs_; }

  // Writes the texture from positions (step 3 alone): for tests and the recall tools, which
  // measure detection on a texture of the same positions.
  void writeTexture(const float* x, const float* y, const float* z, const std::uint32_t* id,
                    std::size_t n);

 private:
  Settings settings_;
  Texture texture_;
  bool valid_ = false;
  bool recordPairs_ = false;
  std::vector<Diagnostics> diagnostics_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs_;
  std::vector<std::uint32_t> touched_;         // texels written last time, to clear cheaply
  std::vector<std::int64_t> texelOfParticle_;  // scratch: texel index or -1
  std::vector<std::uint64_t> keyOfParticle_;
  std::vector<float> nx_, ny_, nz_, nvx_, nvy_, nvz_, nt_;  // scratch: the new state
};

// cdt-cpu as the step's collision pass (integrate = false).
class CdtCpuPass final : public CollisionPass {
 public:
  explicit CdtCpuPass(const Settings& settings) : cdt_(settings) {}
  std::string name() const override { return enumName(scene::CollisionMethod::CdtCpu); }
  void apply(Particles& particles, const CollisionContext& context) override;

 private:
  CdtCpu cdt_;
};

}  // namespace sph::cdt
