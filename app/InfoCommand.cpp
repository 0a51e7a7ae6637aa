// `sphsplat info CACHE`: what an HDF5 cache holds (frames, time range, particle counts, fields,
// scene, size, whether its run finished), read from the file alone.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "job/CacheScene.h"
#include "app/Commands.h"
#include "app/Progress.h"
#include "io/cache/CacheReader.h"
#include "io/cache/CacheWriter.h"
#include "io/MessageText.h"
#include "io/OutputLock.h"
#include "io/cache/XdmfWriter.h"

namespace sph::app {
namespace {

struct InfoOptions {
  std::string cache;
  bool listFrames = false;
};

std::string describeStatus(const io::cache::CacheSummary& s) {
  if (s.status.rfind("running", 0) != 0) return s.status;
  const std::string last =
      s.frames.empty() ? std::string("no frame") : "frame " + std::to_string(s.frames.size() - 1);
  if (io::cache::cacheIsLocked(s.path) || io::OutputLock::isHeld(s.path))
    return "running: a sphsplat run is writing it now (" + last + " so far)";
  return "unfinished: its run was killed or crashed after " + last +
         " (every frame listed is complete; continue with sphsplat run SCENE --resume " + s.path +
         ")";
}

int info(const InfoOptions& o) {
  const io::cache::CacheReader reader(o.cache);
  const io::cache::CacheSummary& s = reader.summary();
  const std::size_t n = s.frames.size();
  std::printf("%s: sphsplat cache (format %lld, written by sphsplat %s, created %s)\n",
              s.path.c_str(), static_cast<long long>(s.formatVersion), s.programVersion.c_str(),
              s.created.c_str());
  std::string overrides;  // as the command line gave them
  for (const std::string& edit : io::cache::sceneEdits(s))
    overrides += (overrides.empty() ? ", --set " : " --set ") + edit;
  std::printf("  scene      %s (%s)%s\n", s.sceneName.c_str(), s.scenePath.c_str(),
              overrides.c_str());
  std::printf("  status     %s\n", describeStatus(s).c_str());
  if (n == 0) {
    std::printf("  frames     none complete\n");
  } else {
    std::printf("  frames     %zu (Step#0 - Step#%zu), t = %g - %g s at %g frames/s\n", n, n - 1,
                s.frames.front().time, s.frames.back().time, s.fps);
    std::size_t lo = s.frames[0].particles, hi = lo;
    double total = 0;
    for (const io::cache::CacheFrame& f : s.frames) {
      lo = std::min(lo, f.particles), hi = std::max(hi, f.particles);
      total += static_cast<double>(f.particles);
    }
    std::printf("  particles  %zu - %zu fluid per frame (%zu in the last), %zu boundary\n", lo, hi,
                s.frames.back().particles, s.boundaryParticles);
    if (total > 0) {
      const double data = static_cast<double>(reader.frameDataBytes());
      std::printf(
          "  size       %sB = %.3g bytes per particle per frame; the frames' datasets alone %.3g\n",
          humanCount(static_cast<double>(s.fileBytes)).c_str(),
          static_cast<double>(s.fileBytes) / total, data / total);
    }
  }
  if (n == 0)
    std::printf("  size       %sB\n", humanCount(static_cast<double>(s.fileBytes)).c_str());
  std::printf(
      "  fields     %s (float%s, id uint32), %s\n", io::cache::describeFields(s.fields).c_str(),
      s.doublePositions ? "32; x y z float64" : "32",
      // The level only: at level 1 one process deflates with zlib's run-length strategy,
      // the ranks of an MPI run writing together with HDF5's level 1, and the cache does
      // not record which wrote a dataset.
      s.compression > 0 ? ("deflate " + std::to_string(s.compression) + " + shuffle").c_str()
                        : "uncompressed");
  const auto resumable = std::count_if(s.frames.begin(), s.frames.end(),
                                       [](const io::cache::CacheFrame& f) { return f.hasRestart; });
  std::printf("  resume     %s\n",
              s.restart ? (std::to_string(resumable) + " frames have a resume record").c_str()
                        : "no resume records (output.restart = false)");
  std::string solver;
  for (const io::cache::Parameter& p : s.parameters) {
    char value[64];
    if (p.isText)
      std::snprintf(value, sizeof value, "%s", p.text.c_str());
    else
      std::snprintf(value, sizeof value, "%g", p.number);
    solver += (solver.empty() ? "" : ", ") + p.name.substr(p.name.find('.') + 1) + " " + value;
  }
  std::printf("  solver     %s; written with %lld thread%s\n", solver.c_str(),
              static_cast<long long>(s.threads), s.threads == 1 ? "" : "s");
  std::string rendered;
  for (const auto& [name, frames] : s.renderers)
    rendered += (rendered.empty() ? "" : "; ") + name + " " + io::cache::describeFrames(frames);
  std::printf("  rendered   %s\n", rendered.empty() ? "none" : rendered.c_str());
  // The rain's drops beside the frames (io/cache/RainCache.h); nothing is printed for a cache without.
  std::size_t rainFrames = 0, rainDrops = 0;
  for (const io::cache::CacheFrame& f : s.frames) {
    if (f.rainDrops > 0) ++rainFrames, rainDrops = f.rainDrops;
  }
  if (rainFrames > 0)
    std::printf(
        "  rain       %zu drops per frame in %zu frame%s (Rain#N; the XDMF's 'rain' grid)\n",
        rainDrops, rainFrames, rainFrames == 1 ? "" : "s");
  // rain.feed_fluid's ledger at the last frame (sim/rain/RainFeed.h).
  if (!s.frames.empty()) {
    if (const rain::FeedState f = reader.readRainFeed(s.frames.size() - 1); f.landedDrops > 0)
      std::printf(
          "  rain feed  %llu drops landed in the water: %llu fluid particles, %.4g m^3 pending\n",
          static_cast<unsigned long long>(f.landedDrops),
          static_cast<unsigned long long>(f.particles), f.pending);
  }
  if (!s.damagedFrame.empty())
    std::printf("  damaged    %s (frames after it are not listed)\n", s.damagedFrame.c_str());
  std::printf("  ParaView   paraview %s   (or open %s with the H5Part reader)\n",
              io::cache::XdmfWriter::sidecarPath(s.path).c_str(), s.path.c_str());
  if (o.listFrames) {
    std::printf("  frame        time (s)   particles       steps  resume\n");
    for (const io::cache::CacheFrame& f : s.frames) {
      std::printf("  %5zu %15.9g %11zu %11llu  %s\n", f.index, f.time, f.particles,
                  static_cast<unsigned long long>(f.step), f.hasRestart ? "yes" : "no");
    }
  }
  // What could not be read is an error, after everything that could (a new cache is published
  // only once frame 0 is in, so a cache without a frame is damaged too).
  // The report is the command's product: one that could not be written (a full disk) is a
  // failed command, not a quiet success.
  if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::fprintf(stderr, "sphsplat: cannot write to standard output (%s)\n", std::strerror(errno));
    return job::kBadInput;
  }
  if (!s.damagedFrame.empty()) return job::exitAfterReading(s);
  if (n == 0) {
    std::fflush(stdout);
    std::fprintf(stderr,
                 "sphsplat: %s: damaged cache: it has no complete frame (not even the initial "
                 "state, frame 0)\n",
                 io::printablePath(s.path).c_str());
    return job::kBadInput;
  }
  return job::kOk;
}

}  // namespace

std::function<int()> addInfoCommand(CLI::App& app) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Describe an HDF5 cache: frames, times, particles, fields, status");
  cmd->add_option("cache", o->cache, "Cache file written by sphsplat run --output")->required();
  cmd->add_flag("--frames", o->listFrames,
                "Also list every frame: time, particle count, solver steps");
  cmd->footer(
      "Exit codes: 0 done, 2 missing, damaged or foreign file (one line on stderr says what; a\n"
      "damaged cache still gets the lines that could be read).");
  return [o, cmd]() { return cmd->parsed() ? info(*o) : -1; };
}

}  // namespace sph::app
