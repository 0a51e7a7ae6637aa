// `sphsplat run SCENE`: simulate a scene, report progress and a summary (job/RunJob.h).
#include <memory>

#include "app/CliChecks.h"
#include "app/Commands.h"
#include "app/RunTerminal.h"
#include "job/RunJob.h"
#include "io/scene/SceneLoader.h"

namespace sph::app {

std::function<int()> addRunCommand(CLI::App& app) {
  auto o = std::make_shared<job::RunRequest>();
  CLI::App* cmd =
      app.add_subcommand("run", "Simulate a scene file (JSON, see docs/scene-format.md)");
  cmd->add_option("scene", o->scene, "Scene file, e.g. scenes/dam_break.json")->required();
  cmd->add_option("--threads,-j", o->threads,
                  "Worker threads (default: all cores; at most 4 x the cores, more is refused)")
      ->check(threadsCheck());
  cmd->add_option("--end", o->end,
                  "Simulated end time in seconds, up to 1e6 (overrides solver.end_time)")
      ->check(positiveUpTo(io::scene::kMaxEndTime, "seconds"));
  cmd->add_option("--set", o->overrides,
                  "Override a scene key before validation, KEY.PATH=VALUE, repeatable\n"
                  "(e.g. --set solver.spacing=0.01 --set fluids[0].velocity=[1,0,0])");
  cmd->add_flag("--quiet,-q", o->quiet, "No progress and no summary, only errors");
  cmd->add_flag("--verbose,-v", o->verbose,
                "Also print the domain, what the scene skips and the time per pass");
  cmd->add_flag("--check", o->check,
                "Check the scene (its keys, values, the edits and the memory the run would need) "
                "and stop without simulating");
  cmd->add_option("--output,-o", o->cache.output,
                  "Write the HDF5 cache (and its .xdmf sidecar) to PATH; overrides output.path");
  cmd->add_flag("--overwrite", o->cache.overwrite, "Replace an existing cache at that path");
  cmd->add_flag("--no-compress", o->cache.noCompress, "Store the cache's datasets uncompressed");
  cmd->add_option("--resume", o->cache.resume,
                  "Continue the run in CACHE from its last complete frame, appending to it\n"
                  "(same scene and --set edits; same --threads for a bit-exact continuation)");
  cmd->footer(
      "Exit codes: 0 done, 2 bad scene, cache or flags, 3 numerical blow-up (the message\n"
      "names the step, time and particle, and the cache's last good frame), 1 internal\n"
      "error, 130/143 stopped by SIGINT/SIGTERM (the cache keeps every finished frame).\n"
      "On K processes (the release build has Open MPI): mpirun -np K\n"
      "sphsplat run SCENE ...; the cache is the same, bit for bit, with WCSPH or DFSPH\n"
      "(docs/scaling.md).");
  return [o, cmd]() {
    if (!cmd->parsed()) return -1;
    RunTerminal terminal;
    return job::runJob(*o, terminal);
  };
}

}  // namespace sph::app
