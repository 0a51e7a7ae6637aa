#include "render/frame/RenderImage.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sph::render::frame {

ImageError compareImages(const RenderImage& image, const RenderImage& reference) {
  if (image.width != reference.width || image.height != reference.height) {
    throw std::invalid_argument("compareImages: images of different sizes");
  }
  if (!image.hasNormals() || !reference.hasNormals()) {
    throw std::invalid_argument(
        "compareImages: an image without normals (render it with ImageContents::ColourAndNormals)");
  }
  ImageError e;
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  double squared = 0;
  for (std::size_t k = 0; k < 3 * pixels; ++k) {
    const double d = static_cast<double>(image.rgb[k]) - reference.rgb[k];
    squared += d * d;
  }
  const double mse = squared / (3.0 * pixels);
  e.psnr = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
  std::size_t holes = 0, both = 0;
  double angles = 0;
  for (std::size_t p = 0; p < pixels; ++p) {
    if (!reference.covered[p]) continue;
    ++e.referenceCovered;
    if (!image.covered[p]) {
      ++holes;
      continue;
    }
    double dot = 0;
    for (int k = 0; k < 3; ++k)
      dot += static_cast<double>(image.normal[3 * p + k]) * reference.normal[3 * p + k];
    angles += std::acos(std::clamp(dot, -1.0, 1.0));
    ++both;
  }
  e.holeFraction = e.referenceCovered ? static_cast<double>(holes) / e.referenceCovered : 0.0;
  e.normalErrorDegrees = both ? angles / both * 180.0 / 3.14159265358979323846 : 0.0;
  return e;
}

ThinCoverage thinCoverage(const RenderImage& image, const RenderImage& reference,
                          const RenderImage& everyParticle) {
  if (!image.hasNormals() || !reference.hasNormals() || !everyParticle.hasNormals() ||
      image.covered.size() != reference.covered.size() ||
      everyParticle.covered.size() != reference.covered.size()) {
    throw std::invalid_argument("thinCoverage: images of one size with their coverage");
  }
  ThinCoverage t;
  std::size_t drawn = 0;
  for (std::size_t i = 0; i < reference.covered.size(); ++i) {
    if (!everyParticle.covered[i] || reference.covered[i]) continue;
    ++t.pixels;
    drawn += image.covered[i] ? 1 : 0;
  }
  t.fraction = t.pixels ? static_cast<double>(drawn) / t.pixels : 0.0;
  return t;
}

}  // namespace sph::render::frame
