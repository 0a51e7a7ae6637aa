#include "job/distributed/MpiStarter.h"

#include <cstdlib>

namespace sph::job::distributed {
namespace {

// The variable's value as a count or rank; -1 when it is unset or not a plain number.
int number(const char* name) {
  const char* text = std::getenv(name);
  if (!text || !*text) return -1;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  return (*end == '\0' && value >= 0 && value < (1L << 30)) ? static_cast<int>(value) : -1;
}

}  // namespace

MpiStarter mpiStarter() {
  MpiStarter s;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) s.launched = true;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (s.processes == 0 && number(name) > 0) s.processes = number(name);
  // PMIx gives no size in the environment; Slurm's srun (`srun --mpi=pmix`) says it beside. Only
  // with a starter's rank set: a batch script's own shell has SLURM_* too, and is one process.
  if (s.launched && s.processes == 0 && number("SLURM_STEP_NUM_TASKS") > 0)
    s.processes = number("SLURM_STEP_NUM_TASKS");
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (s.rank == 0 && number(name) > 0) s.rank = number(name);
  return s;
}

std::string refusalWithoutMpi(const MpiStarter& starter) {
  if (starter.processes <= 1) return {};
  return "started by an MPI launcher as one of " + std::to_string(starter.processes) +
         " processes, but this sphsplat is built without MPI, so each would run the whole job "
         "alone; build the release preset, which has MPI (scripts/build), or run without "
         "mpirun (docs/scaling.md)";
}

}  // namespace sph::job::distributed
