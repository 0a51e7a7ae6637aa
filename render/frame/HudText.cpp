#include "render/frame/HudText.h"

#include <algorithm>

#include "render/frame/Annotate.h"

namespace sph::render::frame {

namespace {
constexpr std::uint8_t kBox[3] = {22, 26, 34};  // dark slate behind the text
constexpr int kMargin = 6;                      // pixels around the text, and from the corner
}  // namespace

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
  image_.upload(w, h, GL_RGB, image.rgb.data(), gl::RowOrder::TopFirst);
  GLint target = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
  image_.blit(static_cast<GLuint>(target), kMargin, height - kMargin - h);
}

void drawTimeline(int width, int height, int played) {
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, width, height);
  glClearColor(0.75f, 0.77f, 0.8f, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  glScissor(0, 0, played, height);
  glClearColor(0.16f, 0.42f, 0.78f, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
}

}  // namespace sph::render::frame
