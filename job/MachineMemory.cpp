#include "job/MachineMemory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "sim/HumanText.h"
#include "sim/InputError.h"

namespace sph::job {
namespace {

// The value of "Key:" in a /proc file of "Key: value kB" lines, in bytes (0 if absent).
double procKilobytes(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string name;
  double value = 0;
  std::string unit;
  while (in >> name >> value) {
    std::getline(in, unit);
    if (name == key + ":") return value * 1024;
  }
  return 0;
}

// A cgroup v2 memory.max (bytes), or 0 when unlimited or not there.
double cgroupLimit() {
  std::ifstream in("/sys/fs/cgroup/memory.max");
  std::string text;
  if (!(in >> text) || text == "max") return 0;
  return std::strtod(text.c_str(), nullptr);
}

double cgroupUsage() {
  std::ifstream in("/sys/fs/cgroup/memory.current");
  double used = 0;
  in >> used;
  return used;
}

std::string count(double n) {
  char text[32];
  std::snprintf(text, sizeof text, n < 1e6 ? "%.0f" : "%.3g", n);
  return text;
}

}  // namespace

MachineMemory machineMemory() {
  MachineMemory m;
  m.totalBytes = procKilobytes("/proc/meminfo", "MemTotal");
  m.availableBytes = procKilobytes("/proc/meminfo", "MemAvailable");
  if (const double limit = cgroupLimit(); limit > 0) {
    const double free = std::max(0.0, limit - cgroupUsage());
    if (free < m.availableBytes) m.availableBytes = free, m.limitedBy = "the cgroup's memory.max";
  }
  m.sharedBytes = m.availableBytes, m.sharedLimitedBy = m.limitedBy;
  struct rlimit as {};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const double free = std::max(
        0.0, static_cast<double>(as.rlim_cur) - procKilobytes("/proc/self/status", "VmSize"));
    if (free < m.availableBytes) m.availableBytes = free, m.limitedBy = "ulimit -v";
  }
  return m;
}

std::string describeMemory(const run::MemoryEstimate& e, const MachineMemory& m) {
  std::ostringstream s;
  s << "about " << humanBytes(e.bytes);
  if (e.ranks > 1) s << " a process on " << e.ranks << " processes";
  s << " (" << count(e.fluidParticles) << " fluid particles";
  if (e.emittedParticles > 0) s << " + " << count(e.emittedParticles) << " from nozzles";
  if (e.rainParticles > 0) s << " + up to " << count(e.rainParticles) << " from the rain";
  if (e.ranks > 1) s << " shared out";
  s << ", " << count(e.boundaryParticles) << " boundary particles";
  if (e.rainDrops > 0) s << ", " << count(e.rainDrops) << " rain drops";
  s << "); ";
  // "25.3 GB, 22.7 GB of it free" or "25.3 GB, of which ulimit -v leaves 921.6 MB".
  s << "the machine has " << humanBytes(m.totalBytes);
  if (m.limitedBy.empty())
    s << ", " << humanBytes(m.availableBytes) << " of it free";
  else
    s << ", of which " << m.limitedBy << " leaves " << humanBytes(m.availableBytes);
  return s.str();
}

std::optional<std::string> memoryRefusal(const scene::Scene& scene,
                                         const run::MemoryEstimate& estimate,
                                         const MachineMemory& m, const RanksHere& here) {
  // This process alone (what only rank 0 holds on rank 0 alone), then the ranks of this machine
  // together (rank 0's part where it runs).
  run::MemoryEstimate e = estimate;
  const double shared = e.bytes - e.rootOnlyBytes;
  if (!here.rankZero) e.bytes = shared;
  const double together =
      shared * std::max(1, here.count) + (here.withRankZero ? e.rootOnlyBytes : 0);
  const bool processFits = m.availableBytes <= 0 || e.bytes <= m.availableBytes;
  const bool machineFits = here.count <= 1 || m.sharedBytes <= 0 || together <= m.sharedBytes;
  if (processFits && machineFits) return std::nullopt;
  const std::string advice = e.largestKey == "solver.spacing"
                                 ? "raise solver.spacing (memory falls with its cube)"
                             : e.largestKey == "rain.count" ? "lower rain.count"
                             : e.largestKey == "rain.drop_volume"
                                 ? "lower rain.drop_volume or rain.count, or end the run earlier"
                                 : "make that nozzle smaller or stop it sooner";
  std::string text =
      scene.sourcePath + ": " + e.largestKey + ": this scene needs " + describeMemory(e, m);
  if (processFits) {
    text += "; the " + std::to_string(here.count) + " processes on this machine need about " +
            humanBytes(together) + " together, and " +
            (m.sharedLimitedBy.empty() ? "it has " : m.sharedLimitedBy + " leaves ") +
            humanBytes(m.sharedBytes) + (m.sharedLimitedBy.empty() ? " free" : "");
  }
  text += "; " + advice;
  text += e.ranks <= 1   ? " or shrink the scene"
          : !processFits ? ", run on more processes or shrink the scene"
                         : ", spread the processes over more machines or shrink the scene";
  return text;
}

RanksHere ranksOnThisMachine(ranks::Communicator& ranks) {
  char name[256] = {};
  gethostname(name, sizeof name - 1);
  const ranks::Bytes mine(name, name + std::strlen(name));
  const std::vector<ranks::Bytes> names = ranks.allGather(mine);
  RanksHere here;
  here.count = 0;
  for (const ranks::Bytes& other : names) here.count += other == mine;
  here.rankZero = ranks.rank() == 0;
  here.withRankZero = !names.empty() && names[0] == mine;
  return here;
}

run::MemoryEstimate checkMemory(const scene::Scene& scene, ranks::Communicator* ranks,
                                bool gathersFrames) {
  run::RankShare share;
  if (ranks)
    share.ranks = ranks->size(), share.distributed = true, share.gathersFrames = gathersFrames;
  const run::MemoryEstimate e = estimateMemory(scene, share);
  const RanksHere here = ranks ? ranksOnThisMachine(*ranks) : RanksHere{};
  const std::optional<std::string> refusal = memoryRefusal(scene, e, machineMemory(), here);
  if (!ranks) {
    if (refusal) throw InputError(*refusal);
    return e;
  }
  // Machines differ: any rank's refusal stops every rank, told once (the first rank's).
  const ranks::Bytes mine = refusal ? ranks::Bytes(refusal->begin(), refusal->end()) : ranks::Bytes{};
  for (const ranks::Bytes& text : ranks->allGather(mine))
    if (!text.empty()) throw InputError(std::string(text.begin(), text.end()));
  return e;
}

}  // namespace sph::job
