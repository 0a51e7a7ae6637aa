// One frame of particles (or the boundary) as a file other tools read: CSV (spreadsheets,
// pandas), PLY (point-cloud tools: CloudCompare, MeshLab, Open3D) and VTK XML unstructured grids
// (.vtu, ParaView and meshio) with a .pvd collection giving a sequence its times. ParaView draws
// the .vtu files: one vertex cell per particle and every field as a point-data array (velocity as
// a 3-component vector). Its PLY reader shows points only with faces, so PLY is for the other
// tools (docs/cache-format.md, "Export").
//
// Values round-trip exactly: CSV and PLY print floats with 9 significant digits (enough for
// float32, IEEE 754-2008 section 5.12.2), .vtu stores the float32 bits as raw appended binary.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "io/cache/CacheFormat.h"
#include "sim/Particles.h"

namespace sph::io::exports {

struct ExportFrame {
  const Particles* particles = nullptr;
  cache::FieldSet fields;  // which arrays of `particles` to write; x y z are always written
  std::string source;      // "cache run.h5, frame 7 (t = 0.07 s)", for comments
  double time = 0;         // s, the frame's time (TimeValue)
  bool hasTime = false;    // false for the boundary
};

// SI unit of a field for headers ("m/s"); "" for id.
const char* fieldUnit(cache::Field f);

// A header row "x [m],y [m],z [m],vx [m/s],...,id" and a row per particle.
void writeCsv(std::FILE* out, const ExportFrame& frame);
// ASCII PLY: one `vertex` element with a property per field, units in a comment.
void writePly(std::FILE* out, const ExportFrame& frame);
// VTK XML UnstructuredGrid (version 1.0, raw appended data, UInt64 headers, the machine's byte
// order): Points, one VTK_VERTEX cell per point, the fields as PointData, TimeValue as FieldData.
void writeVtu(std::FILE* out, const ExportFrame& frame);

// A ParaView collection (.pvd) of files with their times; `file` relative to the .pvd.
struct PvdEntry {
  double time = 0;
  std::string file;
};
void writePvd(std::FILE* out, const std::vector<PvdEntry>& entries);

}  // namespace sph::io::exports
