// Pictures made of pictures: panels side by side with captions, in a built-in 5x7 pixel font
// (no font files needed). For `sphsplat compare`.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/frame/RenderImage.h"

namespace sph::render::frame {

struct Panel {
  const RenderImage* image;
  std::vector<std::string> caption;  // lines under the image (ASCII; lower case drawn as upper)
};

// Panels left to right in rows of `columns` (0: one row), each with its caption below, on a white
// sheet. Returns the RGB image.
RenderImage composePanels(const std::vector<Panel>& panels, int scale = 2, std::size_t columns = 0);

// Draws `text` at (x, y) (top-left of the first glyph) with glyphs `scale` pixels per dot.
void drawText(RenderImage& image, int x, int y, const std::string& text, int scale, std::uint8_t r,
              std::uint8_t g, std::uint8_t b);

// Width in pixels of `text` drawn at `scale`.
int textWidth(const std::string& text, int scale);

}  // namespace sph::render::frame
