// Draws the drops of a sim/rain/RainSystem as camera-facing streaks (seed 002 sections 3.2-3.3):
// each drop a quad from where it was one exposure ago to where it is, so it lies along the drop's
// projected velocity, textured by one layer (picked at random per drop) of an array texture of
// streak images (render/rain/StreakImages.h), coloured by the spotlight of eq. (10)-(13) and
// alpha-blended into the splat frame after the water (render/frame/FrameLayer.h): depth tested
// against the water and solids, not written. rain.draw picks how: "cpu" (default) rasterises the
// quads on the CPU (render/rain/StreakRaster.h) against the frame's depth, read back once with its
// colour, composes the result over that colour and copies it back; "triangles" draws two GL
// triangles per drop.
#pragma once

#include <memory>
#include <vector>

#include "render/frame/FrameLayer.h"
#include "render/gl/GlHandle.h"
#include "render/gl/PixelTransfer.h"
#include "render/gl/ShaderLibrary.h"
#include "render/rain/StreakRaster.h"
#include "sim/rain/RainSystem.h"
#include "sim/scene/RainDesc.h"

namespace sph::render::rain {

class RainRenderer final : public frame::FrameLayer {
 public:
  // Builds the program and the streak array texture. Needs a current context.
  explicit RainRenderer(const scene::RainDesc& desc,
                        const gl::ShaderLibrary& shaders = gl::ShaderLibrary::fromEnvironment());
  Order order() const override { return Order::AfterSplats; }
  // Uploads the drops to draw (their positions, streak layers and the common velocity).
  void setDrops(const sph::rain::RainSystem& rain);
  void draw(const scene::CameraFrame& camera, const frame::Lighting& lighting) override;

  std::size_t drops() const { return count_; }
  // "cpu": the fragments of the last draw that passed the depth test; null for "triangles".
  const StreakRaster* raster() const { return raster_.get(); }

 private:
  void drawTriangles(const scene::CameraFrame& camera, const frame::Lighting& lighting);
  void drawCpu(const scene::CameraFrame& camera, const frame::Lighting& lighting);
  scene::RainDesc desc_;
  // "cpu": the rasteriser, the drops it draws, the frame's depth and colour, and the composed
  // colour put back on the frame.
  std::unique_ptr<StreakRaster> raster_;
  std::vector<Vec3> positions_;
  std::vector<std::uint8_t> layers_;
  std::vector<float> depth_;
  std::vector<std::uint8_t> colour_;  // RGBA8, row 0 at the bottom
  gl::ImageBlit composed_;
  // "triangles":
  gl::Program program_;
  gl::Texture streaks_;
  gl::Buffer drops_;    // vec4 per drop, read by rain.vert as a storage buffer
  gl::Buffer indices_;  // two triangles per drop over its four corners
  gl::VertexArray vao_;
  std::size_t count_ = 0;
  std::size_t dropCapacity_ = 0, indexCapacity_ = 0;  // drops the buffers hold
  std::vector<float> packed_;
  Vec3 velocity_ = Vec3::Zero();
};

// The tint of a drop outside the spotlight's cone (or with no spotlight): the paper takes the
// background colour (eq. (13)) on its night sky; ours is a bright sky, so a drop is drawn as
// this fraction of it, darker than what it passes in front of.
constexpr float kUnlitTint = 0.55f;

}  // namespace sph::render::rain
