// cdt-gl: the CDT collision pass of seeds 000/001 (section 3) in OpenGL 4.5 - one vertex-shader
// invocation per particle (shaders/cdt_collide.vert) reads the collision detection texture the
// previous step wrote, responds, and writes its new state by transform feedback into the other of
// two buffers that swap roles every step; the new positions then fill the next texture (RGBA32F
// position + id, the nearest to the collision camera per texel; more layers by depth peeling),
// either as the paper does - rasterised points, depth test - or with a compute shader and atomic
// minima (the default: the same texture, much faster on llvmpipe; docs/collision.md).
//
// Needs a current gl::GlContext. The state stays on the GPU between steps: upload() and download()
// are the only transfers, so a caller that steps the paper's particle system (integrate = true)
// moves nothing to the CPU unless it asks. cdt-cpu (sim/cdt/CdtCpu) is the reference it must match.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/gl/GlHandle.h"
#include "render/gl/ShaderLibrary.h"
#include "sim/Particles.h"
#include "sim/cdt/CdtCpu.h"

namespace sph::render::cdt {

// std140 mirror of the uniform block CdtParams in shaders/cdt_common.glsl.
struct CdtParamsGpu {
  float projView[16];       // mat4 u_ProjView, column-major
  std::int32_t texture[4];  // ivec4 u_Texture: width, height, layers, r
  std::int32_t control[4];  // ivec4 u_Control: adaptive r cap, flags
  float scalars[4];         // vec4 u_Scalars: range (m), dt (s), speed_factor, cooldown (s)
  float scalars2[4];        // vec4 u_Scalars2: texels per metre at depth 1
};
static_assert(sizeof(CdtParamsGpu) == 128,
              "must match uniform block CdtParams (std140) in shaders/cdt_common.glsl");

// One particle in the vertex buffers and the transform feedback buffers: the inputs a_* and the
// xfb_buffer 0 outputs v_* of shaders/cdt_collide.vert (xfb_stride 48).
struct CdtParticleGpu {
  float position[3];      // a_PositionTime.xyz (m)
  float collideTime;      // a_PositionTime.w (s)
  float velocity[3];      // a_Velocity (m/s)
  std::uint32_t id;       // a_Id
  float acceleration[3];  // a_Acceleration (m/s^2)
  float unused;
};
static_assert(sizeof(CdtParticleGpu) == 48,
              "must match xfb_stride 48 of xfb_buffer 0 in shaders/cdt_collide.vert");
static_assert(sizeof(sph::cdt::Diagnostics) == 16,
              "must match v_Diag (uvec4, xfb_buffer 1) in shaders/cdt_collide.vert");

class CdtGl {
 public:
  // Compiles the shaders and allocates both textures (a current context is required). Throws
  // gl::ShaderError / gl::GlUnavailable.
  explicit CdtGl(const sph::cdt::Settings& settings,
                 const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());
  ~CdtGl();
  CdtGl(const CdtGl&) = delete;
  CdtGl& operator=(const CdtGl&) = delete;

  // Copies `p` into the buffer the next step reads (its order is the draw order).
  void upload(const Particles& p);
  // One step (see sph::cdt::CdtCpu::step for `integrate`): one draw of points with transform
  // feedback and the texture write, then one draw per further layer; swaps buffers and textures.
  void step(float dt, bool integrate);
  // Copies the last step's positions, velocities and cooldowns into `p` (same size and order as
  // uploaded).
  void download(Particles& p) const;
  std::vector<sph::cdt::Diagnostics> diagnostics() const;
  // The texture the next step will read, as sph::cdt::Texture (for tests).
  sph::cdt::Texture readTexture() const;
  void reset();  // empty texture, as on the first step

  std::size_t size() const { return count_; }
  const sph::cdt::Settings& settings() const { return settings_; }
  bool textureValid() const { return valid_; }

 private:
  void allocate(std::size_t capacity);
  void writeAtomic(int side);  // the texture from state_[side], by cdt_write.comp

  sph::cdt::Settings settings_;
  gl::Program collide_, peel_, write_;  // write_: compute (atomic) texture write
  gl::Buffer params_;
  gl::Buffer state_[2];  // ping-pong: state_[current_] is read, the other written
  gl::Buffer diagnostics_;
  gl::Buffer writeKeys_;  // per particle: next texel, depth bits (for the atomic write)
  gl::VertexArray vertexArray_[2];
  gl::TransformFeedback feedback_;
  // Per side: the RGBA32F layers as one 2D array texture (the query indexes layers by a loop
  // variable; a sampler array indexed that way misreads on llvmpipe) and per layer the key of the
  // particle kept in each texel as two R32UI images (depth bits, draw index).
  gl::Texture colour_[2], depthKey_[2][sph::cdt::kMaxLayers], indexKey_[2][sph::cdt::kMaxLayers];
  gl::Renderbuffer depth_;
  gl::Framebuffer framebuffer_[2][sph::cdt::kMaxLayers];
  int current_ = 0;  // buffer and texture side read by the next step
  std::size_t count_ = 0, capacity_ = 0;
  bool valid_ = false;
  mutable std::vector<CdtParticleGpu> staging_;
};

}  // namespace sph::render::cdt
