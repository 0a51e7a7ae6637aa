#include "io/exports/MeshFiles.h"

#include <cerrno>
#include <charconv>
#include <cstring>

#include "sim/InputError.h"

namespace sph::io::exports {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the PLY writer copies floats and ints as they are in memory");

// Buffered writes that check once at the end.
class Writer {
 public:
  Writer(std::FILE* out, const std::string& what) : out_(out), what_(what) {
    buffer_.reserve(kSize);
  }
  void bytes(const void* data, std::size_t n) {
    const char* p = static_cast<const char*>(data);
    buffer_.insert(buffer_.end(), p, p + n);
    if (buffer_.size() >= kSize) flush();
  }
  void text(const std::string& s) { bytes(s.data(), s.size()); }
  void number(float v) {
    char digits[32];
    const auto r = std::to_chars(digits, digits + sizeof digits, v);
    bytes(digits, static_cast<std::size_t>(r.ptr - digits));
  }
  void number(std::uint64_t v) {
    char digits[24];
    const auto r = std::to_chars(digits, digits + sizeof digits, v);
    bytes(digits, static_cast<std::size_t>(r.ptr - digits));
  }
  void character(char c) { buffer_.push_back(c); }
  void flush() {
    if (!buffer_.empty() && std::fwrite(buffer_.data(), 1, buffer_.size(), out_) != buffer_.size())
      throw InputError(what_ + ": cannot write the mesh (" + std::strerror(errno) + ")");
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kSize = 1 << 20;
  std::FILE* out_;
  std::string what_;
  std::vector<char> buffer_;
};

std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

}  // namespace

void writeMeshPly(std::FILE* out, const MeshView& m, const std::string& what) {
  Writer w(out, what);
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  for (const std::string& c : m.comments) header += "comment " + oneLine(c) + "\n";
  header += "element vertex " + std::to_string(m.vertices) +
            "\nproperty float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "element face " +
            std::to_string(m.triangleCount) +
            "\nproperty list uchar int vertex_indices\nend_header\n";
  w.text(header);
  for (std::size_t v = 0; v < m.vertices; ++v) {
    w.bytes(m.positions + 3 * v, 3 * sizeof(float));
    w.bytes(m.normals + 3 * v, 3 * sizeof(float));
  }
  for (std::size_t t = 0; t < m.triangleCount; ++t) {
    const unsigned char three = 3;
    std::int32_t index[3];
    for (int k = 0; k < 3; ++k) index[k] = static_cast<std::int32_t>(m.triangles[3 * t + k]);
    w.bytes(&three, 1);
    w.bytes(index, sizeof index);
  }
  w.flush();
}

void writeMeshObj(std::FILE* out, const MeshView& m, const std::string& what) {
  Writer w(out, what);
  for (const std::string& c : m.comments) w.text("# " + oneLine(c) + "\n");
  for (const char* kind : {"v ", "vn "}) {
    const float* data = kind[1] == ' ' ? m.positions : m.normals;
    for (std::size_t v = 0; v < m.vertices; ++v) {
      w.text(kind);
      for (int k = 0; k < 3; ++k) {
        if (k) w.character(' ');
        w.number(data[3 * v + k]);
      }
      w.character('\n');
    }
  }
  for (std::size_t t = 0; t < m.triangleCount; ++t) {
    w.character('f');
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t index = std::uint64_t{m.triangles[3 * t + k]} + 1;
      w.character(' ');
      w.number(index);
      w.text("//");
      w.number(index);
    }
    w.character('\n');
  }
  w.flush();
}

}  // namespace sph::io::exports
