#include "io/XdmfWriter.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "sim/InputError.h"

namespace sph::io {
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
  return (hasExtension ? cachePath.substr(0, dot) : cachePath) + ".xdmf";
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
  const std::string temporary = path_ + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw InputError(temporary + ": cannot create the XDMF sidecar (" + std::strerror(errno) + ")");
  try {
    writeAll(fd, text, 0, temporary);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  if (std::rename(temporary.c_str(), path_.c_str()) != 0) {
    throw InputError(path_ + ": cannot move the XDMF sidecar into place (" + std::strerror(errno) +
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
         ": fluid particles per frame, boundary particles once.\n"
         "     Written by sphsplat frame by frame; see docs/cache-format.md. -->\n"
         "<Xdmf Version=\"2.0\">\n"
         "  <Domain>\n"
         "    <Grid Name=\"fluid\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
}

std::string XdmfWriter::tail() const {
  std::string text = "    </Grid>\n";
  if (boundaryParticles_ > 0) {
    const std::string n = std::to_string(boundaryParticles_);
    text +=
        "    <Grid Name=\"boundary\" GridType=\"Uniform\">\n"
        "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" +
        n +
        "\" NodesPerElement=\"1\"/>\n"
        "      <Geometry GeometryType=\"X_Y_Z\">\n";
    for (const char* axis : {"x", "y", "z"}) {
      text += "        <DataItem Dimensions=\"" + n +
              "\" NumberType=\"Float\" Precision=\"4\" Format=\"HDF\">" + cacheFile_ + ":/" +
              cache::kBoundaryGroup + "/" + axis + "</DataItem>\n";
    }
    text +=
        "      </Geometry>\n"
        "    </Grid>\n";
  }
  return text + "  </Domain>\n</Xdmf>\n";
}

std::string XdmfWriter::dataItem(const std::string& dataset, std::size_t count, bool isId,
                                 bool isPosition, const std::string& indent) const {
  const char* type = isId ? "UInt" : "Float";
  const char* precision = isId ? "4" : (isPosition && doublePositions_ ? "8" : "4");
  return indent + "<DataItem Dimensions=\"" + std::to_string(count) + "\" NumberType=\"" + type +
         "\" Precision=\"" + precision + "\" Format=\"HDF\">" + cacheFile_ + ":" + dataset +
         "</DataItem>\n";
}

std::string XdmfWriter::frameGrid(const CacheFrame& frame) const {
  const std::string group = "/" + cache::stepName(frame.index) + "/";
  const std::size_t n = frame.particles;
  const std::string count = std::to_string(n);
  if (n == 0) {
    // XDMF 2 readers fail on zero-length arrays (ParaView 5.11 reports "Error in Update() of
    // Geometry"); an empty spatial collection keeps the frame's time without any.
    return "      <Grid Name=\"" + cache::stepName(frame.index) +
           "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
           "        <Time Value=\"" +
           exact(frame.time) +
           "\"/>\n"
           "      </Grid>\n";
  }
  std::string text = "      <Grid Name=\"" + cache::stepName(frame.index) +
                     "\" GridType=\"Uniform\">\n"
                     "        <Time Value=\"" +
                     exact(frame.time) +
                     "\"/>\n"
                     "        <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" +
                     count +
                     "\" NodesPerElement=\"1\"/>\n"
                     "        <Geometry GeometryType=\"X_Y_Z\">\n";
  for (const char* axis : {"x", "y", "z"})
    text += dataItem(group + axis, n, false, true, "          ");
  text += "        </Geometry>\n";
  auto has = [&](Field f) { return fields_[static_cast<std::size_t>(f)]; };
  // Vectors whose three components are all written become one vector attribute (JOIN).
  const struct {
    const char* name;
    Field c[3];
  } vectors[] = {{"velocity", {Field::VX, Field::VY, Field::VZ}},
                 {"acceleration", {Field::AX, Field::AY, Field::AZ}}};
  cache::FieldSet joined;
  for (const auto& v : vectors) {
    if (!(has(v.c[0]) && has(v.c[1]) && has(v.c[2]))) continue;
    text +=
        std::string("        <Attribute Name=\"") + v.name +
        "\" AttributeType=\"Vector\" Center=\"Node\">\n"
        "          <DataItem ItemType=\"Function\" Function=\"JOIN($0, $1, $2)\" Dimensions=\"" +
        count + " 3\">\n";
    for (Field c : v.c) {
      text += dataItem(group + cache::fieldName(c), n, false, false, "            ");
      joined.set(static_cast<std::size_t>(c));
    }
    text +=
        "          </DataItem>\n"
        "        </Attribute>\n";
  }
  for (std::size_t f = static_cast<std::size_t>(Field::VX); f < cache::kFieldCount; ++f) {
    if (!fields_[f] || joined[f]) continue;
    const auto field = static_cast<Field>(f);
    text += std::string("        <Attribute Name=\"") + cache::fieldName(field) +
            "\" AttributeType=\"Scalar\" Center=\"Node\">\n" +
            dataItem(group + cache::fieldName(field), n, field == Field::Id, false, "          ") +
            "        </Attribute>\n";
  }
  return text + "      </Grid>\n";
}

}  // namespace sph::io
