// Two ways to a faster particle-light frame, measured (docs/notes/2026-11-27-lights-fig11.md,
// "Frustum culling" and "Accumulating on the CPU"). A plain program printing tables, as
// bench_lights.
//   bench_lights_faster fig11      frustum culling (lights.cull) in Fig. 11's world
//                                  (bench/Fig11Scene.h), 262,144 and 1M lights, 960 x 540,
//                                  deferred, from its camera and three that see part of it: per
//                                  camera the accumulation of the whole volume against the culled
//                                  one, the share of lights and voxels kept, and the culled
//                                  picture against the unculled one (8-bit steps; should be 0)
//   bench_lights_faster fireflies  the same for scenes/fireflies.json at t = 0.2 s, its own camera
//                                  and a close one on the cup, 640 x 480, forward, no water
//   bench_lights_faster cpu        accumulate "cpu" against "atomic" in Fig. 11's world, 65,536
//                                  to 4M lights (--max-lights), and on the fireflies' frame; whole
//                                  volume: ms and the largest texel difference
//   bench_lights_faster frame      Fig. 11's whole deferred frame as a user gets it on llvmpipe
//                                  (accumulate "cpu", culled to the table's camera, 960 x 540) at
//                                  262,144 and 1M lights: accumulation (whole volume and culled),
//                                  G-buffer pass, each pixel's colour on the CPU (read-back,
//                                  shading, encoding, upload; lights.shade "cpu"), the copy into
//                                  the frame's target (a blit with "cpu", as nothing is drawn after
//                                  it; the lighting pass with "gl"), draw and frame (culled +
//                                  draw), each the minimum of --repeat frames, with CPU ms beside,
//                                  and the solids' triangles drawn. The frame ends with the picture
//                                  in the renderer's offscreen target, where `render` reads it
//                                  back from (the read-back is not in it)
//   bench_lights_faster cpuside    Fig. 11's frame's CPU work alone at 262,144 and 1M lights: the
//                                  culled CPU accumulation and the CPU shading of the frame's
//                                  G-buffer (read back once), each --repeat times in turn: min and
//                                  median ms, wall and CPU, and hashes of the sums' half floats
//                                  and of the shaded pixels (equal hashes, two builds: same bits)
// Options: --repeat N (min of N, default 3), --max-lights N (default 1048576), --accumulate cpu
// (fig11, fireflies: the CPU accumulation instead of the atomic one), --shade gl|cpu|auto (frame:
// lights.shade, default auto = cpu there), --pixels P (frame: the solids' tessellation bound,
// default 0.5 px), --png PREFIX (frame: the last picture of each count to PREFIX-<lights>.png).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench/Fig11Scene.h"
#include "io/exports/Png.h"
#include "io/scene/SceneLoader.h"
#include "job/OpenMpSpinLimit.h"
#include "render/gl/GlContext.h"
#include "render/lights/CpuShading.h"
#include "render/lights/LightCulling.h"
#include "render/lights/LightVolume.h"
#include "render/solids/SceneSolids.h"
#include "render/solids/SolidRenderer.h"
#include "render/splat/SplatRenderer.h"
#include "sim/Parallel.h"
#include "sim/lights/LightParticles.h"
#include "sim/scene/EnumNames.h"

using namespace sph;
using namespace sph::render::lights;

namespace {

int repeat = 3;
std::size_t maxLights = 1048576;
scene::LightAccumulate accumulate =
    scene::LightAccumulate::Atomic;                         // fig11, fireflies: --accumulate
scene::LightShade shade = scene::LightShade::Auto;          // frame: --shade
float pixels = render::solids::TessellationBound{}.pixels;  // frame: --pixels
std::string png;                                            // frame: --png

struct View {
  const char* name;
  scene::CameraDesc camera;
};

// The minimum seconds of `repeat` updates of each of two volumes, taken in turn (the machine's
// load changes while we measure: both see the same).
std::pair<double, double> pairedMin(LightVolume& a, const LightView* viewA, LightVolume& b,
                                    const LightView* viewB,
                                    const std::vector<sph::lights::LightParticle>& lights) {
  a.update(lights, viewA), b.update(lights, viewB);  // compile llvmpipe's variants, size buffers
  double ta = 1e30, tb = 1e30;
  for (int k = 0; k < repeat; ++k) {
    ta = std::min(ta, a.update(lights, viewA));
    tb = std::min(tb, b.update(lights, viewB));
  }
  return {ta, tb};
}

render::frame::RenderImage draw(render::splat::SplatRenderer& r, const scene::CameraDesc& camera,
                                const LightVolume& v) {
  render::frame::Lighting lighting;
  lighting.extra = &v;
  return r.render(render::splat::SplatFrame{}, render::splat::SplatKind::Point, camera, lighting);
}

// One table row per camera: the whole volume, then culled to the camera; both drawn.
void measure(const scene::LightsDesc& desc, const std::vector<sph::lights::LightParticle>& lights,
             render::solids::SolidRenderer& solids, int width, int height,
             const std::vector<View>& views) {
  render::splat::SplatRenderer renderer(width, height);
  renderer.setLayers({&solids});
  LightVolume all(desc), culled(desc);
  for (const View& v : views) {
    // The margin of the scene's default water splats (splat size 1.5, R 2.5 spacings) at a
    // spacing of a voxel: more than the solids alone need.
    const LightView lv = lightView(v.camera, static_cast<float>(width) / static_cast<float>(height),
                                   1.5f, 2.5f, desc.voxelSize);
    const auto [tAll, tCulled] = pairedMin(all, nullptr, culled, &lv, lights);
    draw(renderer, v.camera, all);  // compiles llvmpipe's variants
    double drawAll = 1e30, drawCulled = 1e30;
    render::frame::RenderImage a, c;
    for (int k = 0; k < repeat; ++k) {
      a = draw(renderer, v.camera, all);
      drawAll = std::min(drawAll, a.seconds);
      c = draw(renderer, v.camera, culled);
      drawCulled = std::min(drawCulled, c.seconds);
    }
    int worst = 0;
    std::size_t differing = 0, lit = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
      const int d = std::abs(int(a.rgb[i]) - int(c.rgb[i]));
      worst = std::max(worst, d), differing += d > 0, lit += a.rgb[i] > 0;
    }
    const VoxelBox& box = culled.lastBox();
    std::printf("%-8zu %-8s %10.1f %10.1f %6.2fx %9zu %6.1f%% %11zu %6.1f%% %9.1f %9.1f %5d %9zu\n",
                lights.size(), v.name, 1e3 * tAll, 1e3 * tCulled, tAll / tCulled,
                culled.lastLights(), 100.0 * culled.lastLights() / lights.size(), box.count(),
                100.0 * box.count() / desc.voxelCount(), 1e3 * drawAll, 1e3 * drawCulled, worst,
                differing);
    std::fflush(stdout);
    if (lit == 0) std::printf("  (the picture is black: nothing measured)\n");
  }
}

void header() {
  std::printf("%-8s %-8s %10s %10s %7s %9s %7s %11s %7s %9s %9s %5s %9s\n", "lights", "camera",
              "all ms", "culled ms", "speedup", "kept", "kept", "box voxels", "box", "draw all",
              "draw cull", "diff", "diff px");
}

void fig11() {
  render::solids::SolidRenderer solids(bench::fig11Solids(),
                                       Aabb{Vec3(0, -1, 0), Vec3(128, 128, 128)}, 0.5f);
  // From a corner across the world; from 40 m and 15 m above the middle, looking down.
  scene::CameraDesc corner = bench::fig11Camera(), above = bench::fig11Camera(), low = above;
  corner.position = Vec3(8, 10, 8), corner.target = Vec3(40, 2, 40);
  above.position = Vec3(64, 40, 70), above.target = Vec3(64, 0, 64);
  low.position = Vec3(64, 15, 70), low.target = Vec3(64, 0, 62);
  std::printf(
      "Fig. 11 world (128^3 voxels of 1 m, range 0.5 m, trilinear, deferred, %s; 960 x 540): ms "
      "per accumulation, min of %d\n",
      nameOf(accumulate), repeat);
  header();
  for (std::size_t n : {262144u, 1048576u}) {
    if (n > maxLights) continue;
    scene::LightsDesc d = bench::fig11Lights(n);
    d.pipeline = scene::LightPipeline::Deferred, d.accumulate = accumulate;
    measure(d, sph::lights::lightParticles(d, Particles{}, 0.0), solids, 960, 540,
            {{"fig11", bench::fig11Camera()}, {"corner", corner}, {"above", above}, {"low", low}});
  }
}

// The largest difference between two volumes' texels, relative to max(1, |value|), and how many
// texel channels differ by more than a half-float step (1e-3).
std::pair<float, std::size_t> texelDifference(const LightVolume& a, const LightVolume& b) {
  float worst = 0;
  std::size_t more = 0;
  for (const auto& [x, y] :
       {std::pair(a.readColour(), b.readColour()), std::pair(a.readDirection(), b.readDirection())})
    for (std::size_t i = 0; i < x.size(); ++i)
      for (std::size_t c = 0; c < 4; ++c) {
        const float d = std::abs(x[i][c] - y[i][c]) / std::max(1.0f, std::abs(x[i][c]));
        worst = std::max(worst, d), more += d > 1e-3f;
      }
  return {worst, more};
}

void cpu() {
  std::printf(
      "Fig. 11 world (128^3 voxels of 1 m, range 0.5 m): ms per accumulation (clear, lights, "
      "resolve or upload, glFinish), min of %d, %d OpenMP threads\n",
      repeat, threadCount());
  std::printf("%-9s %10s %10s %8s %14s %10s\n", "lights", "atomic ms", "cpu ms", "speedup",
              "max texel diff", "> 1e-3");
  for (std::size_t n : {65536u, 262144u, 1048576u, 4194304u}) {
    if (n > maxLights) continue;
    scene::LightsDesc d = bench::fig11Lights(n);
    const std::vector<sph::lights::LightParticle> lights =
        sph::lights::lightParticles(d, Particles{}, 0.0);
    LightVolume atomic(d);
    d.accumulate = scene::LightAccumulate::Cpu;
    LightVolume onCpu(d);
    const auto [ta, tc] = pairedMin(atomic, nullptr, onCpu, nullptr, lights);
    const auto [worst, more] = texelDifference(atomic, onCpu);
    std::printf("%-9zu %10.1f %10.1f %7.1fx %14.2e %10zu\n", n, 1e3 * ta, 1e3 * tc, ta / tc, worst,
                more);
    std::fflush(stdout);
  }
  // The fireflies' frame (range 2.5 voxels: the shader visits 7^3 voxels a light).
  const scene::Scene scene =
      io::scene::loadScene(std::string(SPHSPLAT_SOURCE_DIR) + "/scenes/fireflies.json");
  scene::LightsDesc d = *scene.lights;
  const std::vector<sph::lights::LightParticle> lights =
      sph::lights::lightParticles(d, Particles{}, 0.2, sph::lights::lightSolids(scene));
  LightVolume atomic(d);
  d.accumulate = scene::LightAccumulate::Cpu;
  LightVolume onCpu(d);
  const auto [ta, tc] = pairedMin(atomic, nullptr, onCpu, nullptr, lights);
  const auto [worst, more] = texelDifference(atomic, onCpu);
  std::printf("%-9zu %10.1f %10.1f %7.1fx %14.2e %10zu  scenes/fireflies.json, t = 0.2 s\n",
              lights.size(), 1e3 * ta, 1e3 * tc, ta / tc, worst, more);
}

// CPU seconds of this process so far, every thread (OpenMP's and llvmpipe's) included: on a
// machine shared with other work its differences move less than the wall clock's.
double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Fig. 11's world through its camera at 960 x 540, the solids its one layer (frame, cpuside).
struct Fig11View {
  static constexpr int kWidth = 960, kHeight = 540;
  render::solids::SolidRenderer solids{bench::fig11Solids(),
                                       Aabb{Vec3(0, -1, 0), Vec3(128, 128, 128)}, 0.5f};
  render::splat::SplatRenderer renderer{kWidth, kHeight};
  const scene::CameraDesc camera = bench::fig11Camera();
  Fig11View() { renderer.setLayers({&solids}); }
};

// Fig. 11's frame: the accumulation (whole volume and culled, taken in turn), then the deferred
// draw, per frame; each figure its minimum over `repeat` frames, in wall-clock ms and in CPU ms
// (all threads: up to twice the wall clock on two cores). The frame is the culled accumulation
// and the draw: what the defaults (lights.cull on, "auto" = "cpu" on llvmpipe) give.
void frame() {
  Fig11View world;
  world.solids.tessellation.pixels = pixels;
  render::splat::SplatRenderer& renderer = world.renderer;
  const int width = Fig11View::kWidth, height = Fig11View::kHeight;
  const scene::CameraDesc& camera = world.camera;
  std::printf(
      "Fig. 11 frame (128^3 voxels of 1 m, range 0.5 m, trilinear, deferred, accumulate cpu, "
      "shade %s; %d x %d; solids tessellated for their size on screen, %g px): ms, min of %d "
      "frames; [CPU ms, all threads]; triangles drawn\n",
      nameOf(shade), width, height, static_cast<double>(pixels), repeat);
  std::printf("%-8s %9s %9s %9s %9s %9s %9s %9s %9s %9s %9s\n", "lights", "acc all", "acc cull",
              "G-buffer", "cpu shade", "copy", "draw", "frame", "[acc cul]", "[draw]", "triangles");
  for (std::size_t n : {262144u, 1048576u}) {
    if (n > maxLights) continue;
    scene::LightsDesc d = bench::fig11Lights(n);
    d.pipeline = scene::LightPipeline::Deferred, d.accumulate = scene::LightAccumulate::Cpu,
    d.shade = shade;
    const std::vector<sph::lights::LightParticle> lights =
        sph::lights::lightParticles(d, Particles{}, 0.0);
    const LightView view = lightView(camera, static_cast<float>(width) / static_cast<float>(height),
                                     1.5f, 2.5f, d.voxelSize);
    LightVolume all(d), culled(d);
    all.update(lights), culled.update(lights, &view);  // sizes the buffers
    draw(renderer, camera, culled);                    // compiles llvmpipe's variants
    double tAll = 1e30, tCulled = 1e30, gbuffer = 1e30, particles = 1e30, lighting = 1e30,
           drawn = 1e30;
    double cpuCulled = 1e30, cpuDraw = 1e30;
    render::frame::RenderImage last;
    for (int k = 0; k < repeat; ++k) {
      tAll = std::min(tAll, all.update(lights));
      const double c0 = cpuSeconds();
      tCulled = std::min(tCulled, culled.update(lights, &view));
      const double c1 = cpuSeconds();
      render::frame::RenderImage image = draw(renderer, camera, culled);
      const double c2 = cpuSeconds();
      cpuCulled = std::min(cpuCulled, c1 - c0), cpuDraw = std::min(cpuDraw, c2 - c1);
      drawn = std::min(drawn, image.seconds);
      gbuffer = std::min(gbuffer, renderer.lastPasses().gbuffer);
      particles = std::min(particles, renderer.lastPasses().particles);
      lighting = std::min(lighting, renderer.lastPasses().lighting);
      last = std::move(image);
    }
    if (!png.empty())
      io::exports::writePng(png + "-" + std::to_string(n) + ".png", last.width, last.height,
                            last.rgb.data());
    std::printf("%-8zu %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %9.1f %9zu\n", n, 1e3 * tAll,
                1e3 * tCulled, 1e3 * gbuffer, 1e3 * particles, 1e3 * lighting, 1e3 * drawn,
                1e3 * (tCulled + drawn), 1e3 * cpuCulled, 1e3 * cpuDraw, world.solids.triangles());
    std::fflush(stdout);
  }
}

void fireflies() {
  const scene::Scene scene =
      io::scene::loadScene(std::string(SPHSPLAT_SOURCE_DIR) + "/scenes/fireflies.json");
  scene::LightsDesc d = *scene.lights;
  d.accumulate = accumulate;
  const std::vector<sph::lights::LightParticle> lights =
      sph::lights::lightParticles(d, Particles{}, 0.2, sph::lights::lightSolids(scene));
  const std::unique_ptr<render::solids::SolidRenderer> solids = render::solids::sceneSolids(scene);
  scene::CameraDesc cup = *scene.camera;
  cup.position = Vec3(0.62f, 0.3f, 0.05f), cup.target = Vec3(0.35f, 0.07f, -0.25f);
  std::printf(
      "scenes/fireflies.json at t = 0.2 s (%d x %d x %d voxels of %g m, range %g m, %s, %s, %s; "
      "640 x 480, no water): ms per accumulation, min of %d\n",
      d.voxels[0], d.voxels[1], d.voxels[2], d.voxelSize, d.range, nameOf(d.filter),
      nameOf(d.pipeline), nameOf(d.accumulate), repeat);
  header();
  measure(d, lights, *solids, scene.render ? scene.render->width : 640,
          scene.render ? scene.render->height : 480, {{"scene", *scene.camera}, {"cup", cup}});
}

// The frame's volume, with a copy of the G-buffer the CPU shading reads (cpuside).
class GBufferCopy final : public render::frame::ExtraLights {
 public:
  explicit GBufferCopy(const LightVolume& v) : volume_(v) {}
  void apply(GLuint program) const override { volume_.apply(program); }
  bool deferred() const override { return volume_.deferred(); }
  bool shadesOnCpu() const override { return volume_.shadesOnCpu(); }
  void shadeOnCpu(const render::frame::GBufferPixels& g, const Vec3& from,
                  std::uint8_t* rgba) const override {
    const std::size_t n = g.count();
    depth.assign(g.depth, g.depth + n), normal.assign(g.normal, g.normal + 4 * n);
    lit.assign(g.lit, g.lit + 4 * n), albedo.assign(g.albedo, g.albedo + 4 * n);
    if (g.position) position.assign(g.position, g.position + 4 * n);
    pixels = g, eye = from;
    pixels.depth = depth.data(), pixels.normal = normal.data(), pixels.lit = lit.data();
    pixels.albedo = albedo.data(), pixels.position = g.position ? position.data() : nullptr;
    volume_.shadeOnCpu(g, from, rgba);
  }
  mutable render::frame::GBufferPixels pixels;
  mutable Vec3 eye = Vec3::Zero();

 private:
  const LightVolume& volume_;
  mutable std::vector<float> depth, normal, lit, position;
  mutable std::vector<std::uint16_t> albedo;
};

// FNV-1a of n bytes.
std::uint64_t hashOf(const void* data, std::size_t n, std::uint64_t h = 14695981039346656037ull) {
  const auto* c = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 1099511628211ull;
  return h;
}

void cpuSide() {
  Fig11View world;
  std::printf(
      "Fig. 11's CPU side (128^3 voxels, culled, trilinear, %d x %d): ms, min / median "
      "of %d; [CPU ms]; FNV-1a of the sums' halves and of the pixels\n",
      Fig11View::kWidth, Fig11View::kHeight, repeat);
  std::printf("%-8s %9s %17s %17s %17s %17s %17s %17s\n", "lights", "kept", "accumulate",
              "[accumulate]", "shade", "[shade]", "sums hash", "pixels hash");
  for (std::size_t n : {262144u, 1048576u}) {
    if (n > maxLights) continue;
    scene::LightsDesc d = bench::fig11Lights(n);
    d.pipeline = scene::LightPipeline::Deferred, d.accumulate = scene::LightAccumulate::Cpu;
    d.shade = scene::LightShade::Cpu;
    const std::vector<sph::lights::LightParticle> lights =
        sph::lights::lightParticles(d, Particles{}, 0.0);
    const LightView view =
        lightView(world.camera, static_cast<float>(Fig11View::kWidth) / Fig11View::kHeight, 1.5f,
                  2.5f, d.voxelSize);
    LightVolume volume(d);
    volume.update(lights, &view);
    GBufferCopy frame(volume);
    render::frame::Lighting lighting;
    lighting.extra = &frame;
    world.renderer.render(render::splat::SplatFrame{}, render::splat::SplatKind::Point,
                          world.camera, lighting);
    const VoxelBox box = viewVoxels(d, view);
    const ViewCull cull(d, view, box);
    VoxelSums sums;
    std::vector<std::uint8_t> rgba(4 * frame.pixels.count());
    std::vector<double> times[4];  // accumulate wall, CPU; shade wall, CPU
    for (int k = 0; k < repeat; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = cpuSeconds();
      accumulateOnCpu(d, lights, box, fixedScale(d), &cull, sums);
      const auto t1 = std::chrono::steady_clock::now();
      const double c1 = cpuSeconds();
      CpuShading(d, sums, volume.terms).pixels(frame.pixels, frame.eye, rgba.data());
      const auto t2 = std::chrono::steady_clock::now();
      times[0].push_back(std::chrono::duration<double>(t1 - t0).count());
      times[1].push_back(c1 - c0);
      times[2].push_back(std::chrono::duration<double>(t2 - t1).count());
      times[3].push_back(cpuSeconds() - c1);
    }
    char cell[4][32];
    for (int c = 0; c < 4; ++c) {
      std::vector<double>& t = times[c];
      std::sort(t.begin(), t.end());
      std::snprintf(cell[c], sizeof cell[c], "%.1f / %.1f", 1e3 * t.front(), 1e3 * t[t.size() / 2]);
    }
    std::uint64_t h = hashOf(sums.colour.data(), sums.colour.size() * sizeof sums.colour[0]);
    h = hashOf(sums.direction.data(), sums.direction.size() * sizeof sums.direction[0], h);
    std::printf("%-8zu %9zu %17s %17s %17s %17s  %016llx  %016llx\n", n, sums.lights, cell[0],
                cell[1], cell[2], cell[3], static_cast<unsigned long long>(h),
                static_cast<unsigned long long>(hashOf(rgba.data(), rgba.size())));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  job::relaunchWithOpenMpSpinLimit(argv);
  const std::string what = argc > 1 ? argv[1] : "";
  for (int i = 2; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--max-lights")) maxLights = std::strtoull(argv[i + 1], nullptr, 10);
    if (!std::strcmp(argv[i], "--repeat")) repeat = std::max(1, std::atoi(argv[i + 1]));
    if (!std::strcmp(argv[i], "--accumulate") && !std::strcmp(argv[i + 1], "cpu"))
      accumulate = scene::LightAccumulate::Cpu;
    if (!std::strcmp(argv[i], "--pixels")) pixels = std::strtof(argv[i + 1], nullptr);
    if (!std::strcmp(argv[i], "--png")) png = argv[i + 1];
    if (!std::strcmp(argv[i], "--shade")) {
      const std::optional<scene::LightShade> s = scene::parseEnum<scene::LightShade>(argv[i + 1]);
      if (!s) {
        std::fprintf(stderr, "--shade: expected gl, cpu or auto, got %s\n", argv[i + 1]);
        return 2;
      }
      shade = *s;
    }
  }
  if (what != "fig11" && what != "fireflies" && what != "cpu" && what != "frame" &&
      what != "cpuside") {
    std::fprintf(stderr,
                 "usage: bench_lights_faster fig11|fireflies|cpu|frame|cpuside [--repeat N] "
                 "[--max-lights N] [--accumulate cpu] [--shade gl|cpu|auto] [--pixels P] "
                 "[--png PREFIX]\n");
    return 2;
  }
  render::gl::GlContext context = render::gl::GlContext::headless();
  std::printf("GL: %s\n", context.info().renderer.c_str());
  if (what == "fig11") fig11();
  if (what == "fireflies") fireflies();
  if (what == "cpu") cpu();
  if (what == "frame") frame();
  if (what == "cpuside") cpuSide();
  return 0;
}
