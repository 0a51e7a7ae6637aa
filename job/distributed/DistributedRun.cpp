#include "job/distributed/DistributedRun.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "sim/InputError.h"

namespace sph::job::distributed {
namespace {

ranks::Communicator* gWorld = nullptr;
bool gLockstep = false;
std::string gMpiIoChoice;

template <class T>
void put(ranks::Bytes& out, const T& v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}
template <class T>
void take(const ranks::Bytes& in, std::size_t& at, T& v) {
  std::memcpy(&v, in.data() + at, sizeof v);
  at += sizeof v;
}

}  // namespace

ranks::Communicator* world() {
  return gWorld;
}
void setWorld(ranks::Communicator* ranks) {
  gWorld = ranks;
}
const std::string& mpiIoChoice() {
  return gMpiIoChoice;
}
void setMpiIoChoice(std::string choice) {
  gMpiIoChoice = std::move(choice);
}
void setLockstep(bool on) {
  gLockstep = on;
}
bool inLockstep() {
  return gLockstep && gWorld && gWorld->size() > 1;
}
bool isRootProcess() {
  return !gWorld || gWorld->rank() == 0;
}

void refuseUnsupported(const scene::Scene& scene, int ranks) {
  const std::string where = scene.sourcePath.empty() ? "scene" : scene.sourcePath;
  // `exact` runs distributed, `octree` and `cdt-cpu` on the whole fluid gathered on every rank
  // (sim/run/Simulation.cpp, collide); `cdt-gl` would need a GL context per rank.
  if (scene.collision && scene.collision->method == scene::CollisionMethod::CdtGl) {
    throw InputError(where +
                     ": collision.method \"cdt-gl\" runs on one process only (it draws with "
                     "OpenGL); run without mpirun, or set collision.method to \"cdt-cpu\" "
                     "(the same detection on the CPU) or \"exact\" (docs/scaling.md)");
  }
  if (scene.rain && scene.rain->feedFluid) {
    throw InputError(where +
                     ": rain.feed_fluid runs on one process only (the landed drops become "
                     "particles in one place, not shared out yet); run without mpirun or set "
                     "rain.feed_fluid to false (docs/scaling.md)");
  }
  if (scene.render) {
    throw InputError(where +
                     ": the render section draws on one process only; run without mpirun and "
                     "render the cache afterwards with `sphsplat render` (docs/scaling.md)");
  }
  // Slabs are whole planes of support-radius cells along the longest axis; fewer than 4 per
  // rank leaves ranks that hold mostly ghosts.
  const float h = scene.solver.supportRadius();
  const Vec3 extent = scene.domain.hi - scene.domain.lo;
  const double planes = std::floor(extent.maxCoeff() / h);
  if (planes < 4.0 * ranks) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "%s: domain is too small for %d processes: its longest side holds %.0f cells "
                  "of the support radius (%g m), 4 per process are needed; use at most %d "
                  "processes",
                  where.c_str(), ranks, planes, h, std::max(1, static_cast<int>(planes / 4)));
    throw InputError(text);
  }
}

namespace {

// Rank 0's refusal (empty: it went on) on every rank, thrown there if it refused.
void shareRefusal(ranks::Communicator& ranks, ranks::Bytes message) {
  ranks.broadcastFromRoot(message);
  if (message.empty()) return;
  // Every rank stops here with the same error: told once by rank 0 and exit 2, not K times with
  // an abort, whether or not the ranks were already in lockstep.
  setLockstep(false);
  throw InputError(std::string(message.begin(), message.end()));
}

}  // namespace

void refuseOnAllRanks(ranks::Communicator& ranks, const std::string& what) {
  ranks::Bytes message(what.begin(), what.end());
  if (message.empty()) message.push_back(' ');
  shareRefusal(ranks, std::move(message));
  throw InputError(what);  // not reached: a refusal is thrown by shareRefusal
}

void followRoot(ranks::Communicator& ranks) {
  shareRefusal(ranks, {});
}

void onRootAgreeing(ranks::Communicator& ranks, const std::function<void()>& work) {
  if (ranks.rank() == 0) {
    try {
      work();
    } catch (const InputError& e) {
      refuseOnAllRanks(ranks, e.what());
    }
  }
  followRoot(ranks);
}

run::RunState broadcastRunState(ranks::Communicator& ranks, const run::RunState& state) {
  ranks::Bytes b;
  if (ranks.rank() == 0) {
    put(b, state.time), put(b, state.step), put(b, state.lastDt), put(b, state.maxSpeed);
    put(b, state.maxAcceleration), put(b, state.nextId), put(b, state.lostParticles);
    put(b, static_cast<std::uint64_t>(state.emitters.size()));
    for (const run::EmitterState& e : state.emitters) {
      put(b, e.travelled), put(b, e.emitted);
      put(b, static_cast<std::uint8_t>(e.started));
    }
  }
  ranks.broadcastFromRoot(b);
  run::RunState s;
  std::size_t at = 0;
  take(b, at, s.time), take(b, at, s.step), take(b, at, s.lastDt), take(b, at, s.maxSpeed);
  // The lost particles so far: every rank checks the tolerance with them (Simulation::step).
  take(b, at, s.maxAcceleration), take(b, at, s.nextId), take(b, at, s.lostParticles);
  std::uint64_t emitters = 0;
  take(b, at, emitters);
  s.emitters.resize(emitters);
  for (run::EmitterState& e : s.emitters) {
    std::uint8_t started = 0;
    take(b, at, e.travelled), take(b, at, e.emitted), take(b, at, started);
    e.started = started != 0;
  }
  return s;
}

void GatheringSink::frame(const run::Simulation&, std::size_t index) {
  const auto start = std::chrono::steady_clock::now();
  // The solver's per-particle state is attached to the halo (Simulation::setHalo), in the order
  // of Simulation::particleState().
  std::vector<std::vector<float>> attached;
  Particles all = halo_.gather(sim_.fluid(), &attached);
  if (halo_.rank() != 0) return;
  solver::PressureWarmStart warm;
  const std::vector<std::vector<float>*> slots = sim_.particleState(warm);
  for (std::size_t k = 0; k < slots.size() && k < attached.size(); ++k) slots[k]->swap(attached[k]);
  // The sinks see the whole fluid and its solver state (the resume record), in the order one
  // process would hold them.
  auto swapIn = [&] {
    std::swap(sim_.fluid(), all);
    if (!slots.empty()) std::swap(sim_.warmStart(), warm);
  };
  swapIn();
  try {
    for (run::FrameSink* sink : sinks_) sink->frame(sim_, index);
  } catch (...) {
    swapIn();
    throw;
  }
  swapIn();
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string describeExchanges(ranks::Halo& halo, const solver::StepProfile& profile) {
  const ranks::HaloStats& s = halo.stats();
  const double steps = s.steps ? static_cast<double>(s.steps) : 1.0;
  const double total = profile.total();
  char text[480];
  std::snprintf(
      text, sizeof text,
      "rank %d of %d: exchange %.1f%% of the step, %.0f bytes sent per step, %.0f "
      "ghosts per step, %llu particles migrated out, %llu migrated between ranks "
      "after the first step (all ranks), imbalance (max/mean particles per rank) mean "
      "%.3f max %.3f",
      halo.rank(), halo.ranks(), total > 0 ? 100 * profile[solver::Pass::Exchange] / total : 0.0,
      s.bytesSent / steps, s.ghostsReceived / steps, static_cast<unsigned long long>(s.migrated),
      static_cast<unsigned long long>(s.migratedAllRanks), s.imbalanceSum / steps, s.imbalanceMax);
  std::string line = text;
  if (s.refreshes > 0) {  // DFSPH: the ghosts' velocities sent again before every source pass
    const double simSteps = profile.steps ? static_cast<double>(profile.steps) : 1.0;
    std::snprintf(text, sizeof text,
                  "; DFSPH ghost velocity refreshes %.1f per step, %.0f bytes sent per step, "
                  "%.1f%% of the step",
                  s.refreshes / simSteps, s.refreshBytesSent / simSteps,
                  total > 0 ? 100 * s.refreshSeconds / total : 0.0);
    line += text;
  }
  return line;
}

}  // namespace sph::job::distributed
