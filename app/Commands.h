// The subcommands of `sphsplat`. Each registers its options on the CLI11 app and returns the exit
// code of its run: 0 success, 1 internal error, 2 bad input (scene, cache, flags), 3 numerical
// blow-up stopped by the guard, 4 no usable OpenGL (no EGL/display, old driver, shader error).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace sph::app {

enum ExitCode { kOk = 0, kInternalError = 1, kBadInput = 2, kBlowUp = 3, kNoGraphics = 4 };

// Registers `run` and returns the function that executes it once parsed.
std::function<int()> addRunCommand(CLI::App& app);
// `info CACHE` and `export CACHE --frame N --format csv|ply` (HDF5 caches, docs/cache-format.md).
std::function<int()> addInfoCommand(CLI::App& app);
std::function<int()> addExportCommand(CLI::App& app);
// `mesh CACHE --frames F --out DIR`: the renderer's water surface as PLY/OBJ meshes (docs/mesh.md).
std::function<int()> addMeshCommand(CLI::App& app);
// `bench SWEEP.json`: a sweep of scene variants, wall time against error (docs/benchmarks.md).
std::function<int()> addBenchCommand(CLI::App& app);
// `render CACHE`, `compare CACHE --frame N`, `view CACHE`: the splat renderer on cached frames.
std::function<int()> addRenderCommand(CLI::App& app);
std::function<int()> addCompareCommand(CLI::App& app);
std::function<int()> addViewCommand(CLI::App& app);

}  // namespace sph::app
