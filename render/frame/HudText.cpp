#include "render/frame/HudText.h"

#include <algorithm>

#include "render/frame/Annotate.h"

namespace sph::render::frame {

namespace {
constexpr std::uint8_t kBox[3] = {22, 26, 34};  // dark slate behind the text
constexpr int kMargin = 6;                      // pixels around the text, and from the corner
}  // namespace

HudText::HudText() : framebuffer_(gl::Framebuffer::create()) {}

void HudText::draw(const std::vector<std::string>& lines, int width, int height, int scale) {
  if (lines.empty()) return;
  int textWidthPx = 0;
  for (const std::string& line : lines) textWidthPx = std::max(textWidthPx, textWidth(line, scale));
  const int lineHeight = 9 * scale;  // 7 dots and 2 of leading
  const int w = std::min(textWidthPx + 2 * kMargin, width - kMargin);
  const int h = std::min(static_cast<int>(lines.size()) * lineHeight + 2 * kMargin - 2 * scale,
                         height - kMargin);
  if (w <= 0 || h <= 0) return;
  RenderImage image;
  image.resize(w, h, false);
  for (int p = 0; p < w * h; ++p) std::copy_n(kBox, 3, &image.rgb[3 * static_cast<std::size_t>(p)]);
  for (std::size_t k = 0; k < lines.size(); ++k)
    drawText(image, kMargin, kMargin + static_cast<int>(k) * lineHeight, lines[k], scale, 245, 246,
             248);
  // GL's rows run bottom to top.
  std::vector<std::uint8_t> rows(image.rgb.size());
  for (int row = 0; row < h; ++row)
    std::copy_n(&image.rgb[static_cast<std::size_t>(h - 1 - row) * w * 3], w * 3,
                &rows[static_cast<std::size_t>(row) * w * 3]);
  if (w != textureWidth_ || h != textureHeight_) {
    texture_ = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(texture_.id(), 1, GL_RGBA8, w, h);
    glNamedFramebufferTexture(framebuffer_.id(), GL_COLOR_ATTACHMENT0, texture_.id(), 0);
    textureWidth_ = w, textureHeight_ = h;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(texture_.id(), 0, 0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
  GLint target = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
  glBlitNamedFramebuffer(framebuffer_.id(), static_cast<GLuint>(target), 0, 0, w, h, kMargin,
                         height - kMargin - h, kMargin + w, height - kMargin, GL_COLOR_BUFFER_BIT,
                         GL_NEAREST);
}

}  // namespace sph::render::frame
