#include "io/cache/RainCache.h"

#include "io/cache/CacheFormat.h"
#include "io/cache/Hdf5.h"
#include "sim/InputError.h"

namespace sph::io::cache {

using h5::check;
using h5::checked;

void writeRainFrame(CacheWriter& writer, std::size_t frame, double time,
                    const rain::RainSystem& rain) {
  const std::vector<Vec3>& p = rain.positions();
  const std::size_t n = p.size();
  writer.writeFrameGroup(cache::rainName(frame), frame, [&](hid_t group, const h5::Storage& s) {
    h5::writeAttribute(group, cache::kTimeAttr, time);
    h5::writeAttribute(group, cache::kRainDropsAttr, static_cast<std::uint64_t>(n));
    // [n][3] stored as such (not a view of x y z): a view's mapping would go to the global heap
    // block the frame's own views use (CacheWriter::reopen).
    std::vector<float> xyz(3 * n);
    for (std::size_t i = 0; i < n; ++i)
      xyz[3 * i] = p[i].x(), xyz[3 * i + 1] = p[i].y(), xyz[3 * i + 2] = p[i].z();
    h5::Handle position =
        h5::createDataset(group, "position", H5T_IEEE_F32LE, {static_cast<hsize_t>(n), 3}, s);
    if (n > 0) {
      check(H5Dwrite(position.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, xyz.data()),
            "write position");
    }
    check(H5Dflush(position.get()), "write position");
    position.reset();
    h5::writeDataset(group, "generation", H5T_NATIVE_UINT32, H5T_STD_U32LE,
                     rain.generations().data(), n, s);
    h5::writeDataset(group, "layer", H5T_NATIVE_UINT8, H5T_STD_U8LE, rain.layers().data(), n, s);
  });
  writer.writePointIndex(n);  // the sidecar's cells of the drops
}

RainFrame readRainFrame(const CacheReader& reader, std::size_t frame) {
  const std::string name = cache::rainName(frame);
  const std::string where = reader.summary().path + ": /" + name;
  if (frame >= reader.frameCount() || reader.summary().frames[frame].rainDrops == 0 ||
      !h5::hasLink(reader.file(), name))
    throw InputError(where + ": the cache holds no rain drops for frame " + std::to_string(frame));
  RainFrame r;
  try {
    h5::Handle g = h5::openCheckedGroup(reader.file(), name);
    r.time = h5::readDoubleAttribute(g.get(), cache::kTimeAttr);
    const std::size_t n = h5::readUintAttribute(g.get(), cache::kRainDropsAttr);
    r.generations = h5::readDataset<std::uint32_t>(g.get(), "generation");
    r.layers = h5::readDataset<std::uint8_t>(g.get(), "layer");
    if (r.generations.size() != n || r.layers.size() != n)
      throw h5::Error("read the drops", "generation or layer is not of the drops' length");
    h5::Handle position = h5::openCheckedDataset(g.get(), "position");
    h5::Handle space = checked(H5Dget_space(position.get()), "read position's shape");
    hsize_t dims[2] = {0, 0};
    if (H5Sget_simple_extent_ndims(space.get()) != 2 ||
        H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 2 || dims[0] != n || dims[1] != 3)
      throw h5::Error("read the drops", "position is not [drops][3]");
    std::vector<float> xyz(3 * n);
    if (n > 0) {
      check(H5Dread(position.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, xyz.data()),
            "read position");
    }
    r.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      r.positions[i] = Vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  } catch (const h5::Error& e) {
    throw InputError(where + ": " + e.what());
  }
  return r;
}

}  // namespace sph::io::cache
