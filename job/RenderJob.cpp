#include "job/RenderJob.h"

#include <cstdio>
#include <string>
#include <vector>

#include "io/exports/Png.h"
#include "job/CacheRain.h"
#include "job/CacheRendering.h"
#include "job/CacheScene.h"
#include "job/ExitCode.h"
#include "job/RenderOutput.h"
#include "render/compose/SceneFrame.h"
#include "render/gl/GlContext.h"
#include "sim/scene/Camera.h"
#include "sim/scene/EnumNames.h"

namespace sph::job {

int renderJob(const RenderRequest& o) {
  CacheRendering c(o.cache, o.overrides, o.splat, o.size);
  const std::vector<std::size_t> frames = parseFrameRange(o.frames, c.frameCount(), "--frames");
  // Owned for the whole command: pictures (and, with --to-cache, the cache) are not shared with a
  // run or another render writing there at the same time.
  const io::OutputLock directoryLock = lockDirectory(o.out);
  io::OutputLock cacheLock;
  if (o.toCache) cacheLock = io::OutputLock::acquire(o.cache, "cache");
  makeDirectory(o.out);
  render::gl::GlContext context = render::gl::GlContext::headless();
  render::compose::SceneFrame sceneFrame(c.scene, c.desc, [&] { return c.boundary(); });
  render::lights::SceneLights* const lights = sceneFrame.lights();
  if (!o.quiet) {
    std::printf(
        "%s: rendering %zu frame%s of %s at %dx%d with %s splats on %s\n", c.scene.name.c_str(),
        frames.size(), frames.size() == 1 ? "" : "s", o.cache.c_str(), c.desc.width, c.desc.height,
        c.desc.splat == scene::RenderDesc::Splat::Both ? "point and quad"
                                                       : scene::enumName(sceneFrame.kinds()[0]),
        context.info().renderer.c_str());
    if (lights)
      std::printf("  %s\n", render::lights::describeLights(lights->volume().desc()).c_str());
  }
  double seconds = 0;
  std::size_t images = 0;
  std::string first, last;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::size_t f = frames[k];
    const Particles p = c.positions(f);
    if (!c.cameraFromScene && k == 0)
      c.camera = render::splat::framingCamera(p, static_cast<float>(c.desc.width) / c.desc.height);
    const double time = c.frameTime(f);
    const scene::CameraDesc camera =
        c.cameraFromScene ? cameraAt(c.camera, c.scene.cameraPath, time) : c.camera;
    // The rain: the drops the run stored, else regenerated (job/CacheRain.h).
    if (sceneFrame.rain()) showCachedRain(*sceneFrame.rain(), c.reader(), f, time, p);
    const render::compose::Pictures drawn = sceneFrame.draw(p, time, camera);
    seconds += drawn.lightSeconds;
    for (const render::compose::Picture& picture : drawn.pictures) {
      const render::frame::RenderImage& image = picture.splats.image;
      seconds += picture.splats.timings.total();
      const std::string path =
          o.out + "/" +
          io::exports::framePngName(c.scene.name + "_" + scene::enumName(picture.kind), f);
      io::exports::writePng(path, image.width, image.height, image.rgb.data());
      if (o.toCache) c.store(scene::enumName(picture.kind), f, image);
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
  return exitAfterReading(c.reader().summary());
}

}  // namespace sph::job
