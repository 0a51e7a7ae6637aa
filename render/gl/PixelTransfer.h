// Pixels between the CPU and GL, one way each: reading them back (a framebuffer's rectangle, or a
// whole texture) and putting a CPU image on a framebuffer (uploaded into a texture, then copied by
// a blit: llvmpipe copies the rows, where a textured draw would run a fragment program over every
// pixel). GL's rows run bottom to top, pictures' and PNGs' top to bottom: RowOrder says which a
// CPU buffer holds. Rows are tightly packed (pack and unpack alignment 1 while a transfer runs;
// the caller's settings are kept). Need a current context.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "render/gl/GlHandle.h"

namespace sph::render::gl {

enum class RowOrder { BottomFirst, TopFirst };

// A rectangle of a framebuffer in window coordinates, (x, y) its bottom-left corner.
struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
};

// Bytes of one pixel of `format` (GL_RGBA, GL_RGB, GL_RED, GL_RED_INTEGER, GL_DEPTH_COMPONENT) in
// `type` (GL_UNSIGNED_BYTE, GL_HALF_FLOAT, GL_FLOAT, GL_UNSIGNED_INT); std::invalid_argument for
// any other.
std::size_t pixelBytes(GLenum format, GLenum type);

// Reads `rect` of `framebuffer` (0: the window's) into `out`, which holds rect's pixels of
// pixelBytes(format, type) each. `buffer`: the colour buffer read (GL_COLOR_ATTACHMENTn,
// GL_BACK); not used for GL_DEPTH_COMPONENT. The read framebuffer binding and that framebuffer's
// read buffer are left as they were.
void readPixels(GLuint framebuffer, GLenum buffer, const PixelRect& rect, GLenum format,
                GLenum type, void* out, RowOrder rows = RowOrder::BottomFirst);

// Level 0 of `texture`, all of it, into `out` (`bytes` long), rows bottom first.
void readTexture(GLuint texture, GLenum format, GLenum type, std::size_t bytes, void* out);
// One layer of level 0 of an array texture of width x height texels, the same way.
void readTextureLayer(GLuint texture, int layer, int width, int height, GLenum format, GLenum type,
                      std::size_t bytes, void* out);

// A CPU image put on framebuffers: an RGBA8 texture of its size (made again when the size
// changes) with a framebuffer to blit from.
class ImageBlit {
 public:
  // Uploads width x height pixels of `format` (GL_RGBA or GL_RGB, 8 bits a channel).
  void upload(int width, int height, GLenum format, const void* pixels,
              RowOrder rows = RowOrder::BottomFirst);
  // Copies the uploaded image pixel for pixel into `target` (0: the window's), its bottom-left
  // corner at (x, y), into every draw buffer of `target`. No blending and no depth test (a scissor
  // test that is on clips it).
  void blit(GLuint target, int x, int y) const;
  // The uploaded image as a texture, for a pass that samples it instead.
  GLuint texture() const { return texture_.id(); }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  Texture texture_;
  Framebuffer framebuffer_;
  int width_ = 0, height_ = 0;
  std::vector<std::uint8_t> flipped_;  // a top-first image's rows in GL's order
};

}  // namespace sph::render::gl
