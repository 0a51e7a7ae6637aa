// libgomp's idle threads spin after every parallel region, 300,000 `pause` iterations by default
// (about 6.5 ms of a core on the 2-core AMD EPYC we measured, 2026-11-23), before they sleep. In a
// program that also draws with llvmpipe, that spinning takes a core from the rasteriser threads
// while they draw the frame the region just built: at 25,503 particles on 2 cores libgomp was 27%
// of all CPU samples of bench_render, and the quad splats' draw took ~10 ms instead of ~8
// (docs/notes/2026-11-23-splat-renderer.md, "Table 1: time per frame"). The SPH step measured
// the same either way (bench_sph).
//
// libgomp reads GOMP_SPINCOUNT once, while it is loaded, before main() runs; setting it later has
// no effect. (An ELF .preinit_array entry runs earlier, but libc's own initialiser then resets the
// environment to the one the process started with.) So the programs that draw (sphsplat,
// bench_render) start again with it set: relaunchWithOpenMpSpinLimit() is their first statement.
#pragma once

namespace sph::job {

// Idle spin iterations (about 0.2 ms here): short barriers between back-to-back regions still
// find the threads awake.
inline constexpr const char* kOpenMpSpinCount = "10000";

// Whether the environment leaves libgomp's spinning open: neither OMP_WAIT_POLICY nor
// GOMP_SPINCOUNT is set (a user's choice always wins).
bool openMpSpinUnset();

// When openMpSpinUnset(), sets GOMP_SPINCOUNT = kOpenMpSpinCount and replaces the process with a
// fresh copy of itself (same pid, arguments and environment plus that variable); returns only if
// nothing needed doing or the exec failed (the program then runs as it is, just spinning longer).
// Call it first in main(), before any thread exists.
void relaunchWithOpenMpSpinLimit(char** argv);

// One line for `run --verbose`: how libgomp's idle threads wait in this process and why.
const char* describeOpenMpWaiting();

}  // namespace sph::job
