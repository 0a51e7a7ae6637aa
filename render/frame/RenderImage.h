// A rendered frame as the metrics see it: colour, the outward surface normal per pixel and
// whether the surface covers the pixel. Produced by the GL splat renderers (read back from the
// framebuffer) and by the reference ray-marcher.
#pragma once

#include <cstdint>
#include <vector>

namespace sph::render::frame {

// What a GL render reads back: the colour alone (pictures), or with the normal and coverage of
// every pixel (the error figures).
enum class ImageContents { Colour, ColourAndNormals };

struct RenderImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;      // 3 per pixel, row 0 at the top, sRGB-encoded
  std::vector<float> normal;          // 3 per pixel, unit outward normal (0 where uncovered)
  std::vector<std::uint8_t> covered;  // 1 where the surface was drawn
  double seconds = 0;                 // time to produce it
  // normal and covered are empty when the image was rendered as ImageContents::Colour.
  bool hasNormals() const { return !covered.empty(); }

  void resize(int w, int h, bool withNormals = true) {
    width = w, height = h;
    const std::size_t pixels = static_cast<std::size_t>(w) * h;
    rgb.assign(pixels * 3, 0);
    normal.assign(withNormals ? pixels * 3 : 0, 0.0f);
    covered.assign(withNormals ? pixels : 0, 0);
  }
};

// Error figures of `image` against `reference` (same size): PSNR of the colours over the whole
// image (dB), the fraction of the reference's covered pixels that `image` leaves empty (holes),
// and the mean angle between the normals where both cover the pixel (degrees). Both images need
// their normals (std::invalid_argument otherwise).
struct ImageError {
  double psnr = 0, holeFraction = 0, normalErrorDegrees = 0;
  std::size_t referenceCovered = 0;
};
ImageError compareImages(const RenderImage& image, const RenderImage& reference);

// How much of what only the every-particle picture shows (splat::FrameRenderer::
// referenceOfEveryParticle: covered there, not by the SD reference: thin jets and lone drops)
// `image` covers. All three need their coverage.
struct ThinCoverage {
  std::size_t pixels = 0;  // covered by everyParticle and not by reference
  double fraction = 0;     // of those, covered by image (0 when there are none)
};
ThinCoverage thinCoverage(const RenderImage& image, const RenderImage& reference,
                          const RenderImage& everyParticle);

}  // namespace sph::render::frame
