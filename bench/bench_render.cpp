// Seed 003's Table 1 on this machine: time per frame of point and quadrangular-pyramid splats
// (density field + surface detection + normals + splat build + draw) at the paper's particle
// counts (3,555, 10,962, 25,503), then 100k and 1M, plus the error figures against the
// ray-marched reference. The particles are a pool with a wavy surface on the rest lattice (a
// stand-in for simulation frames that we can make at any size, the same shape at every count).
//   build/release/bench/bench_render [--counts 3555,10962,25503,100000,1000000] [--size 960x540]
//                                    [--repeat 5] [--no-reference] [--csv FILE]
// --csv also writes every row (time per frame against the error) for scripts/plot_sweep.py.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "job/OpenMpSpinLimit.h"
#include "render/gl/GlContext.h"
#include "render/splat/FrameRenderer.h"
#include "sim/Parallel.h"

using namespace sph;

namespace {

// A pool of 0.8 x 0.2 x 0.4 m whose top follows a sine swell, on the rest lattice at the spacing
// that gives about n particles (bisection on the spacing; within 1%).
Particles wavyPool(std::size_t n, float& spacing) {
  auto fill = [](float dx, bool keep, Particles* p) {
    const int nx = static_cast<int>(0.8f / dx), ny = static_cast<int>(0.2f / dx),
              nz = static_cast<int>(0.4f / dx);
    std::size_t count = 0;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
          const float x = (i + 0.5f) * dx, y = (j + 0.5f) * dx, z = (k + 0.5f) * dx;
          const float top =
              0.2f * (0.85f + 0.15f * std::sin(6.283f * x / 0.4f) * std::cos(6.283f * z / 0.4f));
          if (y > top) continue;
          if (keep)
            p->append(Vec3(x, y, z), Vec3::Zero(), static_cast<std::uint32_t>(count), 1000.0f);
          ++count;
        }
    return count;
  };
  float lo = 0.0005f, hi = 0.05f;
  for (int it = 0; it < 40; ++it) {
    const float mid = std::sqrt(lo * hi);
    (fill(mid, false, nullptr) > n ? lo : hi) = mid;
  }
  spacing = hi;
  Particles p;
  fill(spacing, true, &p);
  return p;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  job::relaunchWithOpenMpSpinLimit(argv);
  std::vector<std::size_t> counts = {3555, 10962, 25503, 100000, 1000000};
  int width = 960, height = 540, repeat = 5;
  bool reference = true;
  std::string csvPath;
  for (int a = 1; a < argc; ++a) {
    if (!std::strcmp(argv[a], "--counts") && a + 1 < argc) {
      counts.clear();
      std::stringstream s(argv[++a]);
      for (std::string c; std::getline(s, c, ',');) counts.push_back(std::stoul(c));
    } else if (!std::strcmp(argv[a], "--size") && a + 1 < argc) {
      std::sscanf(argv[++a], "%dx%d", &width, &height);
    } else if (!std::strcmp(argv[a], "--repeat") && a + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++a]));
    } else if (!std::strcmp(argv[a], "--csv") && a + 1 < argc) {
      csvPath = argv[++a];
    } else if (!std::strcmp(argv[a], "--no-reference")) {
      reference = false;
    } else {
      std::fprintf(
          stderr,
          "usage: %s [--counts N,N,...] [--size WxH] [--repeat N] [--no-reference] [--csv FILE]\n",
          argv[0]);
      return 2;
    }
  }
  FILE* csv = csvPath.empty() ? nullptr : std::fopen(csvPath.c_str(), "w");
  if (!csvPath.empty() && !csv) {
    std::fprintf(stderr, "bench_render: cannot write %s\n", csvPath.c_str());
    return 2;
  }
  if (csv)
    std::fprintf(
        csv,
        "variant,particles,splats,status,threads,total_ms,psnr_db,rmse,holes_pct,normal_deg\n");
  render::gl::GlContext context = render::gl::GlContext::headless();
  std::printf("renderer: %s, %d threads, %dx%d, median of %d\n\n", context.info().renderer.c_str(),
              threadCount(), width, height, repeat);
  std::printf(
      "| particles | surface | drawn | splats | field ms | surface ms | normals ms | build ms | "
      "draw ms | total ms | PSNR dB | holes %% | normal deg |\n");
  std::printf("|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (std::size_t n : counts) {
    float spacing = 0;
    const Particles pool = wavyPool(n, spacing);
    for (bool newton : {false, true}) {
      scene::RenderDesc desc;
      desc.width = width, desc.height = height,
      desc.projection = newton ? scene::SplatProjection::Newton : scene::SplatProjection::Equation6;
      render::splat::FrameRenderer r(desc, spacing, 1000.0f);
      const scene::CameraDesc camera =
          render::splat::framingCamera(pool, static_cast<float>(width) / height);
      render::frame::RenderImage ref;
      r.prepare(pool);
      if (reference) ref = r.reference(camera);
      for (render::splat::SplatKind kind :
           {render::splat::SplatKind::Point, render::splat::SplatKind::Quad}) {
        if (kind == render::splat::SplatKind::Point && newton)
          continue;  // the projection is the quads'
        std::vector<double> field, surface, normals, build, draw, total;
        render::splat::RenderedSplats last;
        for (int k = 0; k < repeat; ++k) {
          r.prepare(pool);
          last = r.render(kind, camera);
          field.push_back(last.timings.field), surface.push_back(last.timings.splats.surface);
          normals.push_back(last.timings.splats.normals),
              build.push_back(last.timings.splats.build);
          draw.push_back(last.timings.draw), total.push_back(last.timings.total());
        }
        // The error figures from the same frame drawn again with its normal target (untimed).
        render::frame::ImageError e;
        if (reference) e = render::frame::compareImages(r.renderScored(kind, camera).image, ref);
        const char* name = kind == render::splat::SplatKind::Point ? "point"
                           : newton                                ? "quad (newton)"
                                                                   : "quad (eq. 6)";
        std::printf(
            "| %zu | %zu | %zu | %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %s | %s | %s |\n",
            pool.size(), last.surface, last.splats, name, 1e3 * median(field),
            1e3 * median(surface), 1e3 * median(normals), 1e3 * median(build), 1e3 * median(draw),
            1e3 * median(total), reference ? std::to_string(e.psnr).substr(0, 5).c_str() : "-",
            reference ? std::to_string(100 * e.holeFraction).substr(0, 4).c_str() : "-",
            reference ? std::to_string(e.normalErrorDegrees).substr(0, 4).c_str() : "-");
        std::fflush(stdout);
        // rmse: the colour RMS error on [0, 1] that the PSNR is made of (lower is better, so the
        // Pareto front of time and error is one of two minimised columns).
        if (csv)
          std::fprintf(
              csv, "%.0fk %s,%zu,%s,stable,%d,%.3f,%.3f,%.5f,%.3f,%.2f\n", pool.size() / 1e3, name,
              pool.size(), name, threadCount(), 1e3 * median(total), reference ? e.psnr : NAN,
              reference ? std::pow(10.0, -e.psnr / 20.0) : NAN,
              reference ? 100 * e.holeFraction : NAN, reference ? e.normalErrorDegrees : NAN);
      }
    }
  }
  if (csv) std::fclose(csv);
  return 0;
}
