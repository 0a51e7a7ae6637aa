// What an MPI starter (mpirun, mpiexec, srun) told this process through its environment, read
// before MPI is initialised - or in a build without MPI, where it is the only way to notice that
// `mpirun -np K sphsplat run ...` started K plain processes, each of which would run the whole
// scene alone and race the others for the same output (docs/scaling.md).
#pragma once

#include <string>

namespace sph::job::distributed {

struct MpiStarter {
  bool launched = false;  // some starter's variables are set
  int processes = 0;      // how many processes it started; 0 when it does not say
  int rank = 0;           // this process's rank among them; 0 when it does not say
};

// Open MPI's mpirun sets OMPI_COMM_WORLD_SIZE/RANK; PMI and PMIx starters (MPICH's hydra,
// Slurm's srun) set PMI_SIZE/PMI_RANK or PMIX_RANK, and srun the step's SLURM_STEP_NUM_TASKS.
MpiStarter mpiStarter();

// In a build without MPI, the one line that refuses a job started as one of several processes
// (exit 2); empty when nothing needs refusing.
std::string refusalWithoutMpi(const MpiStarter& starter);

}  // namespace sph::job::distributed
