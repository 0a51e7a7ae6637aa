// The subcommands of `sphsplat`. Each registers its options on the CLI11 app and returns the exit
// code of its run (job/ExitCode.h).
#pragma once

#include <functional>

#include "job/ExitCode.h"

// Declared, not included: CLI11's header costs seconds in every file that includes it (it
// constructs its validators in each), and the jobs that return an exit code need none of it.
namespace CLI {
class App;
}

namespace sph::app {

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
