#include "job/CompareJob.h"

#include <cstdio>
#include <string>
#include <vector>

#include "io/MessageText.h"
#include "io/exports/Png.h"
#include "job/CacheRendering.h"
#include "job/CacheScene.h"
#include "job/ExitCode.h"
#include "job/RenderOutput.h"
#include "render/compose/SceneFrame.h"
#include "render/frame/Annotate.h"
#include "render/gl/GlContext.h"
#include "render/lights/LightComparison.h"
#include "render/solids/SceneSolids.h"
#include "sim/lights/LightParticles.h"
#include "sim/scene/EnumNames.h"

namespace sph::job {
namespace {

std::string fmt(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, format, a, b, c, d);
  return buf;
}

// The particle lights' error figures (scene section `lights`; docs/lights.md): the light alone
// on the solids through each filter beside the exact sum, a table and a sheet of pictures.
void compareParticleLights(CacheRendering& c, std::size_t f, const Particles& p,
                           const std::string& out) {
  const scene::LightsDesc& desc = *c.scene.lights;
  render::lights::LightVolume volume(desc);
  const std::vector<lights::LightParticle> lights =
      sph::lights::lightParticles(desc, p, c.frameTime(f), sph::lights::lightSolids(c.scene));
  volume.update(lights);  // the first dispatch compiles llvmpipe's shader variants
  const double accumulate = volume.update(lights);
  const std::unique_ptr<render::solids::SolidRenderer> solids =
      render::solids::sceneSolids(c.scene);
  const render::lights::SolidGBuffer g =
      render::lights::solidGBuffer(*solids, c.camera, c.desc.width, c.desc.height);
  std::printf(
      "particle lights: %zu lights, %d x %d x %d voxels of %.3g m, %s accumulation %.1f ms\n",
      lights.size(), desc.voxels[0], desc.voxels[1], desc.voxels[2], desc.voxelSize,
      enumName(volume.desc().accumulate), 1e3 * accumulate);
  if (g.points.empty()) {
    std::printf("  no solid in view: no particle-light error figures\n");
    return;
  }
  using render::lights::FilterSetting;
  const std::vector<FilterSetting> settings = {{scene::LightFilter::Nearest, 0, 1},
                                               {scene::LightFilter::Trilinear, 0, 1},
                                               {scene::LightFilter::Tricubic, 0, 1},
                                               {scene::LightFilter::Trilinear, 0, 2},
                                               {scene::LightFilter::Tricubic, 1, 2}};
  const std::vector<render::lights::LightComparison> results =
      render::lights::compareLights(volume, lights, g, solids->material.colour, settings);
  std::printf("  light on the solids (%zu pixels) against the exact sum over the lights:\n",
              g.points.size());
  std::printf("  %-16s %9s | %8s %9s | %8s %9s | %8s %9s\n", "filter", "ms", "PSNR dB", "mean abs",
              "diff dB", "diff abs", "spec dB", "spec abs");
  std::vector<render::frame::Panel> panels;
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
  const render::frame::RenderImage sheet = render::frame::composePanels(panels, 1);
  const std::string path =
      out + "/" + io::exports::framePngName(c.scene.name + "_lights_compare", f);
  io::exports::writePng(path, sheet.width, sheet.height, sheet.rgb.data());
  io::sayWritten(path);
}

}  // namespace

int compareJob(const CompareRequest& o) {
  CacheRendering c(o.cache, o.overrides, "both", o.size);
  const std::size_t f = parseOneFrame(o.frame, c.frameCount(), "--frame");
  const io::OutputLock directoryLock = lockDirectory(o.out);
  makeDirectory(o.out);
  render::gl::GlContext context = render::gl::GlContext::headless();
  // Opaque solids are drawn in every panel, the reference's included (GL draws them for it: the
  // rays end on them). Boundary points are translucent: the reference could not have them, so
  // the panels show the water alone then.
  render::compose::SceneFrame sceneFrame(c.scene, c.desc, {},
                                         render::compose::SceneParts::scored());
  render::splat::FrameRenderer& renderer = sceneFrame.renderer();
  const bool solids = c.desc.solids == scene::RenderSolids::Opaque;
  const Particles p = c.positions(f);
  if (!c.cameraFromScene)
    c.camera = render::splat::framingCamera(p, static_cast<float>(c.desc.width) / c.desc.height);
  sceneFrame.setWater(p);
  const render::splat::RenderedSplats point =
      renderer.renderScored(render::splat::SplatKind::Point, c.camera);
  const render::splat::RenderedSplats quad =
      renderer.renderScored(render::splat::SplatKind::Quad, c.camera);
  const render::frame::RenderImage reference = renderer.reference(c.camera);
  const render::frame::RenderImage everyParticle = renderer.referenceOfEveryParticle(c.camera);
  const render::frame::ImageError ep = render::frame::compareImages(point.image, reference);
  const render::frame::ImageError eq = render::frame::compareImages(quad.image, reference);
  const render::frame::ThinCoverage tp =
      render::frame::thinCoverage(point.image, reference, everyParticle);
  const render::frame::ThinCoverage tq =
      render::frame::thinCoverage(quad.image, reference, everyParticle);

  const double time = c.frameTime(f);
  std::printf(
      "%s frame %zu (t = %.3f s): %zu particles, %zu surface (SD = %.3f x ID), %zu splats drawn "
      "(%s)\n",
      c.scene.name.c_str(), f, time, point.particles, point.surface,
      point.ID > 0 ? point.SD / point.ID : 0.0, point.splats,
      point.splats < point.surface ? "the rest face away" : "back faces too");
  std::printf("  %-6s %9s %9s %9s %9s %9s | %8s %8s %11s\n", "splats", "field ms", "surf ms",
              "normal ms", "build ms", "draw ms", "PSNR dB", "holes %", "normal deg");
  auto row = [&](const char* name, const render::splat::RenderedSplats& r,
                 const render::frame::ImageError& e) {
    std::printf("  %-6s %9.1f %9.1f %9.1f %9.1f %9.1f | %8.2f %8.2f %11.1f\n", name,
                1e3 * r.timings.field, 1e3 * r.timings.splats.surface,
                1e3 * r.timings.splats.normals, 1e3 * r.timings.splats.build, 1e3 * r.timings.draw,
                e.psnr, 100 * e.holeFraction, e.normalErrorDegrees);
  };
  row("point", point, ep);
  row("quad", quad, eq);
  std::printf("  reference ray-marched in %.2f s%s\n", reference.seconds,
              solids ? " (the solids drawn by GL, the rays ending on them)" : "");
  std::printf(
      "  beyond the SD surface (thin jets, lone drops, the outer half of the surface layer): %zu "
      "pixels of particle balls; point "
      "splats cover %.1f%%, quad %.1f%%\n",
      tq.pixels, 100 * tp.fraction, 100 * tq.fraction);

  const std::string method =
      c.desc.projection == scene::SplatProjection::Newton ? "newton" : "eq. (6)";
  std::vector<render::frame::Panel> panels = {
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
        fmt("sd = %.3f x id", point.ID > 0 ? point.SD / point.ID : 0.0),
        fmt("frame %.0f, t = %.3f s", static_cast<double>(f), time)}},
      {&everyParticle,
       {"every particle (balls of its volume)", fmt("%.2f s", everyParticle.seconds),
        fmt("beyond sd: %.0f px", static_cast<double>(tq.pixels)),
        fmt("point cover %.1f%%  quad %.1f%%", 100 * tp.fraction, 100 * tq.fraction)}},
  };
  const render::frame::RenderImage sheet = render::frame::composePanels(panels, 2, 2);
  const std::string path = o.out + "/" + io::exports::framePngName(c.scene.name + "_compare", f);
  io::exports::writePng(path, sheet.width, sheet.height, sheet.rgb.data());
  io::sayWritten(path);
  if (c.scene.lights) compareParticleLights(c, f, p, o.out);
  return exitAfterReading(c.reader().summary());
}

}  // namespace sph::job
