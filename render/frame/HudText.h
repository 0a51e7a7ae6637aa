// What `sphsplat view` draws over its picture: a few lines of text (frame, time, splats, frame
// time), drawn with the built-in 5x7 font of Annotate.h into a small image and copied onto the
// current framebuffer's top-left corner on a dark box, so they read over water and background;
// and the timeline bar along its bottom.
#pragma once

#include <string>
#include <vector>

#include "render/gl/PixelTransfer.h"

namespace sph::render::frame {

class HudText {
 public:
  // Draws `lines` at the top-left of the bound draw framebuffer (its size: width x height
  // pixels). Needs a current context.
  void draw(const std::vector<std::string>& lines, int width, int height, int scale = 2);

 private:
  gl::ImageBlit image_;
};

// The timeline: a grey bar `height` pixels high across the bottom of the bound draw framebuffer,
// `width` pixels wide, its first `played` pixels blue (scissored clears, no shader). Leaves the
// scissor test off.
void drawTimeline(int width, int height, int played);

}  // namespace sph::render::frame
