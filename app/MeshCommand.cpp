// `sphsplat mesh CACHE --frames F --out OUT [--format ply|obj]`: the water surface of cached
// frames as triangle meshes for Blender, Houdini and the like (docs/mesh.md): the SD iso-surface
// of the renderer's density field (render/mesh/SurfaceMesh.h), with the scene's render settings
// (kernel radius, surface threshold; --set edits them). Files are named as `export` names them
// (job/OutputNames.h); nothing existing is replaced without --overwrite, and each file is written
// under a temporary name and renamed once complete (io/UserFiles.h).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/CliChecks.h"
#include "app/Commands.h"
#include "io/MessageText.h"
#include "io/UserFiles.h"
#include "io/cache/CacheReader.h"
#include "io/cache/XdmfWriter.h"
#include "io/exports/MeshFiles.h"
#include "job/CacheScene.h"
#include "job/OutputNames.h"
#include "render/mesh/SurfaceMesh.h"
#include "render/splat/SplatBuilder.h"
#include "sim/HumanText.h"
#include "sim/InputError.h"
#include "sim/Parallel.h"

namespace sph::app {
namespace {

struct MeshOptions {
  std::string cache;
  std::string frames = "last";
  std::string output;
  std::string format;  // "" = from the output's extension, else ply
  float cell = 0.5f;   // spacings
  std::vector<std::string> overrides;
  int threads = 0;
  bool overwrite = false;
  bool quiet = false;
};

std::string formatOf(const MeshOptions& o) {
  if (o.output.empty()) throw InputError("--out: expected a file, a name with %05d or a directory");
  if (!o.format.empty()) return o.format;
  // A name the system cannot look up (a symlink loop, a component over 255 bytes, a directory
  // that cannot be searched) is no directory here; checking the output says what is wrong.
  std::error_code unreadable;
  if (o.output.find('%') == std::string::npos && o.output.back() != '/' &&
      !std::filesystem::is_directory(o.output, unreadable)) {
    const std::string ext = job::extensionOf(o.output);
    if (ext == "ply" || ext == "obj") return ext;
    throw InputError("--format: expected ply or obj (the name " + io::printablePath(o.output) +
                     " does not say which)");
  }
  const std::string ext = job::extensionOf(o.output);
  return ext == "obj" ? "obj" : "ply";
}

void writeMesh(const std::string& path, const std::string& format,
               const io::exports::MeshView& mesh) {
  job::writeOutput(path, "the mesh", [&](std::FILE* out) {
    if (format == "obj")
      io::exports::writeMeshObj(out, mesh, path);
    else
      io::exports::writeMeshPly(out, mesh, path);
  });
}

int meshFrames(const MeshOptions& o) {
  setThreadCount(o.threads);
  const std::string format = formatOf(o);
  const io::cache::CacheReader reader(o.cache);
  const io::cache::CacheSummary& s = reader.summary();
  const scene::Scene scene = job::sceneOfCache(s, o.overrides);
  const scene::RenderDesc desc = scene.render ? *scene.render : scene::RenderDesc{};
  const std::vector<std::size_t> frames =
      job::parseFrameRange(o.frames, reader.frameCount(), "--frames");
  const job::OutputNames names(o.output, format, job::fileSafe(s.sceneName), frames.size(),
                               "--out");
  const std::vector<io::ReadFile> reads = {
      {o.cache, "the cache being meshed"},
      {io::cache::XdmfWriter::sidecarPath(o.cache), "the cache's XDMF sidecar"}};
  // Every output is checked before the first is written.
  std::vector<std::string> paths;
  for (const std::size_t f : frames) paths.push_back(names.file(f));
  prepareOutputs(names, paths, o.overwrite, reads);

  const float spacing = scene.solver.spacing, cellSize = o.cell * spacing;
  const bool lines = !o.quiet && o.output != "-";
  if (lines && frames.size() > 1) {
    std::fprintf(stderr, "%s: meshing %zu frames of %s (cell %s m, kernel radius %g spacings)\n",
                 s.sceneName.c_str(), frames.size(), o.cache.c_str(),
                 io::readableNumber(cellSize).c_str(), desc.kernelRadius);
  }
  io::cache::FieldSet xyz;
  for (auto f : {io::cache::Field::X, io::cache::Field::Y, io::cache::Field::Z})
    xyz.set(static_cast<std::size_t>(f));
  const auto start = std::chrono::steady_clock::now();
  double meshSeconds = 0;
  std::size_t fewest = static_cast<std::size_t>(-1), most = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::size_t f = frames[k];
    const Particles p = reader.readFrame(f, xyz);
    job::checkPositions(p.x, p.y, p.z, scene, "frame " + std::to_string(f), o.cache);
    const auto t0 = std::chrono::steady_clock::now();
    const render::splat::DensityField field(p.x.data(), p.y.data(), p.z.data(), p.size(), spacing,
                                            desc.kernelRadius, scene.solver.restDensity);
    const float SD = render::splat::surfaceDensity(field, desc.surfaceThreshold);
    const render::mesh::SurfaceMesh mesh = render::mesh::extractSurface(field, SD, cellSize);
    meshSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    io::exports::MeshView view;
    view.positions = mesh.positions.data(), view.normals = mesh.normals.data();
    view.vertices = mesh.vertexCount();
    view.triangles = mesh.triangles.data(), view.triangleCount = mesh.triangleCount();
    view.comments = {
        "sphsplat mesh: SD iso-surface of the splat renderer's density field (docs/mesh.md)",
        "cache " + o.cache + ", frame " + std::to_string(f) +
            " (t = " + io::readableNumber(s.frames[f].time) + " s), " + std::to_string(p.size()) +
            " particles",
        "SD " + io::readableNumber(SD) + " kg/m^3, kernel radius " +
            io::readableNumber(field.kernelRadius()) + " m, cell " + io::readableNumber(cellSize) +
            " m; units m, normals outward"};
    const std::string path = names.file(f);
    writeMesh(path, format, view);
    fewest = std::min(fewest, mesh.triangleCount());
    most = std::max(most, mesh.triangleCount());
    if (!lines) continue;
    if (frames.size() == 1) {
      io::sayWritten(path + ": " + humanCount(static_cast<double>(mesh.triangleCount())) +
                     " triangles, " + humanCount(static_cast<double>(mesh.vertexCount())) +
                     " vertices of frame " + std::to_string(f) + " (" + std::to_string(p.size()) +
                     " particles), " + humanSeconds(meshSeconds));
    } else if ((k + 1) * 10 / frames.size() != k * 10 / frames.size() || k + 1 == frames.size()) {
      // A line every tenth of the frames (and for the last one).
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double left =
          elapsed / static_cast<double>(k + 1) * static_cast<double>(frames.size() - k - 1);
      std::fprintf(stderr,
                   "%s %3zu%%  frame %zu (%zu of %zu), %s triangles, %s per frame, ETA %s\n",
                   s.sceneName.c_str(), 100 * (k + 1) / frames.size(), f, k + 1, frames.size(),
                   humanCount(static_cast<double>(mesh.triangleCount())).c_str(),
                   humanSeconds(meshSeconds / static_cast<double>(k + 1)).c_str(),
                   humanSeconds(left).c_str());
    }
  }
  if (lines && frames.size() > 1) {
    io::sayWritten(std::to_string(frames.size()) + " " + format + " files " +
                   names.file(frames.front()) + " .. " + job::baseName(names.file(frames.back())) +
                   ": " + humanCount(static_cast<double>(fewest)) + "-" +
                   humanCount(static_cast<double>(most)) + " triangles each");
  }
  return job::exitAfterReading(s);
}

}  // namespace

std::function<int()> addMeshCommand(CLI::App& app) {
  auto o = std::make_shared<MeshOptions>();
  CLI::App* cmd = app.add_subcommand(
      "mesh", "Write the water surface of cached frames as triangle meshes (PLY or OBJ)");
  cmd->add_option("cache", o->cache, "Cache file written by sphsplat run --output")->required();
  cmd->add_option("--frames,--frame,-f", o->frames,
                  "Frames as for render: N, last or -1, A:B (inclusive), A:, :B, all")
      ->capture_default_str();
  cmd->add_option("--out,--output,-o", o->output,
                  "File to write ('-' for standard output); for several frames a name with %05d "
                  "where the frame number goes (out/water_%05d.ply) or a directory, existing or "
                  "ending in / (files SCENE_NNNNN.FORMAT)")
      ->required();
  cmd->add_option("--format", o->format,
                  "ply (binary, with vertex normals) or obj (text, with vertex normals). "
                  "Default: the output's extension; ply for a directory")
      ->check(CLI::IsMember({"ply", "obj"}));
  cmd->add_option("--cell", o->cell,
                  "Marching-cubes cell edge in particle spacings (smaller: finer and slower; "
                  "triangles grow as 1/cell^2)")
      ->capture_default_str()
      ->check(positiveUpTo(10, "spacings"));
  cmd->add_option("--set", o->overrides,
                  "Edit the recorded scene, e.g. --set render.surface_threshold=0.6 or "
                  "render.kernel_radius=3 (the surface is the renderer's: docs/rendering.md)");
  cmd->add_option("--threads,-j", o->threads, "Worker threads (default: all cores)")
      ->check(threadsCheck());
  cmd->add_flag("--overwrite", o->overwrite, "Replace existing files (never the cache itself)");
  cmd->add_flag("--quiet,-q", o->quiet, "No progress or summary lines");
  cmd->footer(
      "The surface is where the renderer's density field D crosses SD, the level the splats and\n"
      "the reference ray-marcher show; vertex normals are -grad D (outward), units are metres,\n"
      "y up as in the scene. Each file appears complete or not at all (a killed run leaves at\n"
      "most a NAME.partial-XXXXXX beside it). Exit codes: 0 done, 2 missing/damaged cache,\n"
      "frames not in the cache, an output that exists (without --overwrite) or is not a file.");
  return [o, cmd]() { return cmd->parsed() ? meshFrames(*o) : -1; };
}

}  // namespace sph::app
