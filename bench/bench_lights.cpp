// Seed 004's measurements on this machine (docs/benchmarks.md, "Particle lights"): a plain
// program printing tables, not a Google Benchmark (each figure needs a warmed-up GL volume and the
// error figures an exact reference).
//   bench_lights accumulate   Table 1 / Table 2: ms to clear + accumulate (+ resolve) the volume
//                             vs light count, volume size and range; atomic vs paper
//   bench_lights table1       Table 1 alone (the counts up to --max-lights)
//   bench_lights loss         what the paper's unsynchronised accumulation loses, per count
//   bench_lights filters      time and error of every filter x oversampling x voxel size
//                             against the exact sum, on a grid of surface points
//   bench_lights pipelines    Fig. 11: ms per frame, forward vs deferred, vs light count, with
//                             the breakdown (accumulate, draw or G-buffer, lighting pass)
//   bench_lights solids       the solids' draw in a scene without lights (the cost of the
//                             particle lights' code compiled into their shader)
// Options: --max-lights N (default 1048576), --repeat N (min of N, default 3), --ppm PREFIX
// (pipelines: each frame as a picture).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "job/OpenMpSpinLimit.h"
#include "bench/Fig11Scene.h"
#include "render/gl/GlContext.h"
#include "render/lights/ExactLights.h"
#include "render/lights/LightVolume.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/lights/LightParticles.h"
#include "sim/scene/Camera.h"

using namespace sph;
using namespace sph::render::lights;

namespace {

int repeat = 3;
std::size_t maxLights = 1048576;
std::string ppm;  // pipelines: write each frame to PREFIX_N_PIPELINE.ppm

// Lights uniform in a cube of `side` m from the origin, white, intensity 1.
std::vector<sph::lights::LightParticle> uniformLights(std::size_t n, float side, unsigned seed) {
  scene::LightEmitterDesc e;
  e.box.lo = Vec3::Zero(), e.box.hi = Vec3::Constant(side);
  e.count = n, e.seed = seed, e.speed = 0;
  scene::LightsDesc d;
  d.source = scene::LightSource::Emitter, d.emitter = e, d.colour = Vec3::Ones();
  return sph::lights::lightParticles(d, Particles{}, 0.0);
}

// The paper's world: 1 m voxels over N^3 m, attenuation range `range` m.
scene::LightsDesc paperVolume(int n, float range, scene::LightAccumulate mode) {
  scene::LightsDesc d;
  d.origin = Vec3::Zero(), d.voxelSize = 1.0f, d.voxels = {n, n, n};
  d.range = range, d.attenuation = {1.0f, 0.0f, 1.0f};
  d.accumulate = mode;
  return d;
}

double minUpdate(LightVolume& v, const std::vector<sph::lights::LightParticle>& lights) {
  v.update(lights);  // compiles llvmpipe's variants, sizes the buffer
  double best = 1e30;
  for (int k = 0; k < repeat; ++k) best = std::min(best, v.update(lights));
  return best;
}

std::vector<std::size_t> counts() {
  std::vector<std::size_t> c;
  for (std::size_t n : {65536u, 262144u, 524288u, 1048576u, 4194304u})
    if (n <= maxLights) c.push_back(n);
  return c;
}

void table1() {
  std::printf(
      "Table 1 (range 0.5 m, 1 m voxels): ms per accumulation (clear + lights + resolve)\n");
  std::printf("%-10s %-7s", "volume", "mode");
  for (std::size_t n : counts()) std::printf(" %10zu", n);
  std::printf("\n");
  // 512^3 with the GL accumulations would hold 5 GiB of textures and sums (over the loader's
  // lights.max_memory_mib); `"cpu"` keeps only the two RGBA16F textures (2 GiB) and the half
  // floats of the box the lights reach in main memory.
  for (int n : {128, 256, 512}) {
    const std::vector<scene::LightAccumulate> modes =
        n < 512 ? std::vector<scene::LightAccumulate>{scene::LightAccumulate::Atomic,
                                                      scene::LightAccumulate::Paper}
                : std::vector<scene::LightAccumulate>{scene::LightAccumulate::Cpu};
    for (scene::LightAccumulate mode : modes) {
      LightVolume v(paperVolume(n, 0.5f, mode));
      std::printf("%-10s %-7s", (std::to_string(n) + "^3").c_str(), nameOf(mode));
      for (std::size_t c : counts()) {
        std::printf(" %10.1f", 1e3 * minUpdate(v, uniformLights(c, static_cast<float>(n), 1)));
        std::fflush(stdout);
      }
      std::printf("\n");
    }
  }
}

void table2() {
  std::printf("\nTable 2 (128^3, 1 m voxels): ms per accumulation vs range, atomic\n");
  std::printf("%-10s", "range");
  for (std::size_t n : counts()) std::printf(" %10zu", n);
  std::printf("\n");
  for (float range : {0.5f, 1.0f, 2.0f}) {
    LightVolume v(paperVolume(128, range, scene::LightAccumulate::Atomic));
    std::printf("%-10.1f", range);
    for (std::size_t c : counts()) {
      std::printf(" %10.1f", 1e3 * minUpdate(v, uniformLights(c, 128, 1)));
      std::fflush(stdout);
    }
    std::printf("\n");
  }
}

void loss() {
  std::printf(
      "Light lost by the paper's imageLoad/imageStore vs atomic (128^3, 1 m voxels, range 2 "
      "m; lights in a 16 m cube, then the whole 128 m)\n");
  std::printf("%-10s %-8s %14s %14s %10s %10s %10s\n", "lights", "cube m", "atomic sum",
              "paper sum", "lost %", "atomic ms", "paper ms");
  for (float side : {16.0f, 128.0f}) {
    for (std::size_t n : {16384u, 65536u, 262144u, 1048576u}) {
      if (n > maxLights) continue;
      const auto lights = uniformLights(n, side, 2);
      double sum[2], ms[2];
      int k = 0;
      for (scene::LightAccumulate mode :
           {scene::LightAccumulate::Atomic, scene::LightAccumulate::Paper}) {
        LightVolume v(paperVolume(128, 2.0f, mode));
        ms[k] = 1e3 * minUpdate(v, lights);
        double s = 0;
        for (const auto& t : v.readColour()) s += t[0];
        sum[k++] = s;
      }
      std::printf("%-10zu %-8.0f %14.1f %14.1f %10.2f %10.1f %10.1f\n", n, side, sum[0], sum[1],
                  100 * (1 - sum[1] / sum[0]), ms[0], ms[1]);
      std::fflush(stdout);
    }
  }
}

void filters() {
  // A 4 m x 4 m floor (y = 0) under 4096 lights in the 4 m cube above it, seen from above at
  // 45 degrees; 256 x 256 surface points.
  const float side = 4.0f;
  std::vector<sph::lights::LightParticle> lights = uniformLights(4096, side, 3);
  std::vector<ProbePoint> points;
  const Vec3 eye(2, 6, 8);
  for (int j = 0; j < 256; ++j)
    for (int i = 0; i < 256; ++i) {
      ProbePoint p;
      p.position = Vec3((i + 0.5f) / 256 * side, 0.01f, (j + 0.5f) / 256 * side);
      p.normal = Vec3::UnitY();
      p.toEye = (eye - p.position).normalized();
      points.push_back(p);
    }
  const Vec3 base(0.8f, 0.8f, 0.8f);
  std::printf(
      "Filters against the exact sum: 4096 lights (range 0.5 m, attenuation [1, 0, 8]) "
      "over a 4 m floor, 65,536 points\n");
  std::printf("%-8s %-22s %9s | %8s %9s | %8s %9s | %8s %9s\n", "voxel m", "filter", "ms",
              "PSNR dB", "mean abs", "diff dB", "diff abs", "spec dB", "spec abs");
  scene::LightsDesc d;
  d.range = 0.5f, d.attenuation = {1.0f, 0.0f, 8.0f}, d.specular = 0.5f, d.shininess = 16;
  std::vector<Vec3> exactT, exactD, exactS;
  {
    const ExactLights exact(d, lights);
    const auto start = std::chrono::steady_clock::now();
    for (const ProbePoint& p : points) {
      const LightTerms t = exact.at(p.position, p.normal, p.toEye, base);
      exactD.push_back(t.diffuse), exactS.push_back(t.specular),
          exactT.push_back(t.diffuse + t.specular);
    }
    std::printf(
        "%-8s %-22s %9.1f |   (CPU, one thread, particle grid)\n", "-", "exact",
        1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  for (float h : {0.25f, 0.125f, 0.0625f}) {
    d.voxelSize = h;
    const int n = static_cast<int>(side / h) + 2;
    d.origin = Vec3::Constant(-h);
    d.voxels = {n, n, n};
    LightVolume v(d);
    v.update(lights);
    struct S {
      scene::LightFilter f;
      float t;
      int o;
    };
    for (S s : {S{scene::LightFilter::Nearest, 0, 1}, S{scene::LightFilter::Nearest, 0, 2},
                S{scene::LightFilter::Trilinear, 0, 1}, S{scene::LightFilter::Trilinear, 0, 2},
                S{scene::LightFilter::Tricubic, 0, 1}, S{scene::LightFilter::Tricubic, 1, 1},
                S{scene::LightFilter::Tricubic, 0, 2}, S{scene::LightFilter::Tricubic, 1, 2}}) {
      v.setFilter(s.f, s.t, s.o);
      v.terms = 3;
      v.probe(points, base);
      double best = 1e30;
      std::vector<Vec3> total;
      for (int k = 0; k < repeat; ++k) {
        const auto start = std::chrono::steady_clock::now();
        total = v.probe(points, base);
        best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      v.terms = 1;
      const auto diffuse = v.probe(points, base);
      v.terms = 2;
      const auto specular = v.probe(points, base);
      const LightError et = lightError(total, exactT), ed = lightError(diffuse, exactD),
                       es = lightError(specular, exactS);
      char name[64];
      std::snprintf(name, sizeof name, "%s%s%s", nameOf(s.f),
                    s.f == scene::LightFilter::Tricubic ? (s.t > 0 ? " t1" : " t0") : "",
                    s.o > 1 ? " x8" : "");
      std::printf("%-8.4g %-22s %9.1f | %8.2f %9.5f | %8.2f %9.5f | %8.2f %9.5f\n", h, name,
                  1e3 * best, et.psnr, et.meanAbs, ed.psnr, ed.meanAbs, es.psnr, es.meanAbs);
      std::fflush(stdout);
    }
  }
}

// Fig. 11 (bench/Fig11Scene.h) at 960 x 540 pixels. Per pipeline: the accumulation (the same for
// both), the draw (forward: the solids lit per fragment; deferred: G-buffer, then the lighting
// pass).
using bench::fig11Camera;
using bench::fig11Solids;

// The cost of the particle lights' code in the solids' fragment shader in a scene without
// lights: the Fig. 11 solids drawn with no volume (the program the build gives a scene without
// `lights`), ms per draw, min of `repeat`.
void solidsWithoutLights() {
  render::solids::SolidRenderer solids(fig11Solids(), Aabb{Vec3(0, -1, 0), Vec3(128, 128, 128)},
                                       0.5f);
  render::splat::SplatRenderer renderer(960, 540);
  renderer.setLayers({&solids});
  render::frame::Lighting lighting;
  double best = 1e30;
  for (int k = 0; k <= repeat; ++k) {
    const double t = renderer
                         .render(render::splat::SplatFrame{}, render::splat::SplatKind::Point,
                                 fig11Camera(), lighting)
                         .seconds;
    if (k > 0) best = std::min(best, t);  // the first compiles llvmpipe's variants
  }
  std::printf("solids without lights (%zu triangles, 960 x 540): %.2f ms per draw, min of %d\n",
              solids.triangles(), 1e3 * best, repeat);
}

void pipelines() {
  render::gl::ShaderLibrary shaders = render::gl::ShaderLibrary::fromEnvironment();
  render::solids::SolidRenderer solids(fig11Solids(), Aabb{Vec3(0, -1, 0), Vec3(128, 128, 128)},
                                       0.5f, shaders);
  const int width = 960, height = 540;
  render::splat::SplatRenderer renderer(width, height, shaders);
  renderer.setLayers({&solids});
  const scene::CameraDesc camera = fig11Camera();
  // No solid triangle count here: the solids are tessellated for the screen at their first draw
  // (render/solids/ScreenTessellation.h), so SolidRenderer::triangles() is 0 until then.
  std::printf(
      "Fig. 11 (128^3, 1 m voxels, range 0.5 m, trilinear; %d x %d): ms per frame, min of %d\n",
      width, height, repeat);
  std::printf("%-10s %-9s %10s %10s %10s %10s %10s %9s\n", "lights", "pipeline", "accumulate",
              "draw", "G-buffer", "lighting", "frame", "max diff");
  for (std::size_t n : {16384u, 65536u, 262144u, 1048576u}) {
    if (n > maxLights) continue;
    scene::LightsDesc d = bench::fig11Lights(n);
    const std::vector<sph::lights::LightParticle> lights =
        sph::lights::lightParticles(d, Particles{}, 0.0);
    LightVolume forward(d, shaders);
    const double accumulate = minUpdate(forward, lights);
    d.pipeline = scene::LightPipeline::Deferred;
    LightVolume deferred(d, shaders);
    deferred.update(lights);
    std::vector<std::uint8_t> first;
    for (const LightVolume* v : {&forward, &deferred}) {
      render::frame::Lighting lighting;
      lighting.extra = v;
      renderer.render(render::splat::SplatFrame{}, render::splat::SplatKind::Point, camera,
                      lighting);  // compiles llvmpipe's variants
      double draw = 1e30, gbuffer = 0, lit = 0;
      render::frame::RenderImage image;
      for (int k = 0; k < repeat; ++k) {
        image = renderer.render(render::splat::SplatFrame{}, render::splat::SplatKind::Point,
                                camera, lighting);
        if (image.seconds < draw) {
          draw = image.seconds;
          gbuffer = renderer.lastPasses().gbuffer, lit = renderer.lastPasses().lighting;
        }
      }
      // The deferred frame against the forward one (8-bit steps): the same picture.
      int diff = 0;
      if (first.empty()) first = image.rgb;
      for (std::size_t i = 0; i < first.size(); ++i)
        diff = std::max(diff, std::abs(int(first[i]) - int(image.rgb[i])));
      if (!ppm.empty()) {  // to look at
        const std::string path =
            ppm + "_" + std::to_string(n) + "_" + nameOf(v->desc().pipeline) + ".ppm";
        if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
          std::fprintf(f, "P6 %d %d 255\n", width, height);
          std::fwrite(image.rgb.data(), 1, image.rgb.size(), f);
          std::fclose(f);
        }
      }
      std::printf("%-10zu %-9s %10.1f %10.1f %10.1f %10.1f %10.1f %9d\n", n,
                  nameOf(v->desc().pipeline), 1e3 * accumulate, 1e3 * draw, 1e3 * gbuffer,
                  1e3 * lit, 1e3 * (accumulate + draw), diff);
      std::fflush(stdout);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  job::relaunchWithOpenMpSpinLimit(argv);
  std::string what = argc > 1 ? argv[1] : "";
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--max-lights")) maxLights = std::strtoull(argv[i + 1], nullptr, 10);
    if (!std::strcmp(argv[i], "--repeat")) repeat = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--ppm")) ppm = argv[i + 1];
  }
  if (what != "accumulate" && what != "table1" && what != "loss" && what != "filters" &&
      what != "pipelines" && what != "solids") {
    std::fprintf(stderr,
                 "usage: bench_lights accumulate|table1|loss|filters|pipelines|solids "
                 "[--max-lights N] [--repeat "
                 "N] [--ppm PREFIX]\n");
    return 2;
  }
  render::gl::GlContext context = render::gl::GlContext::headless();
  std::printf("GL: %s\n", context.info().renderer.c_str());
  if (what == "accumulate" || what == "table1") table1();
  if (what == "accumulate") table2();
  if (what == "loss") loss();
  if (what == "filters") filters();
  if (what == "pipelines") pipelines();
  if (what == "solids") solidsWithoutLights();
  return 0;
}
