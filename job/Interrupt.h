// Ctrl-C (SIGINT) and SIGTERM during `sphsplat run`: the first one only raises a flag that the
// step loop checks, so the run stops between steps with its cache committed and says where it is;
// a second one ends the process at once (the cache is crash-safe, docs/cache-format.md).
#pragma once

namespace sph::job {

void installInterruptHandlers();
// The signal received (SIGINT, SIGTERM), or 0.
int interruptSignal();
const char* signalName(int signal);

}  // namespace sph::job
