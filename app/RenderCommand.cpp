// `sphsplat render CACHE` (frames to PNGs and, if asked, into the cache) and `sphsplat compare
// CACHE --frame N` (point splats, quad splats and the reference side by side, with times and
// error figures). No simulation: the particles come from the cache.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "app/CacheRain.h"
#include "app/CacheScene.h"
#include "app/Commands.h"
#include "app/RenderOutput.h"
#include "io/CacheReader.h"
#include "io/CacheWriter.h"
#include "io/MessageText.h"
#include "io/Png.h"
#include "render/gl/GlContext.h"
#include "render/lights/LightComparison.h"
#include "render/lights/SceneLights.h"
#include "render/rain/SceneRain.h"
#include "render/solids/SceneSolids.h"
#include "render/splat/Annotate.h"
#include "render/splat/FrameRenderer.h"
#include "sim/Camera.h"
#include "sim/InputError.h"
#include "sim/LightParticles.h"
#include "sim/SceneSetup.h"

namespace sph::app {
namespace {

struct RenderOptions {
  std::string cache;
  std::string frames = "0:";
  std::string splat;
  std::string size;
  std::string out = "results/render";
  bool toCache = false;
  bool quiet = false;
  std::vector<std::string> overrides;
};

void applySize(const std::string& size, RenderDesc& d) {
  if (size.empty()) return;
  // WIDTHxHEIGHT, each 16-8192: strtol with its end checked (sscanf's %d overflows silently).
  auto dimension = [](const std::string& text, long& value) {
    char* end = nullptr;
    errno = 0;
    value = std::strtol(text.c_str(), &end, 10);
    return !text.empty() && errno == 0 && *end == 0 && value >= 16 && value <= 8192;
  };
  const std::size_t x = size.find_first_of("xX");
  long w = 0, h = 0;
  if (x == std::string::npos || !dimension(size.substr(0, x), w) ||
      !dimension(size.substr(x + 1), h)) {
    throw InputError(
        "--size: expected WIDTHxHEIGHT between 16 and 8192 pixels, e.g. 960x540, got '" +
        io::printable(size) + "'");
  }
  d.width = static_cast<int>(w), d.height = static_cast<int>(h);
}

std::vector<render::splat::SplatKind> kindsOf(RenderDesc::Splat s) {
  if (s == RenderDesc::Splat::Point) return {render::splat::SplatKind::Point};
  if (s == RenderDesc::Splat::Quad) return {render::splat::SplatKind::Quad};
  return {render::splat::SplatKind::Point, render::splat::SplatKind::Quad};
}

// Everything a command needs to draw frames of a cache.
struct CacheRendering {
  std::string path;
  std::unique_ptr<io::CacheReader>
      open;  // released while the cache is written (HDF5 allows one mode)
  io::CacheSummary summary;
  Scene scene;
  RenderDesc desc;
  CameraDesc camera;
  bool cameraFromScene = false;

  CacheRendering(const std::string& path_, const std::vector<std::string>& overrides,
                 const std::string& splat, const std::string& size)
      : path(path_),
        open(std::make_unique<io::CacheReader>(path_)),
        summary(open->summary()),
        scene(sceneOfCache(summary, overrides)) {
    desc = scene.render ? *scene.render : RenderDesc{};
    if (!splat.empty()) desc.splat = *parseEnum<RenderDesc::Splat>(splat);
    applySize(size, desc);
    cameraFromScene = scene.camera.has_value();
    if (cameraFromScene) camera = *scene.camera;
  }
  io::CacheReader& reader() {
    if (!open) open = std::make_unique<io::CacheReader>(path);
    return *open;
  }
  std::size_t frameCount() const { return summary.frames.size(); }
  Particles positions(std::size_t frame) {
    io::cache::FieldSet xyz;
    for (auto f : {io::cache::Field::X, io::cache::Field::Y, io::cache::Field::Z})
      xyz.set(static_cast<std::size_t>(f));
    // Lights coloured by speed need the velocities (docs/lights.md, "Replay").
    if (render::lights::lightsNeedVelocity(scene))
      for (auto f : {io::cache::Field::VX, io::cache::Field::VY, io::cache::Field::VZ})
        xyz.set(static_cast<std::size_t>(f));
    return reader().readFrame(frame, xyz);
  }
  // Stores an image in the cache: the reader lets go of the file meanwhile.
  void store(const std::string& renderer, std::size_t frame,
             const render::splat::RenderImage& image) {
    open.reset();
    std::unique_ptr<io::CacheWriter> writer = io::CacheWriter::append(path, frameCount());
    writer->writeRenderedFrame(renderer, frame, image.width, image.height, image.rgb.data());
    writer->close();
  }
};

int render(const RenderOptions& o) {
  CacheRendering c(o.cache, o.overrides, o.splat, o.size);
  const std::vector<std::size_t> frames = parseFrameRange(o.frames, c.frameCount(), "--frames");
  // Owned for the whole command: pictures (and, with --to-cache, the cache) are not shared with a
  // run or another render writing there at the same time.
  const io::OutputLock directoryLock = lockDirectory(o.out);
  io::OutputLock cacheLock;
  if (o.toCache) cacheLock = io::OutputLock::acquire(o.cache, "cache");
  makeDirectory(o.out);
  render::gl::GlContext context = render::gl::GlContext::headless();
  render::splat::FrameRenderer renderer(c.desc, c.scene.solver.spacing, c.scene.solver.restDensity);
  const auto solids = render::solids::showSolids(c.scene, renderer, [&] {
    const auto b = c.reader().readBoundary();
    return std::array<std::vector<float>, 3>{b[0], b[1], b[2]};
  });
  const auto lights = render::lights::showLights(c.scene, renderer);
  // The rain: the drops the run stored, else regenerated (app/CacheRain.h).
  const auto rain = render::rain::showRain(c.scene, renderer, solids.get());
  if (!o.quiet) {
    std::printf("%s: rendering %zu frame%s of %s at %dx%d with %s splats on %s\n",
                c.scene.name.c_str(), frames.size(), frames.size() == 1 ? "" : "s", o.cache.c_str(),
                c.desc.width, c.desc.height,
                c.desc.splat == RenderDesc::Splat::Both ? "point and quad"
                                                        : enumName(kindsOf(c.desc.splat)[0]),
                context.info().renderer.c_str());
    if (lights) std::printf("  %s\n", render::lights::describeLights(*c.scene.lights).c_str());
  }
  double seconds = 0;
  std::size_t images = 0;
  std::string first, last;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::size_t f = frames[k];
    const Particles p = c.positions(f);
    if (!c.cameraFromScene && k == 0)
      c.camera = render::splat::framingCamera(p, static_cast<float>(c.desc.width) / c.desc.height);
    renderer.prepare(p);
    if (lights) seconds += lights->update(p, c.summary.frames[f].time);
    const double time = c.summary.frames[f].time;
    const CameraDesc camera =
        c.cameraFromScene ? cameraAt(c.camera, c.scene.cameraPath, time) : c.camera;
    if (rain) showCachedRain(*rain, c.reader(), f, time, p);
    for (render::splat::SplatKind kind : kindsOf(c.desc.splat)) {
      const render::splat::RenderedSplats r = renderer.render(kind, camera);
      seconds += r.timings.total();
      const std::string path =
          o.out + "/" + io::framePngName(c.scene.name + "_" + enumName(kind), f);
      io::writePng(path, r.image.width, r.image.height, r.image.rgb.data());
      if (o.toCache) c.store(enumName(kind), f, r.image);
      if (first.empty()) first = path;
      last = path;
      ++images;
    }
    // A line every tenth of the frames (and for the last one).
    if (!o.quiet && frames.size() > 1 &&
        ((k + 1) * 10 / frames.size() != k * 10 / frames.size() || k + 1 == frames.size())) {
      std::fprintf(stderr, "%s %3zu%%  frame %zu (%zu of %zu), %zu particles, %.0f ms per image\n",
                   c.scene.name.c_str(), 100 * (k + 1) / frames.size(), f, k + 1, frames.size(),
                   p.size(), images ? 1e3 * seconds / images : 0.0);
    }
  }
  if (!o.quiet) {
    std::printf("done: %zu image%s in %s (%s .. %s), %.1f ms per image to build and draw\n", images,
                images == 1 ? "" : "s", o.out.c_str(), first.c_str(), last.c_str(),
                images ? 1e3 * seconds / images : 0.0);
    if (o.toCache) std::printf("  also stored in %s as Render#<point|quad>#N\n", o.cache.c_str());
  }
  return kOk;
}

struct CompareOptions {
  std::string cache;
  std::string frame = "last";
  std::string out = "results/compare";
  std::string size = "640x480";
  std::vector<std::string> overrides;
};

std::string fmt(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

// The particle lights' error figures (scene section `lights`; docs/lights.md): the light alone
// on the solids through each filter beside the exact sum, a table and a sheet of pictures.
void compareParticleLights(CacheRendering& c, std::size_t f, const Particles& p,
                           const std::string& out) {
  const LightsDesc& desc = *c.scene.lights;
  render::lights::LightVolume volume(desc);
  const std::vector<LightParticle> lights =
      lightParticles(desc, p, c.summary.frames[f].time, lightSolids(c.scene));
  volume.update(lights);  // the first dispatch compiles llvmpipe's shader variants
  const double accumulate = volume.update(lights);
  const float thickness = deriveParams(c.scene).boundaryLayers * c.scene.solver.spacing;
  const render::solids::SolidRenderer solids(c.scene.boundaries, c.scene.domain, thickness);
  const render::lights::SolidGBuffer g =
      render::lights::solidGBuffer(solids, c.camera, c.desc.width, c.desc.height);
  std::printf(
      "particle lights: %zu lights, %d x %d x %d voxels of %.3g m, %s accumulation %.1f ms\n",
      lights.size(), desc.voxels[0], desc.voxels[1], desc.voxels[2], desc.voxelSize,
      enumName(desc.accumulate), 1e3 * accumulate);
  if (g.points.empty()) {
    std::printf("  no solid in view: no particle-light error figures\n");
    return;
  }
  using render::lights::FilterSetting;
  const std::vector<FilterSetting> settings = {{LightFilter::Nearest, 0, 1},
                                               {LightFilter::Trilinear, 0, 1},
                                               {LightFilter::Tricubic, 0, 1},
                                               {LightFilter::Trilinear, 0, 2},
                                               {LightFilter::Tricubic, 1, 2}};
  const std::vector<render::lights::LightComparison> results =
      render::lights::compareLights(volume, lights, g, solids.material.colour, settings);
  std::printf("  light on the solids (%zu pixels) against the exact sum over the lights:\n",
              g.points.size());
  std::printf("  %-16s %9s | %8s %9s | %8s %9s | %8s %9s\n", "filter", "ms", "PSNR dB", "mean abs",
              "diff dB", "diff abs", "spec dB", "spec abs");
  std::vector<render::splat::Panel> panels;
  for (const auto& r : results) {
    std::printf("  %-16s %9.1f | %8.2f %9.5f | %8.2f %9.5f | %8.2f %9.5f\n", r.name.c_str(),
                1e3 * r.seconds, r.total.psnr, r.total.meanAbs, r.diffuse.psnr, r.diffuse.meanAbs,
                r.specular.psnr, r.specular.meanAbs);
    panels.push_back(
        {&r.image,
         {r.name,
          r.name == "exact" ? fmt("cpu sum %.0f ms", 1e3 * r.seconds)
                            : fmt("psnr %.2f db", r.total.psnr),
          r.name == "exact" ? std::string("reference") : fmt("spec %.2f db", r.specular.psnr)}});
  }
  const render::splat::RenderImage sheet = render::splat::composePanels(panels, 1);
  const std::string path = out + "/" + io::framePngName(c.scene.name + "_lights_compare", f);
  io::writePng(path, sheet.width, sheet.height, sheet.rgb.data());
  std::printf("wrote %s\n", path.c_str());
}

int compare(const CompareOptions& o) {
  CacheRendering c(o.cache, o.overrides, "both", o.size);
  const std::size_t f = parseOneFrame(o.frame, c.frameCount(), "--frame");
  const io::OutputLock directoryLock = lockDirectory(o.out);
  makeDirectory(o.out);
  render::gl::GlContext context = render::gl::GlContext::headless();
  render::splat::FrameRenderer renderer(c.desc, c.scene.solver.spacing, c.scene.solver.restDensity);
  const Particles p = c.positions(f);
  if (!c.cameraFromScene)
    c.camera = render::splat::framingCamera(p, static_cast<float>(c.desc.width) / c.desc.height);
  renderer.prepare(p);
  const render::splat::RenderedSplats point =
      renderer.renderScored(render::splat::SplatKind::Point, c.camera);
  const render::splat::RenderedSplats quad =
      renderer.renderScored(render::splat::SplatKind::Quad, c.camera);
  const render::splat::RenderImage reference = renderer.reference(c.camera);
  const render::splat::ImageError ep = render::splat::compareImages(point.image, reference);
  const render::splat::ImageError eq = render::splat::compareImages(quad.image, reference);

  const double time = c.summary.frames[f].time;
  std::printf(
      "%s frame %zu (t = %.3f s): %zu particles, %zu surface (SD = %.3f x ID), %zu splats drawn "
      "(%s)\n",
      c.scene.name.c_str(), f, time, point.particles, point.surface, point.SD / point.ID,
      point.splats, point.splats < point.surface ? "the rest face away" : "back faces too");
  std::printf("  %-6s %9s %9s %9s %9s %9s | %8s %8s %11s\n", "splats", "field ms", "surf ms",
              "normal ms", "build ms", "draw ms", "PSNR dB", "holes %", "normal deg");
  auto row = [&](const char* name, const render::splat::RenderedSplats& r,
                 const render::splat::ImageError& e) {
    std::printf("  %-6s %9.1f %9.1f %9.1f %9.1f %9.1f | %8.2f %8.2f %11.1f\n", name,
                1e3 * r.timings.field, 1e3 * r.timings.splats.surface,
                1e3 * r.timings.splats.normals, 1e3 * r.timings.splats.build, 1e3 * r.timings.draw,
                e.psnr, 100 * e.holeFraction, e.normalErrorDegrees);
  };
  row("point", point, ep);
  row("quad", quad, eq);
  std::printf("  reference ray-marched in %.2f s\n", reference.seconds);

  const std::string method = c.desc.projection == SplatProjection::Newton ? "newton" : "eq. (6)";
  std::vector<render::splat::Panel> panels = {
      {&point.image,
       {"point splats", fmt("%.1f ms build + draw", 1e3 * point.timings.total()),
        fmt("psnr %.2f db  holes %.2f%%", ep.psnr, 100 * ep.holeFraction),
        fmt("normal error %.1f deg", ep.normalErrorDegrees)}},
      {&quad.image,
       {"quad splats (" + method + ")", fmt("%.1f ms build + draw", 1e3 * quad.timings.total()),
        fmt("psnr %.2f db  holes %.2f%%", eq.psnr, 100 * eq.holeFraction),
        fmt("normal error %.1f deg", eq.normalErrorDegrees)}},
      {&reference,
       {"reference (ray-marched)", fmt("%.2f s", reference.seconds),
        fmt("sd = %.3f x id", point.SD / point.ID),
        fmt("frame %.0f, t = %.3f s", static_cast<double>(f), time)}},
  };
  const render::splat::RenderImage sheet = render::splat::composePanels(panels);
  const std::string path = o.out + "/" + io::framePngName(c.scene.name + "_compare", f);
  io::writePng(path, sheet.width, sheet.height, sheet.rgb.data());
  std::printf("wrote %s\n", path.c_str());
  if (c.scene.lights) compareParticleLights(c, f, p, o.out);
  return kOk;
}

}  // namespace

std::function<int()> addRenderCommand(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render frames of a cache with point or quad splats (no simulation)");
  cmd->add_option("cache", o->cache, "HDF5 cache written by `sphsplat run`")->required();
  cmd->add_option("--frames", o->frames,
                  "Frames: N, A:B (inclusive), A:, :B, last or -1, all (default: all)");
  cmd->add_option(
         "--splat", o->splat,
         enumNameList<RenderDesc::Splat>() + " (default: the scene's render.splat, else quad)")
      ->check(CLI::IsMember(enumNames<RenderDesc::Splat>()));
  cmd->add_option("--size", o->size,
                  "Image size WIDTHxHEIGHT (default: the scene's render section, else 960x540)");
  cmd->add_option("--out", o->out, "Directory for the PNGs (created)")->capture_default_str();
  cmd->add_flag("--to-cache", o->toCache, "Also store the images in the cache under /Render");
  cmd->add_option("--set", o->overrides,
                  "Edit the recorded scene, e.g. --set render.projection=eq6 for the paper's rule "
                  "(repeatable)");
  cmd->add_flag("--quiet,-q", o->quiet, "No progress and no summary");
  cmd->footer(
      "The camera is the scene's; without one, a camera framing the first frame's particles.\n"
      "Needs OpenGL 4.5 (headless EGL; Mesa's llvmpipe works without a GPU).");
  return [o, cmd]() { return cmd->parsed() ? render(*o) : -1; };
}

std::function<int()> addCompareCommand(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Point vs quad splats vs the ray-marched reference, side by side with times and errors");
  cmd->add_option("cache", o->cache, "HDF5 cache written by `sphsplat run`")->required();
  cmd->add_option("--frame", o->frame, "Frame index, or last / -1 (default: last)");
  cmd->add_option("--out", o->out, "Directory for the PNG (created)")->capture_default_str();
  cmd->add_option("--size", o->size, "Size of each panel, WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--set", o->overrides,
                  "Edit the recorded scene, e.g. --set render.projection=eq6 for the paper's rule "
                  "(repeatable)");
  cmd->footer(
      "Errors are against a CPU ray-marcher of the same SPH iso-surface: PSNR of the colours,\n"
      "holes (surface pixels a renderer leaves empty) and the mean normal angle error.");
  return [o, cmd]() { return cmd->parsed() ? compare(*o) : -1; };
}

}  // namespace sph::app
