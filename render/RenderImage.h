// A rendered frame as the metrics see it: colour, the outward surface normal per pixel and
// whether the surface covers the pixel. Produced by the GL splat renderers (read back from the
// framebuffer) and by the reference ray-marcher.
#pragma once

#include <cstdint>
#include <vector>

namespace sph::render {

struct RenderImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;      // 3 per pixel, row 0 at the top, sRGB-encoded
  std::vector<float> normal;          // 3 per pixel, unit outward normal (0 where uncovered)
  std::vector<std::uint8_t> covered;  // 1 where the surface was drawn
  double seconds = 0;                 // time to produce it

  void resize(int w, int h) {
    width = w, height = h;
    rgb.assign(static_cast<std::size_t>(w) * h * 3, 0);
    normal.assign(static_cast<std::size_t>(w) * h * 3, 0.0f);
    covered.assign(static_cast<std::size_t>(w) * h, 0);
  }
};

// Error figures of `image` against `reference` (same size): PSNR of the colours over the whole
// image (dB), the fraction of the reference's covered pixels that `image` leaves empty (holes),
// and the mean angle between the normals where both cover the pixel (degrees).
struct ImageError {
  double psnr = 0, holeFraction = 0, normalErrorDegrees = 0;
  std::size_t referenceCovered = 0;
};
ImageError compareImages(const RenderImage& image, const RenderImage& reference);

}  // namespace sph::render
