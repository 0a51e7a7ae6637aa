// `sphsplat export CACHE --frames F --format csv|ply|vtu -o OUT`: frames of a cache as files for
// tools that read neither HDF5 nor XDMF (io/exports/ParticleExport.h). One frame goes to OUT; a
// sequence goes to numbered files, OUT being a name with %05d (or %d) where the frame number goes,
// or a directory. Nothing existing is replaced without --overwrite, the cache itself never, and
// each file is written under a temporary name and renamed once complete (io/UserFiles.h).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/Commands.h"
#include "io/MessageText.h"
#include "io/UserFiles.h"
#include "io/cache/CacheReader.h"
#include "io/cache/XdmfWriter.h"
#include "io/exports/ParticleExport.h"
#include "job/CacheScene.h"
#include "job/OutputNames.h"
#include "sim/InputError.h"

namespace sph::app {
namespace {

namespace cache = io::cache;

struct ExportOptions {
  std::string cache;
  std::string frames = "last";
  std::string format;  // "" = from the output's extension
  std::string output;
  std::vector<std::string> fields;
  bool boundary = false;
  bool overwrite = false;
  const CLI::Option* framesOption = nullptr;
};

std::string formatOf(const ExportOptions& o) {
  if (!o.format.empty()) return o.format;
  const std::string ext = job::extensionOf(o.output);
  if (ext == "csv" || ext == "ply" || ext == "vtu") return ext;
  throw InputError("--format: expected csv, ply or vtu (the name " + io::printablePath(o.output) +
                   " does not say which)");
}

void writeFile(const std::string& path, const std::string& format,
               const io::exports::ExportFrame& frame) {
  job::writeOutput(path, "the export", [&](std::FILE* out) {
    if (format == "csv")
      io::exports::writeCsv(out, frame);
    else if (format == "ply")
      io::exports::writePly(out, frame);
    else
      io::exports::writeVtu(out, frame);
  });
}

int exportFrames(const ExportOptions& o) {
  const std::string format = formatOf(o);
  const io::cache::CacheReader reader(o.cache);
  const io::cache::CacheSummary& s = reader.summary();
  // Files the export reads, which no output may replace whatever path names them.
  const std::vector<io::ReadFile> reads = {
      {o.cache, "the cache being exported"},
      {io::cache::XdmfWriter::sidecarPath(o.cache), "the cache's XDMF sidecar"}};

  std::vector<std::size_t> frames;
  if (o.boundary) {
    if (o.framesOption && o.framesOption->count() > 0)
      throw InputError("--boundary exports the boundary, which has no frames; leave out --frames");
  } else {
    frames = job::parseFrameRange(o.frames, reader.frameCount(), "--frames");
  }
  const std::size_t files = o.boundary ? 1 : frames.size();
  const job::OutputNames names(o.output, format, job::fileSafe(s.sceneName), files);
  const bool pvd = format == "vtu" && names.sequence() && !o.boundary;

  // Every output is checked before the first is written.
  std::vector<std::string> paths;
  for (std::size_t k = 0; k < files; ++k) paths.push_back(names.file(o.boundary ? 0 : frames[k]));
  if (pvd) paths.push_back(names.pvd());
  prepareOutputs(names, paths, o.overwrite, reads);

  cache::FieldSet fields = s.fields;
  if (!o.fields.empty()) {
    std::string error;
    std::vector<std::string> list = o.fields;
    list.insert(list.end(), {"x", "y", "z"});
    fields = cache::parseFields(list, error);
    if (!error.empty()) throw InputError("--fields: " + io::printable(error, 240));
  }

  std::vector<io::exports::PvdEntry> collection;
  std::size_t fewest = static_cast<std::size_t>(-1), most = 0;
  std::string what;
  for (std::size_t k = 0; k < files; ++k) {
    Particles particles;
    io::exports::ExportFrame frame;
    frame.particles = &particles;
    if (o.boundary) {
      std::vector<std::vector<float>> b = reader.readBoundary();
      particles.x = std::move(b[0]), particles.y = std::move(b[1]), particles.z = std::move(b[2]);
      what = "boundary points";
      frame.source = "cache " + o.cache + ", boundary particles";
    } else {
      const std::size_t f = frames[k];
      particles = reader.readFrame(f, fields);  // names the missing dataset if one is asked for
      frame.fields = fields;
      frame.time = s.frames[f].time;
      frame.hasTime = true;
      const std::string frameText =
          "frame " + std::to_string(f) + " (t = " + io::readableNumber(frame.time) + " s)";
      what = "particles of " + frameText;
      frame.source = "cache " + o.cache + ", " + frameText;
    }
    const std::string path = names.file(o.boundary ? 0 : frames[k]);
    writeFile(path, format, frame);
    fewest = std::min(fewest, particles.size());
    most = std::max(most, particles.size());
    if (pvd) collection.push_back({frame.time, job::baseName(path)});
  }
  if (pvd) {
    io::AtomicOutput out(names.pvd());
    io::exports::writePvd(out.file(), collection);
    out.commit();
  }
  if (o.output == "-") return job::exitAfterReading(s);
  const std::string forParaView = pvd ? "; open " + names.pvd() + " in ParaView" : "";
  if (files == 1) {
    io::sayWritten(names.file(o.boundary ? 0 : frames[0]) + ": " + std::to_string(most) + " " +
                   what + ", " + format + forParaView);
  } else {
    const std::string counts =
        fewest == most ? std::to_string(most) : std::to_string(fewest) + "-" + std::to_string(most);
    io::sayWritten(std::to_string(files) + " " + format + " files " + names.file(frames.front()) +
                   " .. " + job::baseName(names.file(frames.back())) + ": frames " +
                   std::to_string(frames.front()) + "-" + std::to_string(frames.back()) +
                   " (t = " + io::readableNumber(s.frames[frames.front()].time) + " - " +
                   io::readableNumber(s.frames[frames.back()].time) + " s), " + counts +
                   " particles each" + (pvd ? forParaView + " for the times" : ""));
  }
  return job::exitAfterReading(s);
}

}  // namespace

std::function<int()> addExportCommand(CLI::App& app) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export", "Write frames of an HDF5 cache as CSV, PLY or VTK (.vtu, for ParaView)");
  cmd->add_option("cache", o->cache, "Cache file written by sphsplat run --output")->required();
  o->framesOption =
      cmd->add_option("--frames,--frame,-f", o->frames,
                      "Frames as for render: N, last or -1, A:B (inclusive), A:, :B, all")
          ->capture_default_str();
  cmd->add_option("--format", o->format,
                  "csv (a header row with units, a row per particle), ply (ASCII point cloud) or "
                  "vtu (VTK XML: vertex cells, every field as point data; ParaView, meshio). "
                  "Default: the output's extension")
      ->check(CLI::IsMember({"csv", "ply", "vtu"}));
  cmd->add_option("--output,-o", o->output,
                  "File to write ('-' for standard output); for several frames a name with %05d "
                  "where the frame number goes (out/frame_%05d.vtu) or a directory ending in / "
                  "(files SCENE_NNNNN.FORMAT)")
      ->required();
  cmd->add_option("--fields", o->fields, "Only these datasets besides x y z, e.g. --fields rho,p")
      ->delimiter(',');
  cmd->add_flag("--boundary", o->boundary,
                "Export the (static) boundary particles instead of a frame");
  cmd->add_flag("--overwrite", o->overwrite, "Replace existing files (never the cache itself)");
  cmd->footer(
      "A vtu sequence also gets a .pvd collection (frame.pvd for out/frame_%05d.vtu, SCENE.pvd in\n"
      "a directory) that gives ParaView the frames' times. Each file appears complete or not at\n"
      "all. Exit codes: 0 done, 2 missing/damaged/foreign cache, missing dataset, frames not in\n"
      "the cache, an output that exists (without --overwrite) or is not a regular file.");
  return [o, cmd]() { return cmd->parsed() ? exportFrames(*o) : -1; };
}

}  // namespace sph::app
