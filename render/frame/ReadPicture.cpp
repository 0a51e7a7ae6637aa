#include "render/frame/ReadPicture.h"

#include <cstdint>
#include <vector>

#include "render/gl/PixelTransfer.h"

namespace sph::render::frame {

RenderImage readPicture(GLuint framebuffer, GLenum buffer, int width, int height) {
  RenderImage image;
  image.resize(width, height, false);
  // RGBA, the targets' own layout: on llvmpipe a copy of the rows, where RGB would be converted.
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::vector<std::uint8_t> rgba(4 * pixels);
  gl::readPixels(framebuffer, buffer, {0, 0, width, height}, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data(),
                 gl::RowOrder::TopFirst);
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t k = 0; k < 3; ++k) image.rgb[3 * p + k] = rgba[4 * p + k];
  return image;
}

RenderImage readWindow(int width, int height) {
  return readPicture(0, GL_BACK, width, height);
}

}  // namespace sph::render::frame
