// Something drawn into the same frame as the water's splats, with the same camera and lighting:
// the solids (opaque, before the splats: render/solids), rain streaks (blended, after them). A
// layer draws into the colour picture only; the error figures' normal target is the water's
// alone, as the reference ray-marcher's is.
#pragma once

#include "render/frame/Lighting.h"
#include "sim/scene/Camera.h"

namespace sph::render::frame {

class FrameLayer {
 public:
  enum class Order { BeforeSplats, AfterSplats };
  virtual ~FrameLayer() = default;
  virtual Order order() const = 0;
  // Draws with the current framebuffer, viewport and depth buffer (a GL context is current).
  virtual void draw(const scene::CameraFrame& camera, const Lighting& lighting) = 0;
  // The deferred pipeline (ExtraLights::deferred(); render/frame/DeferredTarget.h): writes the
  // layer's opaque surfaces into the bound G-buffer (shaders/gbuffer_out.glsl) and returns true;
  // false: the layer cannot, and is drawn forward (draw()) after the lighting pass.
  virtual bool drawGBuffer(const scene::CameraFrame& /*camera*/, const Lighting& /*lighting*/) {
    return false;
  }
};

}  // namespace sph::render::frame
