// A few lines of text over a picture on screen (`sphsplat view`: frame, time, splats, frame
// time), drawn with the built-in 5x7 font of Annotate.h into a small image and copied onto the
// current framebuffer's top-left corner on a dark box, so they read over water and background.
#pragma once

#include <string>
#include <vector>

#include "render/gl/GlHandle.h"

namespace sph::render::frame {

class HudText {
 public:
  // Needs a current context.
  HudText();
  // Draws `lines` at the top-left of the bound framebuffer (its size: width x height pixels).
  void draw(const std::vector<std::string>& lines, int width, int height, int scale = 2);

 private:
  gl::Texture texture_;
  gl::Framebuffer framebuffer_;
  int textureWidth_ = 0, textureHeight_ = 0;
};

}  // namespace sph::render::frame
