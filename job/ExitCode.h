// The exit codes of every `sphsplat` command: 0 success, 1 internal error, 2 bad input (scene,
// cache, flags) or an output that could not be written (a full disk), 3 numerical blow-up stopped
// by the guard, 4 no usable OpenGL (no EGL/display, old driver, shader error).
#pragma once

namespace sph::job {

enum ExitCode { kOk = 0, kInternalError = 1, kBadInput = 2, kBlowUp = 3, kNoGraphics = 4 };

}  // namespace sph::job
