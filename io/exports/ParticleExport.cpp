#include "io/exports/ParticleExport.h"

#include <cstdint>
#include <cstring>

#include "io/MessageText.h"

namespace sph::io::exports {
namespace {

using cache::Field;

bool has(const ExportFrame& f, Field field) {
  return field == Field::X || field == Field::Y || field == Field::Z ||
         f.fields[static_cast<std::size_t>(field)];
}

// The fields written, in the cache's canonical order, x y z first.
std::vector<Field> columns(const ExportFrame& f) {
  std::vector<Field> out;
  for (std::size_t k = 0; k < cache::kFieldCount; ++k) {
    if (has(f, static_cast<Field>(k))) out.push_back(static_cast<Field>(k));
  }
  return out;
}

void writeRows(std::FILE* out, const ExportFrame& f, char separator) {
  const Particles& p = *f.particles;
  const std::vector<Field> cols = columns(f);
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t c = 0; c < cols.size(); ++c) {
      if (c) std::fputc(separator, out);
      if (cols[c] == Field::Id)
        std::fprintf(out, "%u", p.id[i]);
      else
        std::fprintf(out, "%.9g", static_cast<double>((p.*cache::floatMember(cols[c]))[i]));
    }
    std::fputc('\n', out);
  }
}

bool littleEndian() {
  const std::uint16_t one = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// Escapes text for an XML attribute value.
std::string xmlAttribute(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// The bytes as base64 (RFC 4648, padded).
std::string base64(const std::vector<char>& bytes) {
  static const char* const digits =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t left = bytes.size() - i;
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (left > 1) v |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (left > 2) v |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += digits[(v >> 18) & 63];
    out += digits[(v >> 12) & 63];
    out += left > 1 ? digits[(v >> 6) & 63] : '=';
    out += left > 2 ? digits[v & 63] : '=';
  }
  return out;
}

// One DataArray: its element, and the bytes it holds.
struct Block {
  std::string header;  // the <DataArray ...>{DATA}</DataArray> element
  std::vector<char> bytes;
};

template <class T>
Block block(const std::string& element, const std::vector<T>& values) {
  Block b{element, std::vector<char>(values.size() * sizeof(T))};
  if (!values.empty()) std::memcpy(b.bytes.data(), values.data(), b.bytes.size());
  return b;
}

std::vector<float> interleave(const std::vector<float>& a, const std::vector<float>& b,
                              const std::vector<float>& c) {
  std::vector<float> out(3 * a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    out[3 * i] = a[i], out[3 * i + 1] = b[i], out[3 * i + 2] = c[i];
  return out;
}

}  // namespace

const char* fieldUnit(Field f) {
  switch (f) {
    case Field::X:
    case Field::Y:
    case Field::Z:
      return "m";
    case Field::VX:
    case Field::VY:
    case Field::VZ:
      return "m/s";
    case Field::AX:
    case Field::AY:
    case Field::AZ:
      return "m/s^2";
    case Field::Rho:
      return "kg/m^3";
    case Field::P:
      return "Pa";
    case Field::CollideTime:
      return "s";
    default:
      return "";
  }
}

void writeCsv(std::FILE* out, const ExportFrame& f) {
  const std::vector<Field> cols = columns(f);
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const std::string unit = fieldUnit(cols[c]);
    std::fprintf(out, "%s%s%s", c ? "," : "", cache::fieldName(cols[c]),
                 unit.empty() ? "" : (" [" + unit + "]").c_str());
  }
  std::fputc('\n', out);
  writeRows(out, f, ',');
}

void writePly(std::FILE* out, const ExportFrame& f) {
  const std::vector<Field> cols = columns(f);
  std::fprintf(out, "ply\nformat ascii 1.0\ncomment sphsplat %s\n",
               printable(f.source, 300).c_str());
  std::string units;
  for (Field c : cols) {
    if (*fieldUnit(c)) units += std::string(" ") + cache::fieldName(c) + " [" + fieldUnit(c) + "]";
  }
  std::fprintf(out, "comment units:%s\n", units.c_str());
  if (f.hasTime) std::fprintf(out, "comment time %.17g s\n", f.time);
  std::fprintf(out, "element vertex %zu\n", f.particles->size());
  for (Field c : cols)
    std::fprintf(out, "property %s %s\n", c == Field::Id ? "uint" : "float", cache::fieldName(c));
  std::fprintf(out, "end_header\n");
  writeRows(out, f, ' ');
}

void writeVtu(std::FILE* out, const ExportFrame& f) {
  const Particles& p = *f.particles;
  const std::size_t n = p.size();
  std::vector<Block> point;  // PointData arrays
  auto vector = [&](Field a, Field b, Field c, const char* name) {
    if (!has(f, a) || !has(f, b) || !has(f, c)) return false;
    point.push_back(block(
        std::string("<DataArray type=\"Float32\" Name=\"") + name +
            "\" NumberOfComponents=\"3\" format=\"binary\">{DATA}</DataArray>",
        interleave(p.*cache::floatMember(a), p.*cache::floatMember(b), p.*cache::floatMember(c))));
    return true;
  };
  const bool velocity = vector(Field::VX, Field::VY, Field::VZ, "velocity");
  const bool acceleration = vector(Field::AX, Field::AY, Field::AZ, "acceleration");
  for (Field c : columns(f)) {
    const bool inVector = (velocity && (c == Field::VX || c == Field::VY || c == Field::VZ)) ||
                          (acceleration && (c == Field::AX || c == Field::AY || c == Field::AZ));
    if (c == Field::X || c == Field::Y || c == Field::Z || inVector) continue;
    const std::string head = std::string("<DataArray type=\"") +
                             (c == Field::Id ? "UInt32" : "Float32") + "\" Name=\"" +
                             cache::fieldName(c) + "\" format=\"binary\">{DATA}</DataArray>";
    point.push_back(c == Field::Id ? block(head, p.id) : block(head, p.*cache::floatMember(c)));
  }
  std::vector<std::int64_t> connectivity(n), offsets(n);
  for (std::size_t i = 0; i < n; ++i)
    connectivity[i] = static_cast<std::int64_t>(i), offsets[i] = static_cast<std::int64_t>(i + 1);
  const std::vector<std::uint8_t> types(n, 1);  // VTK_VERTEX
  const Block points = block(
      "<DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" format=\"binary\">"
      "{DATA}</DataArray>",
      interleave(p.x, p.y, p.z));
  const Block cells[3] = {
      block("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"binary\">"
            "{DATA}</DataArray>",
            connectivity),
      block("<DataArray type=\"Int64\" Name=\"offsets\" format=\"binary\">{DATA}</DataArray>",
            offsets),
      block("<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">{DATA}</DataArray>",
            types)};

  // Each array inline as base64 ("binary"): its UInt64 size and its bytes, encoded as one
  // stream, as VTK writes it. Not appended raw data: the expat of an up-to-date Debian 12
  // (2.5.0-1+deb12u5, with its reparse deferral) stops ParaView 5.11's XML reader at the appended
  // section, raw or base64 ("not well-formed (invalid token)"), and the file reads as empty.
  auto element = [&](const Block& b) {
    const std::uint64_t size = b.bytes.size();
    std::vector<char> sized(sizeof size + b.bytes.size());
    std::memcpy(sized.data(), &size, sizeof size);
    if (size) std::memcpy(sized.data() + sizeof size, b.bytes.data(), b.bytes.size());
    std::string e = b.header;
    e.replace(e.find("{DATA}"), 6, base64(sized));
    return e;
  };
  std::fprintf(out,
               "<?xml version=\"1.0\"?>\n"
               "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" "
               "header_type=\"UInt64\">\n  <UnstructuredGrid>\n",
               littleEndian() ? "LittleEndian" : "BigEndian");
  if (f.hasTime) {
    // ParaView takes a FieldData array named TimeValue as the file's time.
    std::fprintf(out,
                 "    <FieldData>\n      <DataArray type=\"Float64\" Name=\"TimeValue\" "
                 "NumberOfTuples=\"1\" format=\"ascii\">%.17g</DataArray>\n    </FieldData>\n",
                 f.time);
  }
  std::fprintf(out, "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n", n, n);
  std::fprintf(out, "      <PointData%s%s>\n", velocity ? " Vectors=\"velocity\"" : "",
               has(f, Field::Rho) ? " Scalars=\"rho\"" : "");
  for (const Block& b : point) std::fprintf(out, "        %s\n", element(b).c_str());
  std::fprintf(out, "      </PointData>\n      <Points>\n        %s\n      </Points>\n",
               element(points).c_str());
  std::fprintf(out, "      <Cells>\n");
  for (const Block& b : cells) std::fprintf(out, "        %s\n", element(b).c_str());
  std::fprintf(out, "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
  std::fprintf(out, "</VTKFile>\n");
}

void writePvd(std::FILE* out, const std::vector<PvdEntry>& entries) {
  std::fprintf(out,
               "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
               "byte_order=\"%s\">\n  <Collection>\n",
               littleEndian() ? "LittleEndian" : "BigEndian");
  for (const PvdEntry& e : entries) {
    std::fprintf(out, "    <DataSet timestep=\"%.17g\" part=\"0\" file=\"%s\"/>\n", e.time,
                 xmlAttribute(e.file).c_str());
  }
  std::fprintf(out, "  </Collection>\n</VTKFile>\n");
}

}  // namespace sph::io::exports
