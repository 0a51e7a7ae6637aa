// `sphsplat render CACHE` and `sphsplat compare CACHE --frame N`: their flags; the work is
// job/RenderJob.h and job/CompareJob.h.
#include <CLI/CLI.hpp>
#include <memory>

#include "app/Commands.h"
#include "job/CompareJob.h"
#include "job/RenderJob.h"
#include "sim/scene/EnumNames.h"
#include "sim/scene/RenderDesc.h"

namespace sph::app {

std::function<int()> addRenderCommand(CLI::App& app) {
  auto o = std::make_shared<job::RenderRequest>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render frames of a cache with point or quad splats (no simulation)");
  cmd->add_option("cache", o->cache, "HDF5 cache written by `sphsplat run`")->required();
  cmd->add_option("--frames", o->frames,
                  "Frames: N, A:B (inclusive), A:, :B, last or -1, all (default: all)");
  cmd->add_option("--splat", o->splat,
                  scene::enumNameList<scene::RenderDesc::Splat>() +
                      " (default: the scene's render.splat, else quad)")
      ->check(CLI::IsMember(scene::enumNames<scene::RenderDesc::Splat>()));
  cmd->add_option("--size", o->size,
                  "Image size WIDTHxHEIGHT (default: the scene's render section, else 960x540)");
  cmd->add_option("--out", o->out, "Directory for the PNGs (created)")->capture_default_str();
  cmd->add_flag("--to-cache", o->toCache, "Also store the images in the cache under /Render");
  cmd->add_option("--set", o->overrides,
                  "Edit the recorded scene, e.g. --set render.projection=eq6 for the paper's rule "
                  "(repeatable)");
  cmd->add_flag("--quiet,-q", o->quiet, "No progress and no summary");
  cmd->footer(
      "The camera is the scene's; without one, a camera framing the first frame's particles.\n"
      "Needs OpenGL 4.5 (headless EGL; Mesa's llvmpipe works without a GPU).");
  return [o, cmd]() { return cmd->parsed() ? renderJob(*o) : -1; };
}

std::function<int()> addCompareCommand(CLI::App& app) {
  auto o = std::make_shared<job::CompareRequest>();
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Point vs quad splats vs the ray-marched reference, side by side with times and errors");
  cmd->add_option("cache", o->cache, "HDF5 cache written by `sphsplat run`")->required();
  cmd->add_option("--frame", o->frame, "Frame index, or last / -1 (default: last)");
  cmd->add_option("--out", o->out, "Directory for the PNG (created)")->capture_default_str();
  cmd->add_option("--size", o->size, "Size of each panel, WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--set", o->overrides,
                  "Edit the recorded scene, e.g. --set render.projection=eq6 for the paper's rule "
                  "(repeatable)");
  cmd->footer(
      "Errors are against a CPU ray-marcher of the same SPH iso-surface: PSNR of the colours,\n"
      "holes (surface pixels a renderer leaves empty) and the mean normal angle error. Opaque\n"
      "solids are in every panel (the reference's rays end on them). A fourth panel shows every\n"
      "particle as a ball of its volume: the thin jets the iso-surface omits (not scored).");
  return [o, cmd]() { return cmd->parsed() ? compareJob(*o) : -1; };
}

}  // namespace sph::app
