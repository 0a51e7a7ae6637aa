#include "render/frame/Srgb8Table.h"

#include <cmath>

namespace sph::render::frame {
namespace {

// The linear value whose encoding is e (the inverse of toSrgb, Lighting.h), in double.
double fromSrgb(double e) {
  return e <= 12.92 * 0.0031308 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

}  // namespace

Srgb8Table::Srgb8Table() {
  threshold_[0] = 0.0f;
  // Code k begins where 255 toSrgb(c) reaches k - 1/2.
  for (int k = 1; k < 256; ++k)
    threshold_[static_cast<std::size_t>(k)] = static_cast<float>(fromSrgb((k - 0.5) / 255.0));
  int k = 0;
  for (int bin = 0; bin <= kBins; ++bin) {
    const float c = static_cast<float>(bin) / kBins;
    while (k < 255 && c >= threshold_[static_cast<std::size_t>(k) + 1]) ++k;
    start_[static_cast<std::size_t>(bin)] = static_cast<std::uint8_t>(k);
  }
}

const Srgb8Table& srgb8Table() {
  static const Srgb8Table table;
  return table;
}

}  // namespace sph::render::frame
