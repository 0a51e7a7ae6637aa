#include "io/cache/XdmfWriter.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "io/UserFiles.h"
#include "sim/InputError.h"

namespace sph::io::cache {
namespace {

using cache::Field;

std::string exact(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

void writeAll(int fd, const std::string& text, long long offset, const std::string& path) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n =
        pwrite(fd, text.data() + done, text.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw InputError(path + ": cannot write the XDMF sidecar (" + std::strerror(errno) + ")");
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

std::string XdmfWriter::sidecarPath(const std::string& cachePath) {
  const std::size_t slash = cachePath.find_last_of('/');
  const std::size_t dot = cachePath.find_last_of('.');
  const bool hasExtension =
      dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  return siblingPath(hasExtension ? cachePath.substr(0, dot) : cachePath, "", ".xdmf");
}

XdmfWriter::XdmfWriter(std::string xdmfPath, std::string cacheFileName,
                       const cache::FieldSet& fields, bool doublePositions,
                       std::size_t boundaryParticles, const std::vector<CacheFrame>& frames)
    : path_(std::move(xdmfPath)),
      cacheFile_(std::move(cacheFileName)),
      fields_(fields),
      doublePositions_(doublePositions),
      boundaryParticles_(boundaryParticles),
      frames_(frames) {
  rewrite();
}

void XdmfWriter::append(const CacheFrame& frame) {
  frames_.push_back(frame);
  ++pending_;
  constexpr std::size_t kBytesPerRewrite = 256 * 1024;
  if (pending_ * kBytesPerRewrite >= documentBytes_) rewrite();
}

void XdmfWriter::flush() {
  if (pending_ > 0) rewrite();
}

void XdmfWriter::rewrite() {
  const std::string text = document(frames_);
  const std::string temporary = siblingPath(path_, "", ".tmp");
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw InputError(temporary + ": cannot create the XDMF sidecar (" + std::strerror(errno) + ")");
  // A sidecar that cannot be written whole (a full disk) leaves the last whole one in place and
  // no half-written temporary behind.
  try {
    writeAll(fd, text, 0, temporary);
  } catch (...) {
    ::close(fd);
    ::unlink(temporary.c_str());
    throw;
  }
  ::close(fd);
  if (std::rename(temporary.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    throw InputError(path_ + ": cannot move the XDMF sidecar into place (" + std::strerror(error) +
                     ")");
  }
  documentBytes_ = text.size();
  pending_ = 0;
}

std::string XdmfWriter::document(const std::vector<CacheFrame>& frames) const {
  std::string text = head();
  for (const CacheFrame& f : frames) text += frameGrid(f);
  return text + tail();
}

std::string XdmfWriter::head() const {
  return "<?xml version=\"1.0\" ?>\n"
         "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
         "<!-- sphsplat cache " +
         cacheFile_ +
         ": per frame, the fluid particles and the boundary particles.\n"
         "     Written by sphsplat frame by frame; see docs/cache-format.md. -->\n"
         "<Xdmf Version=\"2.0\">\n"
         "  <Domain>\n"
         "    <Grid Name=\"sphsplat\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
}

std::string XdmfWriter::tail() const {
  return "    </Grid>\n"
         "  </Domain>\n"
         "</Xdmf>\n";
}

std::string XdmfWriter::dataItem(const std::string& dataset, const std::string& dimensions,
                                 bool isId, bool isPosition, const std::string& indent) const {
  const char* type = isId ? "UInt" : "Float";
  const char* precision = isId ? "4" : (isPosition && doublePositions_ ? "8" : "4");
  return indent + "<DataItem Dimensions=\"" + dimensions + "\" NumberType=\"" + type +
         "\" Precision=\"" + precision + "\" Format=\"HDF\">" + cacheFile_ + ":" + dataset +
         "</DataItem>\n";
}

// One point set: a vertex cell per point and XYZ geometry read from an [n][3] dataset (ParaView's
// Xdmf3 readers accept no other way for points given as separate x, y, z). The cells' connectivity
// is spelled out, the first n numbers of a point index (cache::pointIndexName): without it the
// Xdmf3 readers make no cells, and ParaView draws nothing. The hyperslab's source is the whole
// index, as stored: the older XDMF reader crashes on a dataset shorter than the file's.
std::string XdmfWriter::pointGrid(const std::string& name, std::size_t count,
                                  const std::string& positions, bool isFluid) const {
  const std::string n = std::to_string(count);
  return "        <Grid Name=\"" + name +
         "\" GridType=\"Uniform\">\n"
         "          <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" +
         n +
         "\" NodesPerElement=\"1\">\n"
         "            <DataItem ItemType=\"HyperSlab\" Dimensions=\"" +
         n +
         "\">\n"
         "              <DataItem Dimensions=\"3 1\" Format=\"XML\">0 1 " +
         n + "</DataItem>\n" +
         dataItem("/" + cache::pointIndexName(count),
                  std::to_string(cache::pointIndexLength(count)), true, false, "              ") +
         "            </DataItem>\n"
         "          </Topology>\n"
         "          <Geometry GeometryType=\"XYZ\">\n" +
         dataItem(positions, n + " 3", false, isFluid, "            ") + "          </Geometry>\n";
}

std::string XdmfWriter::frameGrid(const CacheFrame& frame) const {
  // Each time step is a spatial collection of the fluid and the boundary: every reader then shows
  // both at every time (the Xdmf3 readers take only one grid at the top level, the time series).
  std::string text = "      <Grid Name=\"" + cache::stepName(frame.index) +
                     "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
                     "        <Time Value=\"" +
                     exact(frame.time) + "\"/>\n";
  const std::size_t n = frame.particles;
  // A frame with no particle (a pour's first) has no fluid grid: XDMF readers fail on
  // zero-length arrays (ParaView 5.11: "Error in Update() of Geometry").
  if (n > 0) {
    const std::string step = "/" + cache::stepName(frame.index) + "/";
    const std::string vectors = "/" + cache::vectorsName(frame.index) + "/";
    text += pointGrid("fluid", n, vectors + cache::kVectorViews[0].name, true);
    const std::string count = std::to_string(n);
    cache::FieldSet described;
    for (const cache::VectorView& view : cache::kVectorViews) {
      if (!cache::hasAll(fields_, view)) continue;
      for (cache::Field c : view.components) described.set(static_cast<std::size_t>(c));
      if (view.components[0] == Field::X) continue;  // the geometry
      text += std::string("          <Attribute Name=\"") + view.name +
              "\" AttributeType=\"Vector\" Center=\"Node\">\n" +
              dataItem(vectors + view.name, count + " 3", false, false, "            ") +
              "          </Attribute>\n";
    }
    for (std::size_t f = 0; f < cache::kFieldCount; ++f) {
      if (!fields_[f] || described[f]) continue;
      const auto field = static_cast<Field>(f);
      text += std::string("          <Attribute Name=\"") + cache::fieldName(field) +
              "\" AttributeType=\"Scalar\" Center=\"Node\">\n" +
              dataItem(step + cache::fieldName(field), count, field == Field::Id, false,
                       "            ") +
              "          </Attribute>\n";
    }
    text += "        </Grid>\n";
  }
  if (boundaryParticles_ > 0) {
    text += pointGrid("boundary", boundaryParticles_,
                      std::string("/") + cache::kBoundaryGroup + "/" + cache::kVectorViews[0].name,
                      false) +
            "        </Grid>\n";
  }
  // The rain's drops (scenes with a rain section, io/cache/RainCache.h): a third point set.
  if (frame.rainDrops > 0) {
    text += pointGrid("rain", frame.rainDrops, "/" + cache::rainName(frame.index) + "/position",
                      false) +
            "        </Grid>\n";
  }
  return text + "      </Grid>\n";
}

}  // namespace sph::io::cache
