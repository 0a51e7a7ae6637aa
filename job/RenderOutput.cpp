#include "job/RenderOutput.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstdio>

#include "io/UserFiles.h"
#include "io/exports/Png.h"
#include "sim/InputError.h"
#include "sim/rain/RainFeed.h"
#include "sim/scene/Camera.h"

namespace sph::job {

io::OutputLock lockDirectory(const std::string& dir) {
  std::string parent = dir;
  while (parent.size() > 1 && parent.back() == '/') parent.pop_back();
  const std::size_t slash = parent.find_last_of('/');
  parent = slash == std::string::npos ? "." : parent.substr(0, std::max<std::size_t>(slash, 1));
  makeDirectory(parent);
  return io::OutputLock::acquire(dir, "frames directory");
}

void makeDirectory(const std::string& dir) {
  std::string partial;
  for (std::size_t i = 0; i <= dir.size(); ++i) {
    if ((i == dir.size() || dir[i] == '/') && !partial.empty()) ::mkdir(partial.c_str(), 0755);
    if (i < dir.size()) partial += dir[i];
  }
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
    throw InputError(dir + ": cannot create the output directory");
  }
}

std::string RenderOutput::directoryFor(const scene::Scene& scene, const std::string& cachePath) {
  if (!scene.render->directory.empty()) return scene.render->directory;
  if (cachePath.empty()) return "results/" + scene.name + "_frames";
  const std::size_t dot = cachePath.rfind('.');
  return io::siblingPath(dot == std::string::npos || cachePath.find('/', dot) != std::string::npos
                             ? cachePath
                             : cachePath.substr(0, dot),
                         "", "_frames");
}

std::unique_ptr<RenderOutput> RenderOutput::prepare(const scene::Scene& scene,
                                                    const solver::BoundaryParticles& boundary,
                                                    io::cache::CacheSession* cache) {
  if (!scene.render) return nullptr;
  const std::string dir = directoryFor(scene, cache ? cache->path() : "");
  makeDirectory(dir);
  return std::unique_ptr<RenderOutput>(new RenderOutput(scene, boundary, dir, cache));
}

RenderOutput::RenderOutput(const scene::Scene& scene, const solver::BoundaryParticles& boundary,
                           std::string directory, io::cache::CacheSession* cache)
    : context_(render::gl::GlContext::headless()),
      frame_(scene, *scene.render,
             [&] {
               return std::array<std::vector<float>, 3>{boundary.x, boundary.y, boundary.z};
             }),
      desc_(*scene.render),
      camera_(*scene.camera),
      cameraPath_(scene.cameraPath),
      name_(scene.name),
      directory_(std::move(directory)),
      cache_(cache) {}

void RenderOutput::frame(const run::Simulation& sim, std::size_t frame) {
  // The rain: the drops the cache stores (its session steps them at every output frame, before
  // this sink), else stepped here the same way, so `render` of the cache draws the same drops.
  // A feeding rain is the simulation's own (rain.feed_fluid).
  if (render::rain::SceneRain* rain = frame_.rain()) {
    if (sim.rainFeed())
      rain->show(sim.rainFeed()->stepper().system());
    else if (cache_ && cache_->rain())
      rain->show(cache_->rain()->system());
    else
      rain->advanceTo(sim.time(), sim.fluid());
  }
  if (frame % static_cast<std::size_t>(desc_.every) != 0) return;
  const scene::CameraDesc camera = cameraAt(camera_, cameraPath_, sim.time());
  for (const render::compose::Picture& p : frame_.draw(sim.fluid(), sim.time(), camera).pictures) {
    const char* kindName = scene::enumName(p.kind);
    const render::frame::RenderImage& image = p.splats.image;
    seconds_ += p.splats.timings.total();
    io::exports::writePng(
        directory_ + "/" + io::exports::framePngName(name_ + "_" + kindName, frame), image.width,
        image.height, image.rgb.data());
    if (cache_ && desc_.toCache)
      cache_->writeRenderedFrame(kindName, frame, image.width, image.height, image.rgb.data());
    ++images_;
  }
}

}  // namespace sph::job
