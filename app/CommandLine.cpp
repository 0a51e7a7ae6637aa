// The command line of `sphsplat` once the process is set up (app/main.cpp): the subcommands, their
// parsing and the one line every failure ends with.
#include "app/CommandLine.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <functional>
#include <new>
#include <vector>

#include "app/CliChecks.h"
#include "app/Commands.h"
#include "io/MessageText.h"
#include "job/Version.h"
#include "job/distributed/DistributedRun.h"
#include "job/distributed/Launch.h"
#include "render/gl/GlError.h"
#include "sim/InputError.h"

namespace sph::app {

int runCommandLine(int argc, char** argv) {
  // Errors are told once: by the only process, or by rank 0 (every rank meets the same ones).
  const auto tell = [](const char* format, const char* what) {
    job::distributed::noteStopping();
    // One line whatever it quotes (a path or a scene's name with a newline or ESC in it).
    if (job::distributed::isRootProcess() || job::distributed::inLockstep())
      std::fprintf(stderr, format, io::oneLine(what).c_str());
    // This rank alone failed while the others wait in a collective: end them all.
    if (job::distributed::inLockstep()) {
      std::fflush(stderr);
      job::distributed::abortAllRanks(2);
    }
  };
  CLI::App app{"sphsplat " SPHSPLAT_VERSION_STRING
               ": SPH fluid simulation with an image-based collision pass and splat rendering.\n"
               "Scenes are JSON files (scenes/, docs/scene-format.md)."};
  app.set_version_flag("--version", "sphsplat " SPHSPLAT_VERSION_STRING);
  app.require_subcommand(1, 1);
  app.failure_message(oneLineFailure);

  std::vector<std::function<int()>> commands;
  commands.push_back(addRunCommand(app));
  commands.push_back(addInfoCommand(app));
  commands.push_back(addExportCommand(app));
  commands.push_back(addMeshCommand(app));
  commands.push_back(addBenchCommand(app));
  commands.push_back(addRenderCommand(app));
  commands.push_back(addCompareCommand(app));
  commands.push_back(addViewCommand(app));
  // After the subcommands: CLI11 copies a parent's footer into each subcommand made after it.
  app.footer(
      "Run 'sphsplat COMMAND --help' for a command's options.\n"
      "Example: sphsplat run scenes/dam_break.json --threads 2");

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    // --help, --version: every rank parses the same arguments, rank 0 alone prints.
    return job::distributed::isRootProcess() ? app.exit(e) : 0;
  } catch (const CLI::ParseError& e) {
    if (job::distributed::isRootProcess()) app.exit(e);
    return job::kBadInput;
  }
  try {
    for (auto& command : commands) {
      const int code = command();
      if (code >= 0) return code;
    }
  } catch (const sph::InputError& e) {
    tell("sphsplat: %s\n", e.what());
    return job::kBadInput;
  } catch (const sph::render::gl::GlError& e) {
    tell("sphsplat: %s\n", e.what());
    return job::kNoGraphics;
  } catch (const std::bad_alloc&) {
    tell("sphsplat: %s\n",
         "out of memory: the job needs more memory than this process may use "
         "(run --verbose prints a scene's estimate; a larger solver.spacing needs less)");
    return job::kBadInput;
  } catch (const std::exception& e) {
    tell("sphsplat: internal error: %s\n", e.what());
    return job::kInternalError;
  }
  return job::kInternalError;
}

}  // namespace sph::app
