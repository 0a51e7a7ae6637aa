// The visible fraction of a run's stored drops (docs/notes/2026-11-29-rain-visible-budget.md): for
// each frame of a cache written by `sphsplat run` of a scene with rain, the share of the frame's
// drops (/Rain#N) that the eye sees, from the geometry (tests/RainSight.h): the scene's solids and
// the frame's own simulated water, each particle a sphere of one spacing. Prints CSV: frame, time,
// the share seen, the share in the frustum; then the least and the mean.
//   rain_sight_cache scenes/rain_pour.json run.h5 [KEY=VALUE ...]   (the run's --set overrides)
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "io/cache/CacheReader.h"
#include "io/cache/RainCache.h"
#include "io/scene/SceneLoader.h"
#include "sim/rain/RainStepper.h"
#include "sim/scene/Camera.h"
#include "tests/RainSight.h"

int main(int argc, char** argv) {
  using namespace sph;
  if (argc < 3) {
    std::fprintf(stderr, "usage: rain_sight_cache SCENE CACHE [KEY=VALUE ...]\n");
    return 2;
  }
  const scene::Scene scene =
      io::scene::loadScene(argv[1], std::vector<std::string>(argv + 3, argv + argc));
  if (!scene.rain || !scene.camera) {
    std::fprintf(stderr, "%s: no rain or no camera\n", argv[1]);
    return 2;
  }
  std::vector<scene::Solid> solids;
  for (const scene::BoundaryShape& b : scene.boundaries)
    solids.emplace_back(b, scene.solver.wallThickness());
  const float aspect = rain::RainStepper::sceneAspect(scene);
  const io::cache::CacheReader reader(argv[2]);
  double least = 1, mean = 0;
  std::printf("frame,time,visible,in_view\n");
  for (std::size_t k = 0; k < reader.frameCount(); ++k) {
    const io::cache::RainFrame drops = io::cache::readRainFrame(reader, k);
    const Particles fluid = reader.readFrame(k);
    std::vector<Vec3> water;
    for (std::size_t i = 0; i < fluid.size(); ++i)
      water.emplace_back(fluid.x[i], fluid.y[i], fluid.z[i]);
    const test::EyeSight sight(solids, water, scene.solver.spacing);
    const scene::CameraDesc c = scene::cameraAt(*scene.camera, scene.cameraPath, drops.time);
    const double seen = test::visibleFraction(sight, c.position, drops.positions);
    const double inView =
        test::inViewFraction(drops.positions, c, aspect, scene.rain->near, scene.rain->far);
    std::printf("%zu,%.4f,%.4f,%.4f\n", k, drops.time, seen, inView);
    least = std::min(least, seen), mean += seen / static_cast<double>(reader.frameCount());
  }
  std::printf("# least %.4f, mean %.4f over %zu frames\n", least, mean, reader.frameCount());
  return 0;
}
