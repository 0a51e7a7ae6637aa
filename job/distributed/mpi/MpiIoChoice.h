// Which of Open MPI's two MPI-IO implementations the ranks write the cache with (docs/scaling.md,
// "A write that fails on one rank"). Open MPI 4.1's default, OMPIO, does not report a write the
// disk refused as an MPI error (it prints "mca_fbtl_posix_pwritev: error in (p)write(v)" and
// returns success), so HDF5 fails the short write on that rank alone and the ranks can wait for
// each other for ever; ROMIO returns the error, and the run stops with one line. So the ranks
// ask for ROMIO where this Open MPI has it, unless the user chose.
#pragma once

#include <string>
#include <vector>

namespace sph::job::distributed::mpi {

// The name of an Open MPI ROMIO component ("romio321", "romio341": the name follows the ROMIO
// release) whose plug-in (mca_io_romio*.so) is in one of `directories`; "" when none is.
std::string findRomioComponent(const std::vector<std::string>& directories);

// Where this Open MPI keeps its plug-ins: the directory found at build time, then the layouts
// beside the libmpi this process loaded (upstream: LIBDIR/openmpi; Debian:
// LIBDIR/openmpi/lib/openmpi3).
std::vector<std::string> componentDirectories();

// Call before MPI starts. Unless OMPI_MCA_io is set (by the user, or by `mpirun --mca io ...`),
// asks Open MPI for its ROMIO component when one is installed. Returns what the run writes with,
// for `run`'s summary: "ROMIO (romio321)", "OMPIO (this Open MPI has no ROMIO component that
// loads)", or the user's choice. A ROMIO plug-in is chosen only if it loads (dlopen).
std::string preferRomio();

}  // namespace sph::job::distributed::mpi
