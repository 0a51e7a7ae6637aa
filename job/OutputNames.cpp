#include "job/OutputNames.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "io/MessageText.h"
#include "sim/InputError.h"

namespace sph::job {

std::string extensionOf(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return "";
  return path.substr(dot + 1);
}

std::string fileSafe(const std::string& name) {
  std::string out;
  for (const char c : name.substr(0, 64)) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '-' || c == '_' || c == '.';
    out += ok ? c : '_';
  }
  return out.empty() || out[0] == '.' ? "frames" + out : out;
}

std::string baseName(const std::string& path) {
  return path.substr(path.find_last_of('/') + 1);
}

OutputNames::OutputNames(const std::string& output, const std::string& format,
                         const std::string& scene, std::size_t count, const std::string& flag) {
  const std::size_t slash = output.find_last_of('/');
  const std::size_t percent = output.find('%', slash == std::string::npos ? 0 : slash + 1);
  std::error_code error;
  if (output == "-" && count > 1)
    throw InputError(flag + " -: standard output takes one frame, not " + std::to_string(count));
  if (percent != std::string::npos) {
    parsePattern(output, percent, flag);
  } else if (output != "-" &&
             (output.back() == '/' || std::filesystem::is_directory(output, error))) {
    directory_ = output.back() == '/' ? output.substr(0, output.size() - 1) : output;
    if (directory_.empty()) directory_ = "/";
    prefix_ = directory_ + "/" + scene + "_";
    suffix_ = "." + format;
    width_ = 5;
    pvd_ = directory_ + "/" + scene + ".pvd";
  } else if (count > 1) {
    throw InputError(flag + " " + io::printablePath(output) + ": " + std::to_string(count) +
                     " frames need one file each: give a name with %05d where the frame "
                     "number goes (e.g. out/frame_%05d." +
                     format + ") or a directory (ending in /)");
  } else {
    single_ = output;
  }
}

std::string OutputNames::file(std::size_t frame) const {
  if (!single_.empty()) return single_;
  char digits[32];
  std::snprintf(digits, sizeof digits, "%0*zu", width_, frame);
  return prefix_ + digits + suffix_;
}

// One %d, %Nd or %0Nd (N up to 20) in the file name; no other %.
void OutputNames::parsePattern(const std::string& output, std::size_t at, const std::string& flag) {
  std::size_t end = at + 1;
  if (end < output.size() && output[end] == '0') ++end;
  std::size_t digitsStart = end;
  while (end < output.size() && end - digitsStart < 2 && output[end] >= '0' && output[end] <= '9')
    ++end;
  const bool ok =
      end < output.size() && output[end] == 'd' && output.find('%', end + 1) == std::string::npos;
  if (!ok) {
    throw InputError(flag + " " + io::printablePath(output) +
                     ": expected one %d or %05d where the frame number goes, and no other %");
  }
  width_ = digitsStart < end ? std::stoi(output.substr(digitsStart, end - digitsStart)) : 1;
  if (width_ > 20) width_ = 20;
  prefix_ = output.substr(0, at);
  suffix_ = output.substr(end + 1);
  const std::size_t slash = output.find_last_of('/');
  directory_ = slash == std::string::npos ? "." : output.substr(0, std::max<std::size_t>(slash, 1));
  // frame_%05d.vtu -> frame.pvd: the name without the number and its separator.
  std::string stem = prefix_.substr(slash == std::string::npos ? 0 : slash + 1);
  while (!stem.empty() && (stem.back() == '_' || stem.back() == '-' || stem.back() == '.'))
    stem.pop_back();
  if (stem.empty()) stem = "frames";
  pvd_ = (slash == std::string::npos ? "" : output.substr(0, slash + 1)) + stem + ".pvd";
}

void prepareOutputs(const OutputNames& names, const std::vector<std::string>& paths, bool overwrite,
                    const std::vector<io::ReadFile>& reads) {
  for (const std::string& path : paths)
    if (path != "-") io::checkOutputPath(path, overwrite, reads);
  if (!names.sequence()) return;
  std::error_code error;
  std::filesystem::create_directories(names.directory(), error);
  if (error) {
    throw InputError(names.directory() + ": cannot create the output directory (" +
                     error.message() + ")");
  }
}

void writeOutput(const std::string& path, const std::string& what,
                 const std::function<void(std::FILE*)>& write) {
  if (path == "-") {
    write(stdout);
    if (std::fflush(stdout) != 0 || std::ferror(stdout))
      throw InputError("standard output: cannot write " + what);
    return;
  }
  io::AtomicOutput out(path);
  write(out.file());
  out.commit();
}

}  // namespace sph::job
