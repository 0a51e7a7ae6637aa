#include "render/splat/RenderImage.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sph::render::splat {

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

}  // namespace sph::render::splat
