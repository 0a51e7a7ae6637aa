// `sphsplat export CACHE --frame N --format csv|ply`: one frame of a cache as a plain text file,
// for tools that read neither HDF5 nor XDMF. Floats are printed with 9 significant digits, which
// reads back to the same float32 bits.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/Commands.h"
#include "io/CacheReader.h"
#include "sim/InputError.h"

namespace sph::app {
namespace {

namespace cache = io::cache;

struct ExportOptions {
  std::string cache;
  std::string frame = "last";
  std::string format;
  std::string output;
  std::vector<std::string> fields;
  bool boundary = false;
};

// One named column of floats or ids.
struct Column {
  std::string name;
  const std::vector<float>* values = nullptr;
  const std::vector<std::uint32_t>* ids = nullptr;
};

std::size_t parseFrame(const std::string& text, std::size_t frames, const std::string& cachePath) {
  if (text == "last") {
    if (frames == 0) throw InputError(cachePath + ": the cache has no complete frame to export");
    return frames - 1;
  }
  std::size_t used = 0;
  unsigned long long value = 0;
  try {
    value = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || text[0] == '-') {
    throw InputError("--frame: expected a frame index (0, 1, ...) or 'last', got '" + text + "'");
  }
  return static_cast<std::size_t>(value);
}

void writeRows(std::FILE* out, const std::vector<Column>& columns, std::size_t rows,
               char separator) {
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c) std::fputc(separator, out);
      if (columns[c].ids)
        std::fprintf(out, "%u", (*columns[c].ids)[i]);
      else
        std::fprintf(out, "%.9g", static_cast<double>((*columns[c].values)[i]));
    }
    std::fputc('\n', out);
  }
}

int exportFrame(const ExportOptions& o) {
  if (o.output == o.cache)
    throw InputError(o.output + ": refusing to write the export over the cache itself");
  const io::CacheReader reader(o.cache);
  const io::CacheSummary& s = reader.summary();

  Particles particles;
  std::vector<std::vector<float>> boundary;
  std::vector<Column> columns;
  std::size_t rows = 0;
  std::string what;
  if (o.boundary) {
    boundary = reader.readBoundary();
    for (int a = 0; a < 3; ++a)
      columns.push_back({std::string(1, "xyz"[a]), &boundary[a], nullptr});
    rows = boundary[0].size();
    what = "boundary particles";
  } else {
    const std::size_t frame = parseFrame(o.frame, reader.frameCount(), o.cache);
    cache::FieldSet fields = s.fields;
    if (!o.fields.empty()) {
      std::string error;
      std::vector<std::string> names = o.fields;
      names.insert(names.end(), {"x", "y", "z"});
      fields = cache::parseFields(names, error);
      if (!error.empty()) throw InputError("--fields: " + error);
    }
    particles = reader.readFrame(frame, fields);  // names the missing dataset if one is asked for
    for (std::size_t f = 0; f < cache::kFieldCount; ++f) {
      if (!fields[f]) continue;
      const auto field = static_cast<cache::Field>(f);
      if (field == cache::Field::Id)
        columns.push_back({"id", nullptr, &particles.id});
      else
        columns.push_back(
            {cache::fieldName(field), &(particles.*cache::floatMember(field)), nullptr});
    }
    rows = particles.x.size();
    what =
        "frame " + std::to_string(frame) + " (t = " + std::to_string(s.frames[frame].time) + " s)";
  }

  const bool toStdout = o.output == "-";
  const std::string path = toStdout ? "standard output" : o.output;
  std::FILE* out = toStdout ? stdout : std::fopen(o.output.c_str(), "w");
  if (!out) throw InputError(o.output + ": cannot create the export file");
  if (o.format == "csv") {
    for (std::size_t c = 0; c < columns.size(); ++c)
      std::fprintf(out, "%s%s", c ? "," : "", columns[c].name.c_str());
    std::fputc('\n', out);
    writeRows(out, columns, rows, ',');
  } else {
    std::fprintf(out, "ply\nformat ascii 1.0\ncomment sphsplat cache %s, %s\nelement vertex %zu\n",
                 o.cache.c_str(), what.c_str(), rows);
    for (const Column& c : columns)
      std::fprintf(out, "property %s %s\n", c.ids ? "uint" : "float", c.name.c_str());
    std::fprintf(out, "end_header\n");
    writeRows(out, columns, rows, ' ');
  }
  const bool failed = std::ferror(out) != 0;
  if (!toStdout && std::fclose(out) != 0)
    throw InputError(o.output + ": cannot write the export file");
  if (failed) throw InputError(path + ": cannot write the export");
  if (!toStdout)
    std::fprintf(stderr, "wrote %s: %zu %s of %s, %s\n", o.output.c_str(), rows,
                 o.boundary ? "points" : "particles", what.c_str(), o.format.c_str());
  return kOk;
}

}  // namespace

std::function<int()> addExportCommand(CLI::App& app) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand("export", "Write one frame of an HDF5 cache as CSV or PLY");
  cmd->add_option("cache", o->cache, "Cache file written by sphsplat run --output")->required();
  cmd->add_option("--frame,-f", o->frame, "Frame index (0 = the initial state) or 'last'")
      ->capture_default_str();
  cmd->add_option("--format", o->format,
                  "csv (a header row, one particle per line) or ply (ASCII point cloud)")
      ->required()
      ->check(CLI::IsMember({"csv", "ply"}));
  cmd->add_option("--output,-o", o->output, "File to write; '-' for standard output")->required();
  cmd->add_option("--fields", o->fields, "Only these datasets besides x y z, e.g. --fields rho,p")
      ->delimiter(',');
  cmd->add_flag("--boundary", o->boundary,
                "Export the (static) boundary particles instead of a frame");
  cmd->footer(
      "Exit codes: 0 done, 2 missing/damaged/foreign cache, missing dataset or frame out of "
      "range.");
  return [o, cmd]() { return cmd->parsed() ? exportFrame(*o) : -1; };
}

}  // namespace sph::app
