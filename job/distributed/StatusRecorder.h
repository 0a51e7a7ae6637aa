// Recording why an MPI run stopped when rank 0 cannot (docs/scaling.md, "A write that fails on
// one rank"). While the ranks write a frame together, a failure on any rank can leave rank 0 in
// a collective call it never returns from, or released from the cache's MPI-IO file mid-frame;
// mpirun then ends it. So for that stretch rank 0 keeps a recorder ready: when the run must stop
// (its own failure, the watch of job/distributed/mpi/FileErrorWatch.h, or mpirun's SIGTERM) it
// starts one, a fresh `sphsplat` process that waits until rank 0 and then its launcher (mpirun,
// which exits once every rank has) have exited, then writes "stopped: ..." into the cache as one
// process would, through the commit protocol (io/cache/CacheSession.h, recordStop), unless the
// cache no longer says "running" or holds more frames than this run could have written (a resume
// got there first). A run that still stops cleanly and records its status itself tells a started
// recorder to do nothing.
#pragma once

#include <cstdint>
#include <string>

namespace sph::job::distributed {

// The hidden first argument that makes `sphsplat` a recorder (runIfStatusRecorder in Launch.h,
// first thing in app/main.cpp).
inline constexpr const char* kRecorderArgument = "--record-stopped-run";
// The recorder's process: `argv` = {exe, kRecorderArgument, CACHE, REASON, LAUNCHER_PID,
// MAX_FRAMES}; the pipe from rank 0 is its descriptor 3. Returns the exit code.
inline constexpr int kRecorderArgc = 6;
int runStatusRecorder(char** argv);

// Rank 0, around a frame written together: the cache (its path now), the reason to record if
// the run ends in it, and how many frames the cache may hold then (with this one).
void armStatusRecorder(const std::string& cache, const std::string& reason,
                       std::uint64_t maxFrames);
void disarmStatusRecorder();
// Whether a frame written together is under way on this rank (every rank arms; only rank 0,
// which names the cache, can start a recorder).
bool statusRecorderArmed();
// Starts the recorder if armed and not started yet; `reason` (if not null) replaces the armed
// one. Async-signal-safe when `reason` is null (the SIGTERM handler, the watch).
void startStatusRecorder(const char* reason = nullptr);
// Rank 0 recorded the status itself after all: a started recorder exits without writing.
void cancelStatusRecorder();

}  // namespace sph::job::distributed
