#include "render/gl/PixelTransfer.h"

#include <algorithm>
#include <stdexcept>

namespace sph::render::gl {
namespace {

// Swaps row k with row rows - 1 - k of a tightly packed image.
void flipRows(std::uint8_t* data, std::size_t rowBytes, int rows) {
  for (int k = 0; k < rows / 2; ++k) {
    std::uint8_t* a = data + static_cast<std::size_t>(k) * rowBytes;
    std::uint8_t* b = data + static_cast<std::size_t>(rows - 1 - k) * rowBytes;
    std::swap_ranges(a, a + rowBytes, b);
  }
}

// Sets a pixel-store alignment for the life of the object, then puts the caller's back.
class Alignment {
 public:
  Alignment(GLenum name, GLint value) : name_(name) {
    glGetIntegerv(name, &previous_);
    glPixelStorei(name, value);
  }
  ~Alignment() { glPixelStorei(name_, previous_); }
  Alignment(const Alignment&) = delete;
  Alignment& operator=(const Alignment&) = delete;

 private:
  GLenum name_;
  GLint previous_ = 4;
};

}  // namespace

std::size_t pixelBytes(GLenum format, GLenum type) {
  std::size_t components = 0;
  switch (format) {
    case GL_RGBA:
      components = 4;
      break;
    case GL_RGB:
      components = 3;
      break;
    case GL_RED:
    case GL_RED_INTEGER:
    case GL_DEPTH_COMPONENT:
      components = 1;
      break;
    default:
      throw std::invalid_argument("pixelBytes: a pixel format no transfer uses");
  }
  switch (type) {
    case GL_UNSIGNED_BYTE:
      return components;
    case GL_HALF_FLOAT:
      return 2 * components;
    case GL_FLOAT:
    case GL_UNSIGNED_INT:
      return 4 * components;
    default:
      throw std::invalid_argument("pixelBytes: a pixel type no transfer uses");
  }
}

void readPixels(GLuint framebuffer, GLenum buffer, const PixelRect& rect, GLenum format,
                GLenum type, void* out, RowOrder rows) {
  if (rect.width <= 0 || rect.height <= 0) return;
  GLint bound = 0, readBuffer = GL_NONE;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &bound);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  const bool colour = format != GL_DEPTH_COMPONENT;
  if (colour) {
    glGetIntegerv(GL_READ_BUFFER, &readBuffer);
    glReadBuffer(buffer);
  }
  {
    const Alignment pack(GL_PACK_ALIGNMENT, 1);
    glReadPixels(rect.x, rect.y, rect.width, rect.height, format, type, out);
  }
  if (colour) glReadBuffer(static_cast<GLenum>(readBuffer));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(bound));
  if (rows == RowOrder::TopFirst)
    flipRows(static_cast<std::uint8_t*>(out),
             static_cast<std::size_t>(rect.width) * pixelBytes(format, type), rect.height);
}

void readTexture(GLuint texture, GLenum format, GLenum type, std::size_t bytes, void* out) {
  const Alignment pack(GL_PACK_ALIGNMENT, 1);
  glGetTextureImage(texture, 0, format, type, static_cast<GLsizei>(bytes), out);
}

void readTextureLayer(GLuint texture, int layer, int width, int height, GLenum format, GLenum type,
                      std::size_t bytes, void* out) {
  const Alignment pack(GL_PACK_ALIGNMENT, 1);
  glGetTextureSubImage(texture, 0, 0, 0, layer, width, height, 1, format, type,
                       static_cast<GLsizei>(bytes), out);
}

void ImageBlit::upload(int width, int height, GLenum format, const void* pixels, RowOrder rows) {
  if (width <= 0 || height <= 0) return;
  if (width != width_ || height != height_) {
    texture_ = Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(texture_.id(), 1, GL_RGBA8, width, height);
    if (framebuffer_.id() == 0) framebuffer_ = Framebuffer::create();
    glNamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, texture_.id(), 0);
    glNamedFramebufferReadBuffer(framebuffer_.id(), GL_COLOR_ATTACHMENT0);
    width_ = width, height_ = height;
  }
  if (rows == RowOrder::TopFirst) {
    const std::size_t rowBytes =
        static_cast<std::size_t>(width) * pixelBytes(format, GL_UNSIGNED_BYTE);
    const auto* from = static_cast<const std::uint8_t*>(pixels);
    flipped_.resize(rowBytes * static_cast<std::size_t>(height));
    for (int row = 0; row < height; ++row)
      std::copy_n(from + static_cast<std::size_t>(height - 1 - row) * rowBytes, rowBytes,
                  flipped_.data() + static_cast<std::size_t>(row) * rowBytes);
    pixels = flipped_.data();
  }
  const Alignment unpack(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(texture_.id(), 0, 0, 0, width, height, format, GL_UNSIGNED_BYTE, pixels);
}

void ImageBlit::blit(GLuint target, int x, int y) const {
  if (width_ == 0) return;
  glBlitNamedFramebuffer(framebuffer_.id(), target, 0, 0, width_, height_, x, y, x + width_,
                         y + height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

}  // namespace sph::render::gl
