// The MPI side of a distributed run (docs/scaling.md): the one place that includes <mpi.h>.
// sim/ sees only ranks::Communicator; job/distributed/Launch.h opens an MpiSession when the
// process was started by mpirun, and a run then decomposes the scene over the ranks
// (sim/ranks/Halo.h).
#pragma once

#include <memory>

#include "sim/ranks/Communicator.h"

namespace sph::job::distributed::mpi {

// MPI_Init_thread / MPI_Finalize around main(). Launch (job/distributed/Launch.h) opens one only
// when an MPI starter (mpirun, mpiexec) launched the process (job/distributed/MpiStarter.h): a
// plain `sphsplat` stays a plain process.
class MpiSession {
 public:
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  // The world's ranks.
  ranks::Communicator* world() { return world_.get(); }
  // Ends every rank at once (a rank that must stop while others wait in a collective).
  [[noreturn]] static void abortAll(int code);

 private:
  std::unique_ptr<ranks::Communicator> world_;
};

}  // namespace sph::job::distributed::mpi
