// The pixel transfers every renderer shares (render/gl/PixelTransfer.h): an image uploaded and
// blitted comes back pixel for pixel, rows in the order asked for, whatever the row length, and
// the caller's pixel-store alignment and read framebuffer are as they were.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "render/gl/GlContext.h"
#include "render/gl/GlHandle.h"
#include "render/gl/PixelTransfer.h"

namespace sph::render::gl {
namespace {

// A width x height RGBA8 framebuffer, cleared to (1, 2, 3, 4) / 255.
struct Target {
  Texture colour;
  Framebuffer framebuffer;
  Target(int width, int height)
      : colour(Texture::create(GL_TEXTURE_2D)), framebuffer(Framebuffer::create()) {
    glTextureStorage2D(colour.id(), 1, GL_RGBA8, width, height);
    glNamedFramebufferTexture(framebuffer.id(), GL_COLOR_ATTACHMENT0, colour.id(), 0);
    const float clear[4] = {1 / 255.0f, 2 / 255.0f, 3 / 255.0f, 4 / 255.0f};
    glClearNamedFramebufferfv(framebuffer.id(), GL_COLOR, 0, clear);
  }
};

std::uint8_t value(int x, int y, int k) {
  return static_cast<std::uint8_t>(40 * y + 8 * x + k + 10);
}

TEST(PixelTransfer, AnImageBlittedComesBackRowsInTheOrderAskedFor) {
  GlContext context = GlContext::headless();
  const int w = 3, h = 2;  // RGB rows of 9 bytes: a transfer at alignment 4 would skew them
  std::vector<std::uint8_t> topFirst(3 * w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k) topFirst[3 * (y * w + x) + k] = value(x, y, k);
  Target target(5, 4);
  ImageBlit image;
  image.upload(w, h, GL_RGB, topFirst.data(), RowOrder::TopFirst);
  EXPECT_EQ(image.width(), w);
  EXPECT_EQ(image.height(), h);
  image.blit(target.framebuffer.id(), 1, 2);  // the image's top row lands on the target's top row

  std::vector<std::uint8_t> back(4 * 5 * 4);
  readPixels(target.framebuffer.id(), GL_COLOR_ATTACHMENT0, {0, 0, 5, 4}, GL_RGBA, GL_UNSIGNED_BYTE,
             back.data(), RowOrder::TopFirst);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) {
      const std::uint8_t* p = &back[4 * (y * 5 + x)];
      const bool inside = x >= 1 && x < 1 + w && y < h;
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(p[k], inside ? value(x - 1, y, k) : k + 1) << x << " " << y << " " << k;
      EXPECT_EQ(p[3], inside ? 255 : 4);
    }
  // Bottom first: the same rows the other way up.
  std::vector<std::uint8_t> bottomFirst(back.size());
  readPixels(target.framebuffer.id(), GL_COLOR_ATTACHMENT0, {0, 0, 5, 4}, GL_RGBA, GL_UNSIGNED_BYTE,
             bottomFirst.data());
  for (int y = 0; y < 4; ++y)
    for (int i = 0; i < 4 * 5; ++i)
      EXPECT_EQ(bottomFirst[4 * 5 * y + i], back[4 * 5 * (3 - y) + i]) << y << " " << i;
  // A rectangle of it, in RGB: rows of 6 bytes.
  std::vector<std::uint8_t> rect(3 * 2 * 2);
  readPixels(target.framebuffer.id(), GL_COLOR_ATTACHMENT0, {1, 2, 2, 2}, GL_RGB, GL_UNSIGNED_BYTE,
             rect.data(), RowOrder::TopFirst);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(rect[3 * (y * 2 + x) + k], value(x, y, k));
}

TEST(PixelTransfer, LeavesTheCallersAlignmentAndReadFramebuffer) {
  GlContext context = GlContext::headless();
  Target target(4, 4), other(4, 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 8);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, other.framebuffer.id());
  std::vector<std::uint8_t> pixels(4 * 16, 7);
  ImageBlit image;
  image.upload(4, 4, GL_RGBA, pixels.data());
  image.blit(target.framebuffer.id(), 0, 0);
  readPixels(target.framebuffer.id(), GL_COLOR_ATTACHMENT0, {0, 0, 4, 4}, GL_RGBA, GL_UNSIGNED_BYTE,
             pixels.data());
  readTexture(target.colour.id(), GL_RGBA, GL_UNSIGNED_BYTE, pixels.size(), pixels.data());
  EXPECT_EQ(pixels[0], 7);
  GLint pack = 0, unpack = 0, read = 0;
  glGetIntegerv(GL_PACK_ALIGNMENT, &pack);
  glGetIntegerv(GL_UNPACK_ALIGNMENT, &unpack);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
  EXPECT_EQ(pack, 8);
  EXPECT_EQ(unpack, 2);
  EXPECT_EQ(static_cast<GLuint>(read), other.framebuffer.id());
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST(PixelTransfer, PixelBytesOfTheFormatsInUse) {
  EXPECT_EQ(pixelBytes(GL_RGBA, GL_UNSIGNED_BYTE), 4u);
  EXPECT_EQ(pixelBytes(GL_RGB, GL_UNSIGNED_BYTE), 3u);
  EXPECT_EQ(pixelBytes(GL_RGBA, GL_FLOAT), 16u);
  EXPECT_EQ(pixelBytes(GL_RGBA, GL_HALF_FLOAT), 8u);
  EXPECT_EQ(pixelBytes(GL_DEPTH_COMPONENT, GL_FLOAT), 4u);
  EXPECT_EQ(pixelBytes(GL_RED_INTEGER, GL_UNSIGNED_INT), 4u);
  EXPECT_THROW(pixelBytes(GL_BGRA, GL_UNSIGNED_BYTE), std::invalid_argument);
}

}  // namespace
}  // namespace sph::render::gl
