// PNG files of 8-bit RGB images (libpng). Written to a temporary name and renamed, so a PNG that
// exists is complete.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace sph::io {

// Writes width x height RGB pixels (row 0 at the top). Throws InputError naming the path if the
// file cannot be written.
void writePng(const std::string& path, int width, int height, const std::uint8_t* rgb);

// Reads an 8-bit RGB or RGBA PNG into RGB. Throws InputError naming the path.
std::vector<std::uint8_t> readPng(const std::string& path, int& width, int& height);

}  // namespace sph::io
