// What a rank does when one of its MPI-IO calls on the cache fails (docs/scaling.md, "The cache
// is written by all ranks"): HDF5 usually returns the error and the run stops every rank with one
// line, but a failure inside a collective step can leave this rank and the others waiting in
// calls that no longer match (HDF5 1.10.8's close after a failed superblock write: one rank in
// the file close's barrier, the other in the metadata cache's), and mpirun would wait forever.
#pragma once

namespace sph::job::distributed::mpi {

// Makes every file opened from now on report its errors here: the first one starts a watch that,
// if this process still runs `graceSeconds` later, prints one line naming the rank and the MPI
// error and ends the process with `exitCode` (mpirun then ends the other ranks); `beforeExit`
// gets that line (without its newline) first. Call once, after MPI_Init.
void watchFileErrors(double graceSeconds, int exitCode, void (*beforeExit)(const char* line));
// This rank has printed why it stops: a watch that fires after this ends the process without a
// second line.
void noteStopping();

}  // namespace sph::job::distributed::mpi
