#include "io/exports/Png.h"
#include "sim/InputError.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "io/UserFiles.h"

namespace sph::io::exports {

std::string framePngName(const std::string& stem, std::size_t frame) {
  char digits[24];
  std::snprintf(digits, sizeof digits, "_%05zu.png", frame);
  return stem + digits;
}

namespace {

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};
using File = std::unique_ptr<FILE, FileCloser>;

// libpng's errors and warnings, kept for the one line the program prints instead of printing
// them itself (its default handlers write to standard error: a second line on a full disk).
struct PngMessages {
  char error[160] = "";
  int errnoAtError = 0;
};

void onPngError(png_structp png, png_const_charp message) {
  auto* m = static_cast<PngMessages*>(png_get_error_ptr(png));
  m->errnoAtError = errno;
  std::snprintf(m->error, sizeof m->error, "%s", message);
  png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

}  // namespace

void writePng(const std::string& path, int width, int height, const std::uint8_t* rgb) {
  // Frames are redrawn over older frames, but never over a device node, FIFO or socket.
  const std::string kind = nonRegularKind(path);
  if (!kind.empty()) {
    throw InputError(path + ": is " + kind +
                     ", not a regular file; refusing to replace it with an image");
  }
  AtomicOutput file(path);
  PngMessages messages;
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, &messages, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw InputError(path + ": cannot write the image (libpng could not start)");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    const std::string cause = messages.errnoAtError != 0
                                  ? std::string(": ") + std::strerror(messages.errnoAtError)
                                  : std::string();
    throw InputError(path + ": cannot write the image (libpng: " + messages.error + cause + ")");
  }
  png_init_io(png, file.file());
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int row = 0; row < height; ++row) {
    png_write_row(png, const_cast<png_bytep>(rgb + static_cast<std::size_t>(row) * width * 3));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  file.commit();  // renames the temporary over `path` (a PNG that exists is complete)
}

std::vector<std::uint8_t> readPng(const std::string& path, int& width, int& height) {
  File file(std::fopen(path.c_str(), "rb"));
  if (!file) throw InputError(path + ": cannot open the image (" + std::strerror(errno) + ")");
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw InputError(path + ": cannot read the image (libpng could not start)");
  }
  std::vector<std::uint8_t> rgb;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw InputError(path + ": not a readable PNG file");
  }
  png_init_io(png, file.get());
  png_read_info(png, info);
  width = static_cast<int>(png_get_image_width(png, info));
  height = static_cast<int>(png_get_image_height(png, info));
  png_set_strip_16(png);
  png_set_strip_alpha(png);
  png_set_palette_to_rgb(png);
  png_set_gray_to_rgb(png);
  png_read_update_info(png, info);
  rgb.resize(static_cast<std::size_t>(width) * height * 3);
  for (int row = 0; row < height; ++row)
    png_read_row(png, rgb.data() + static_cast<std::size_t>(row) * width * 3, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return rgb;
}

}  // namespace sph::io::exports
