// Rendered images in the cache (`render --to-cache`, a run whose scene stores its pictures):
// one HDF5 Image per frame and renderer, committed like a frame (io/cache/CacheCommit.cpp).
#include <algorithm>
#include <chrono>

#include "io/cache/CacheWriter.h"
#include "sim/InputError.h"

namespace sph::io::cache {

using h5::check;
using h5::checked;

void CacheWriter::writeRenderedFrame(const std::string& renderer, std::size_t frame, int width,
                                     int height, const std::uint8_t* rgb) {
  const bool nameOk =
      !renderer.empty() && std::all_of(renderer.begin(), renderer.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               c == '_' || c == '-';
      });
  if (!nameOk)
    throw InputError(path_ + ": renderer name '" + renderer +
                     "': expected letters, digits, '_' or '-'");
  if (frame >= frames_) {
    throw InputError(path_ + ": cannot store a rendered frame " + std::to_string(frame) +
                     ": the cache has frames 0-" + std::to_string(frames_ - 1));
  }
  if (width <= 0 || height <= 0) throw InputError(path_ + ": rendered frame size must be positive");
  const auto start = std::chrono::steady_clock::now();
  const std::string name = cache::renderedFrameName(renderer, frame);
  try {
    const hid_t root = file_.get();
    const std::string legacy = std::string(cache::kLegacyRenderGroup) + "/" + renderer + "/" +
                               cache::legacyRenderedFrameName(frame);
    if (h5::hasLink(root, name) || h5::hasPath(root, legacy)) {
      throw InputError(path_ + ": rendered frame " + std::to_string(frame) + " of '" + renderer +
                       "' is already written");
    }
    // Same two-phase commit as a frame: the image is written, then linked into the root.
    const std::vector<hsize_t> dims = {static_cast<hsize_t>(height), static_cast<hsize_t>(width),
                                       3};
    h5::Handle image = h5::createDataset(root, "", H5T_STD_U8LE, dims, storage_);
    check(H5Dwrite(image.get(), H5T_NATIVE_UINT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, rgb),
          "write " + name);
    // Compress and place the chunks now: left to the commit's flush, their allocation would move
    // the end of the file after commitObjects() has grown it (point 4 there).
    check(H5Dflush(image.get()), "write " + name);
    // The HDF5 Image specification's attributes, so HDFView and h5py tools show it as a picture;
    // fixed-length strings, as that specification writes them (and none in the global heap).
    h5::writeFixedAttribute(image.get(), "CLASS", "IMAGE");
    h5::writeFixedAttribute(image.get(), "IMAGE_VERSION", "1.2");
    h5::writeFixedAttribute(image.get(), "IMAGE_SUBCLASS", "IMAGE_TRUECOLOR");
    h5::writeFixedAttribute(image.get(), "INTERLACE_MODE", "INTERLACE_PIXEL");
    h5::Handle step = checked(H5Gopen2(root, cache::stepName(frame).c_str(), H5P_DEFAULT),
                              "open the frame's step");
    h5::writeAttribute(image.get(), cache::kTimeAttr,
                       h5::readDoubleAttribute(step.get(), cache::kTimeAttr));
    h5::writeAttribute(image.get(), "frame", static_cast<std::uint64_t>(frame));
    h5::writeFixedAttribute(image.get(), "renderer", renderer);
    step.reset();
    commitObjects();
    check(H5Olink(image.get(), root, name.c_str(), H5P_DEFAULT, H5P_DEFAULT), "link /" + name);
    image.reset();
    commitObjects(root);
  } catch (const h5::Error& e) {
    throw InputError(path_ + ": cannot write rendered frame " + std::to_string(frame) + " of '" +
                     renderer + "' (" + e.what() + ")");
  }
  secondsWriting_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace sph::io::cache
