#include "job/distributed/mpi/MpiIoChoice.h"

#include <dlfcn.h>
#include <mpi.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace sph::job::distributed::mpi {

std::string findRomioComponent(const std::vector<std::string>& directories) {
  const std::string prefix = "mca_io_", suffix = ".so";
  for (const std::string& dir : directories) {
    std::error_code error;
    std::string best;
    for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
      const std::string name = entry.path().filename().string();
      if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix + "romio", 0) != 0 ||
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        continue;
      const std::string component =
          name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
      if (component > best) best = component;  // the newest ROMIO, where several are installed
    }
    if (!best.empty()) return best;
  }
  return "";
}

std::vector<std::string> componentDirectories() {
  std::vector<std::string> dirs;
#ifdef SPHSPLAT_OMPI_PKGLIBDIR
  dirs.push_back(SPHSPLAT_OMPI_PKGLIBDIR);
#endif
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&MPI_Init), &info) && info.dli_fname) {
    const std::filesystem::path lib = std::filesystem::path(info.dli_fname).parent_path();
    dirs.push_back((lib / "openmpi").string());
    dirs.push_back((lib / "openmpi" / "lib" / "openmpi3").string());
  }
  return dirs;
}

std::string preferRomio() {
#ifdef OPEN_MPI
  if (const char* chosen = std::getenv("OMPI_MCA_io"))
    return std::string("as OMPI_MCA_io says (") + chosen + ")";
  std::string romio;
  for (const std::string& dir : componentDirectories()) {
    const std::string found = findRomioComponent({dir});
    if (found.empty()) continue;
    // The list is exclusive: a plug-in that is there but cannot load (a missing library, a
    // leftover of another install) would leave no MPI-IO at all, where OMPIO works.
    if (void* plugin = dlopen((dir + "/mca_io_" + found + ".so").c_str(), RTLD_LAZY | RTLD_LOCAL)) {
      dlclose(plugin);
      romio = found;
      break;
    }
  }
  if (romio.empty()) return "OMPIO (this Open MPI has no ROMIO component that loads)";
  setenv("OMPI_MCA_io", romio.c_str(), 0);
  return "ROMIO (" + romio + ")";
#else
  return "this MPI's own";  // MPICH and its kin have ROMIO only
#endif
}

}  // namespace sph::job::distributed::mpi
