// PNG files of 8-bit RGB images (libpng). Written to a temporary name and renamed, so a PNG that
// exists is complete.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sph::io::exports {

// Writes width x height RGB pixels (row 0 at the top). Throws InputError naming the path if the
// file cannot be written.
void writePng(const std::string& path, int width, int height, const std::uint8_t* rgb);

// Reads an 8-bit RGB or RGBA PNG into RGB. Throws InputError naming the path.
std::vector<std::uint8_t> readPng(const std::string& path, int& width, int& height);

// The file name of one frame's picture, "<stem>_<frame, 5 digits>.png": "pour_quad_00012.png"
// for `run` and `render` (stem: scene_splat), "dam_break_compare_00030.png" for `compare`,
// "sphsplat_view_00007.png" for `view`. Frames past 99999 get more digits.
std::string framePngName(const std::string& stem, std::size_t frame);

}  // namespace sph::io::exports
