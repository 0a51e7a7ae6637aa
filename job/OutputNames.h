// Where the files of a per-frame output go, for every command that writes one file per frame
// (`export`, `mesh`): OUT itself (one frame, or "-" for standard output), OUT with its %05d
// replaced by the frame number, or DIR/<scene>_NNNNN.<format> for a directory (an existing one,
// or a name ending in /).
#pragma once

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "io/UserFiles.h"

namespace sph::job {

// "ply" of "out/a.ply"; "" when the last path component has no dot.
std::string extensionOf(const std::string& path);
// Scene names are user text: what is safe in a file name (at most 64 characters).
std::string fileSafe(const std::string& name);
// The last path component.
std::string baseName(const std::string& path);

class OutputNames {
 public:
  // `flag` names the option in messages ("-o"). Throws InputError for several frames into one
  // file, a pattern other than one %d / %0Nd, or several frames to "-".
  OutputNames(const std::string& output, const std::string& format, const std::string& scene,
              std::size_t count, const std::string& flag = "-o");

  bool sequence() const { return single_.empty(); }
  const std::string& directory() const { return directory_; }
  // The .pvd collection beside a sequence ("" for one named file).
  const std::string& pvd() const { return pvd_; }

  std::string file(std::size_t frame) const;

 private:
  void parsePattern(const std::string& output, std::size_t at, const std::string& flag);
  std::string single_, prefix_, suffix_, directory_, pvd_;
  int width_ = 5;
};

// Checks every output before the first is written (io::checkOutputPath; "-" is standard output)
// and, for a sequence, creates its directory. Throws InputError.
void prepareOutputs(const OutputNames& names, const std::vector<std::string>& paths, bool overwrite,
                    const std::vector<io::ReadFile>& reads);

// Writes one output through `write`: to standard output for "-", else under a temporary name
// renamed over `path` once complete (io::AtomicOutput). `what` names the content in errors
// ("the mesh").
void writeOutput(const std::string& path, const std::string& what,
                 const std::function<void(std::FILE*)>& write);

}  // namespace sph::job
