// How close each way of drawing the rain (rain.lod_width, rain.far_tier; docs/rain.md, "The
// default: the sums at lod_width 8") comes to the streaks' true picture, not only to the exact
// streaks: the exact streaks drawn at `scale` times the resolution and box-filtered down
// (tests/RainTruth.h). The frame is bench_rain's (bench/RainBenchScenes.h: 960 x 540, the camera
// at (0, 1, 4) looking along -z, `view` rain 0.1..5 m reset there, no solids), over the
// renderer's background (render/frame/Lighting.h) with its unlit drop colour
// (render/rain/RainRenderer.h).
//
// Prints CSV, per drop count and way of drawing: the PSNR of its 8-bit frame against the
// reference (all pixels, and of 4x4-pixel means), against the exact streaks at 1x, and its light
// over the reference's. With `--crops DIR`: DIR/truth_<drops>_crops.png, a 160 x 90 crop of the
// frame's centre from the reference (top left), the exact streaks (top right), the sums at
// lod_width 8 (bottom left) and the lines at 1 (bottom right), each enlarged 3x. `--spotlight`:
// bench_rain's red cone (RainDraw/.../1) lights part of the rain. `--sorted`: the reference
// draws the drops farthest first, as light through them composes; the ways draw them as the run
// has them, in no order of depth (the exact path blends in drop order, the sums put the far tier
// behind the rest and lose the order within it).
//
// usage: rain_truth [--drops N[,N...]] [--scale S] [--spotlight] [--sorted] [--crops DIR]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/RainBenchScenes.h"
#include "io/exports/Png.h"
#include "render/frame/Lighting.h"
#include "render/rain/RainRenderer.h"
#include "tests/RainTruth.h"

namespace {

using namespace sph;
using bench::kHeight;
using bench::kWidth;

struct Way {
  const char* name;
  float lodWidth;
  scene::RainFarTier tier;
};
constexpr Way kWays[] = {
    {"exact (lod_width 0)", 0, scene::RainFarTier::Lines},
    {"lines 1", 1, scene::RainFarTier::Lines},
    {"sums 1", 1, scene::RainFarTier::Sums},
    {"sums 2", 2, scene::RainFarTier::Sums},
    {"sums 4", 4, scene::RainFarTier::Sums},
    {"sums 8", 8, scene::RainFarTier::Sums},
};

// The 2 x 2 panels of 160 x 90 crops from the frame's centre, each enlarged 3x.
void writeCrops(const std::string& path, const std::vector<const std::vector<double>*>& panels) {
  constexpr int cw = 160, ch = 90, zoom = 3, x0 = (kWidth - cw) / 2, y0 = (kHeight - ch) / 2;
  constexpr int pw = cw * zoom, ph = ch * zoom;
  std::vector<std::uint8_t> rgb(3 * static_cast<std::size_t>(2 * pw) * 2 * ph);
  for (std::size_t i = 0; i < panels.size() && i < 4; ++i) {
    const int px = static_cast<int>(i % 2) * pw, py = static_cast<int>(i / 2) * ph;
    for (int y = 0; y < ph; ++y)
      for (int x = 0; x < pw; ++x) {
        const int fy = kHeight - 1 - (y0 + y / zoom), fx = x0 + x / zoom;  // frame row 0: bottom
        for (int k = 0; k < 3; ++k) {
          const double v = (*panels[i])[3 * (static_cast<std::size_t>(fy) * kWidth + fx) + k];
          rgb[3 * (static_cast<std::size_t>(py + y) * 2 * pw + px + x) + k] =
              static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
        }
      }
  }
  io::exports::writePng(path, 2 * pw, 2 * ph, rgb.data());
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> counts{50000, 200000, 1000000};
  int scale = 4;
  bool spotlight = false, sorted = false;
  std::string crops;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--drops" && i + 1 < argc) {
      counts.clear();
      for (char* s = argv[++i]; *s != 0;) {
        counts.push_back(std::strtoull(s, &s, 10));
        if (*s == ',') ++s;
      }
    } else if (a == "--scale" && i + 1 < argc) {
      scale = std::atoi(argv[++i]);
    } else if (a == "--spotlight") {
      spotlight = true;
    } else if (a == "--sorted") {
      sorted = true;
    } else if (a == "--crops" && i + 1 < argc) {
      crops = argv[++i];
    } else {
      std::fprintf(
          stderr,
          "usage: rain_truth [--drops N[,N...]] [--scale S] [--spotlight] [--sorted] [--crops "
          "DIR]\n");
      return 2;
    }
  }
  const render::frame::Lighting lighting;
  const Vec3 unlit = render::rain::kUnlitTint * lighting.background;
  std::uint8_t background[3];
  for (int k = 0; k < 3; ++k) background[k] = render::frame::toSrgb8(lighting.background[k]);
  const scene::CameraFrame camera = scene::cameraFrame(bench::cameraAtFrame(0), bench::kAspect);
  std::printf(
      "drops,way,psnr_reference_db,psnr_reference_4x4_db,psnr_exact_db,light_over_reference\n");
  for (const std::size_t count : counts) {
    scene::RainDesc d = bench::desc(static_cast<std::int64_t>(count), 0);
    if (spotlight) {
      scene::SpotlightDesc l;
      l.position = Vec3(0, 4, 0), l.height = 5, l.baseRadius = 3;
      l.colour = Vec3(1, 0.2f, 0.2f);
      d.spotlight = l;
    }
    rain::RainSystem system(d, bench::kAspect);
    system.reset(bench::cameraAtFrame(0));
    // The reference's drops: the run's order, or farthest first with --sorted.
    std::vector<Vec3> positions = system.positions();
    std::vector<std::uint8_t> layers = system.layers();
    if (sorted) {
      const Vec3 eye = bench::cameraAtFrame(0).position;
      std::vector<std::size_t> order(positions.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return (positions[a] - eye).squaredNorm() > (positions[b] - eye).squaredNorm();
      });
      std::vector<Vec3> p(order.size());
      std::vector<std::uint8_t> l(order.size());
      for (std::size_t i = 0; i < order.size(); ++i)
        p[i] = positions[order[i]], l[i] = layers[order[i]];
      positions.swap(p), layers.swap(l);
    }
    const render::rain::StreakDrops drops = test::truth::dropsOf(system);
    const std::vector<double> reference =
        test::truth::reference(d, render::rain::StreakDrops{&positions, &layers, system.velocity()},
                               camera, kWidth, kHeight, scale, unlit, background);
    const std::vector<double> referenceBlocks = test::truth::blocks(reference, kWidth, kHeight);
    const double referenceLight = test::truth::light(reference, background);
    std::vector<std::vector<double>> frames;
    for (const Way& way : kWays) {
      d.lodWidth = way.lodWidth, d.farTier = way.tier;
      frames.push_back(test::truth::frame(d, drops, camera, kWidth, kHeight, 1, unlit, background));
      const std::vector<double>& f = frames.back();
      std::printf("%zu,%s,%.2f,%.2f,%.2f,%.4f\n", count, way.name, test::truth::psnr(f, reference),
                  test::truth::psnr(test::truth::blocks(f, kWidth, kHeight), referenceBlocks),
                  frames.size() == 1 ? INFINITY : test::truth::psnr(f, frames.front()),
                  test::truth::light(f, background) / referenceLight);
      std::fflush(stdout);
    }
    if (!crops.empty())
      writeCrops(crops + "/truth_" + std::to_string(count) + (spotlight ? "_spot" : "") +
                     (sorted ? "_sorted" : "") + "_crops.png",
                 {&reference, &frames[0], &frames[5], &frames[1]});
  }
  return 0;
}
