#include "bench/collision/Snapshot.h"

#include <cstdio>

#include "io/scene/SceneLoader.h"
#include "render/cdt/CollisionSetup.h"

namespace sph::collisionbench {

scene::Scene rainScene(char density, std::size_t n, std::vector<std::string> overrides) {
  const bool a = density == 'A';
  const double spacing = a ? 0.012 : 0.024;
  const double top = 0.75 + static_cast<double>(n / 2500) * spacing;
  char edit[96];
  std::snprintf(edit, sizeof edit, "fluids[0].max=[%g,%.4f,%g]", a ? 0.3 : 0.6, top, a ? 0.3 : 0.6);
  overrides.insert(overrides.begin(), edit);
  return io::scene::loadScene(std::string(SPHSPLAT_SOURCE_DIR) +
                                  (a ? "/scenes/cdt_rain.json" : "/scenes/cdt_rain_sparse.json"),
                              overrides);
}

Snapshot takeSnapshot(char density, std::size_t n, double warm) {
  Snapshot s{density, n, rainScene(density, n), {}, {}};
  scene::Scene scene = s.scene;
  scene.collision->method = scene::CollisionMethod::Exact;
  run::Simulation sim(scene);
  sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
  sim.advanceTo(warm);
  s.state = sim.runState();
  s.particles = sim.fluid();
  return s;
}

}  // namespace sph::collisionbench
