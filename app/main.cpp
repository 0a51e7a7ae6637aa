// sphsplat: the command-line program. Thin: parses arguments and hands over to one subcommand.
#include <CLI/CLI.hpp>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "app/CliChecks.h"
#include "app/Commands.h"
#include "app/DistributedRun.h"
#include "app/MpiStarter.h"
#include "app/OpenMpSpinLimit.h"
#include "app/StatusRecorder.h"
#include "app/Version.h"
#include "io/Hdf5.h"
#include "render/gl/GlError.h"
#include "sim/InputError.h"
#ifdef SPHSPLAT_MPI
#include "mpi/FileErrorWatch.h"
#include "mpi/MpiCommunicator.h"
#include "mpi/MpiIoChoice.h"
#endif

namespace {

// Started with standard input, output or error closed (`>&-`), the program would give their
// numbers to the first files it opens, the cache's lock and the cache, and a progress line would
// land in the cache: those numbers get /dev/null instead.
void openClosedStandardStreams() {
  for (int fd = 0; fd <= 2; ++fd) {
    if (fcntl(fd, F_GETFD) == -1 && errno == EBADF)
      static_cast<void>(open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY));  // the lowest free: fd
  }
}

}  // namespace

int main(int argc, char** argv) {
  openClosedStandardStreams();
  sph::io::h5::startWithoutExitCleanup();
  // A recorder that rank 0 of an MPI run started (app/StatusRecorder.h): nothing else of main.
  if (argc == sph::app::kRecorderArgc && std::strcmp(argv[1], sph::app::kRecorderArgument) == 0)
    return sph::app::runStatusRecorder(argv);
  sph::app::relaunchWithOpenMpSpinLimit(argv);
  const sph::app::MpiStarter starter = sph::app::mpiStarter();
#ifdef SPHSPLAT_MPI
  // Under mpirun: the ranks of a distributed run (docs/scaling.md); a plain process otherwise.
  std::optional<sph::mpi::MpiSession> mpi;
  if (starter.launched) {
    // Open MPI's OMPIO locks the whole file around each write on NFS (its automatic choice),
    // which would wait for ever on the run's own lock of the cache (io/CacheFileLock.cpp): ask
    // it for the written ranges only, unless the user chose (mpirun --mca exports the setting).
    setenv("OMPI_MCA_fs_ufs_lock_algorithm", "3", 0);
    // ROMIO reports a write the disk refused; OMPIO 4.1 does not (mpi/MpiIoChoice.h).
    sph::app::setMpiIoChoice(sph::mpi::preferRomio());
    sph::app::setWorld(mpi.emplace(&argc, &argv).world());
    // A rank stuck after its write of the cache failed ends the run after 3 s (a failure HDF5
    // returns has stopped every rank by then, with its own line).
    sph::mpi::watchFileErrors(3.0, sph::app::kBadInput,
                              [](const char* line) { sph::app::startStatusRecorder(line); });
  }
#else
  if (const std::string refusal = sph::app::refusalWithoutMpi(starter); !refusal.empty()) {
    if (starter.rank == 0) std::fprintf(stderr, "sphsplat: %s\n", refusal.c_str());
    return sph::app::kBadInput;
  }
#endif
  // Errors are told once: by the only process, or by rank 0 (every rank meets the same ones).
  const auto tell = [](const char* format, const char* what) {
#ifdef SPHSPLAT_MPI
    sph::mpi::noteStopping();
#endif
    if (sph::app::isRootProcess() || sph::app::inLockstep()) std::fprintf(stderr, format, what);
#ifdef SPHSPLAT_MPI
    // This rank alone failed while the others wait in a collective: end them all.
    if (sph::app::inLockstep()) {
      std::fflush(stderr);
      sph::mpi::MpiSession::abortAll(2);
    }
#endif
  };
  CLI::App app{"sphsplat " SPHSPLAT_VERSION_STRING
               ": SPH fluid simulation with an image-based collision pass and splat rendering.\n"
               "Scenes are JSON files (scenes/, docs/scene-format.md)."};
  app.set_version_flag("--version", "sphsplat " SPHSPLAT_VERSION_STRING);
  app.require_subcommand(1, 1);
  app.failure_message(sph::app::oneLineFailure);

  std::vector<std::function<int()>> commands;
  commands.push_back(sph::app::addRunCommand(app));
  commands.push_back(sph::app::addInfoCommand(app));
  commands.push_back(sph::app::addExportCommand(app));
  commands.push_back(sph::app::addMeshCommand(app));
  commands.push_back(sph::app::addBenchCommand(app));
  commands.push_back(sph::app::addRenderCommand(app));
  commands.push_back(sph::app::addCompareCommand(app));
  commands.push_back(sph::app::addViewCommand(app));
  // After the subcommands: CLI11 copies a parent's footer into each subcommand made after it.
  app.footer(
      "Run 'sphsplat COMMAND --help' for a command's options.\n"
      "Example: sphsplat run scenes/dam_break.json --threads 2");

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    // --help, --version: every rank parses the same arguments, rank 0 alone prints.
    return sph::app::isRootProcess() ? app.exit(e) : 0;
  } catch (const CLI::ParseError& e) {
    if (sph::app::isRootProcess()) app.exit(e);
    return sph::app::kBadInput;
  }
  try {
    for (auto& command : commands) {
      const int code = command();
      if (code >= 0) return code;
    }
  } catch (const sph::InputError& e) {
    tell("sphsplat: %s\n", e.what());
    return sph::app::kBadInput;
  } catch (const sph::render::gl::GlError& e) {
    tell("sphsplat: %s\n", e.what());
    return sph::app::kNoGraphics;
  } catch (const std::bad_alloc&) {
    tell("sphsplat: %s\n",
         "out of memory: the job needs more memory than this process may use "
         "(run --verbose prints a scene's estimate; a larger solver.spacing needs less)");
    return sph::app::kBadInput;
  } catch (const std::exception& e) {
    tell("sphsplat: internal error: %s\n", e.what());
    return sph::app::kInternalError;
  }
  return sph::app::kInternalError;
}
