#include "bench/collision/Timing.h"

#include <glad/gl.h>

#include <algorithm>
#include <cstdio>

#include "render/cdt/CdtGl.h"
#include "render/cdt/CollisionSetup.h"
#include "render/gl/GlContext.h"
#include "sim/run/Simulation.h"
#include "sim/cdt/CdtCpu.h"

namespace sph::collisionbench {

double millisecondsSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

Timing summarise(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  return {ms.front(), ms[ms.size() / 2]};
}

std::string format(const Timing& t, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f / %.*f", decimals, t.minMs, decimals, t.medianMs);
  return text;
}

double loadAverage() {
  double load = 0;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = 0;
    std::fclose(f);
  }
  return load;
}

Timing timeMethod(const Snapshot& snap, scene::CollisionMethod method, int steps,
                  const std::vector<std::string>& overrides) {
  scene::Scene scene = overrides.empty() ? snap.scene : rainScene(snap.density, snap.n, overrides);
  scene.collision->method = method;
  run::Simulation sim(scene);
  sim.setCollisionPass(render::cdt::makeCollisionPass(scene));
  sim.restore(snap.state, snap.particles);
  sim.step();
  std::vector<double> ms;
  for (int s = 0; s < steps; ++s) {
    const double before = sim.profile()[solver::Pass::Collide];
    sim.step();
    ms.push_back(1e3 * (sim.profile()[solver::Pass::Collide] - before));
  }
  return summarise(ms);
}

Timing timeGlResident(const Snapshot& snap, int steps, bool rasterWrite) {
  render::gl::GlContext context = render::gl::GlContext::headless();
  scene::CollisionDesc desc = *snap.scene.collision;
  desc.textureWrite = rasterWrite ? scene::CdtTextureWrite::Raster : scene::CdtTextureWrite::Atomic;
  render::cdt::CdtGl gl(cdt::makeSettings(desc, snap.scene.camera));
  gl.upload(snap.particles);
  const float dt = snap.scene.solver.maxTimeStep;
  gl.step(dt, true);
  glFinish();
  std::vector<double> ms;
  for (int s = 0; s < steps; ++s) {
    const auto start = Clock::now();
    gl.step(dt, true);
    glFinish();
    ms.push_back(millisecondsSince(start));
  }
  return summarise(ms);
}
}  // namespace sph::collisionbench
