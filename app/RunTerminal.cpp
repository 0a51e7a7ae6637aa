#include "app/RunTerminal.h"

#include <cstdio>

#include "app/RunReport.h"
#include "io/MessageText.h"
#include "job/Interrupt.h"
#include "job/MachineMemory.h"
#include "sim/HumanText.h"
#include "sim/ranks/Halo.h"

namespace sph::app {

void RunTerminal::checked(const job::RunRequest& o, const scene::Scene& scene,
                          const run::MemoryEstimate& memory) {
  std::printf("%s: a valid scene (%s); memory: %s\n", io::oneLine(o.scene).c_str(),
              io::oneLine(scene.name).c_str(),
              job::describeMemory(memory, job::machineMemory()).c_str());
}

void RunTerminal::nothingToDo(const std::string& cachePath, double time) {
  std::printf("%s already reaches t = %g s; nothing to do (--end sets a later end time)\n",
              io::oneLine(cachePath).c_str(), time);
}

void RunTerminal::started(const job::RunStart& s) {
  label_ = s.scene.name;
  printHeader(s.request, s.scene, s.sim, s.fluidParticles, s.cache, s.setupSeconds, s.memory);
}

void RunTerminal::resumed(const job::RunResume& r) {
  if (!r.distributed) {
    std::printf("  resuming %s from frame %llu at t = %g s%s\n", io::oneLine(r.cachePath).c_str(),
                static_cast<unsigned long long>(r.frame), r.time, r.note.c_str());
    return;
  }
  std::printf(
      "  resuming %s from frame %llu at t = %g s (each of the %d ranks read its slab of it: "
      "at most %lld of its %lld particles)%s\n",
      io::oneLine(r.cachePath).c_str(), static_cast<unsigned long long>(r.frame), r.time, r.ranks,
      r.mostRead, r.totalRead, r.note.c_str());
}

Progress& RunTerminal::bar() {
  if (!progress_) progress_ = std::make_unique<Progress>(Progress::detect(false), label_);
  return *progress_;
}

void RunTerminal::settling(const job::RunSample& s) {
  if (!settling_)
    settling_ = std::make_unique<Progress>(Progress::detect(false), label_ + " settling");
  settling_->update(s);
}

void RunTerminal::settled(const job::RunSample& s, double wallSeconds) {
  if (settling_) settling_->finish(s);
  std::printf(
      "  settled for %g s (scene key settle) in %llu steps, %s; the run starts there at "
      "t = 0\n",
      s.endTime, static_cast<unsigned long long>(s.steps), humanSeconds(wallSeconds).c_str());
  std::fflush(stdout);
}

void RunTerminal::blewUpSettling(const StabilityError& e) {
  if (settling_) settling_->finish({});
  std::fprintf(stderr,
               "sphsplat: %s, while the fluid settled before t = 0 (scene key settle); "
               "nothing was written\n",
               io::oneLine(e.what()).c_str());
}

void RunTerminal::progress(const job::RunSample& s) {
  bar().update(s);
}

void RunTerminal::progressDone(const job::RunSample& s) {
  bar().finish(s);
}

void RunTerminal::blewUp(const job::RunRequest& o, const StabilityError& e,
                         const run::RunPlan& plan, const run::RunOutcome& outcome) {
  std::fprintf(stderr, "sphsplat: %s\n", io::oneLine(e.what()).c_str());
  std::fprintf(stderr, "  reproduce: %s\n", reproduceCommand(o, plan, outcome).c_str());
}

void RunTerminal::interrupted(const job::RunRequest&, int signal, double time) {
  std::fprintf(stderr, "sphsplat: interrupted by %s at t = %g s\n", job::signalName(signal), time);
}

void RunTerminal::cacheStopped(const std::string& kept) {
  std::fprintf(stderr, "  %s\n", io::oneLine(kept).c_str());
}

void RunTerminal::canContinue(const job::RunRequest& o, const std::string& cachePath) {
  std::fprintf(stderr, "  continue with: %s --resume %s\n", commandLine(o, o.end).c_str(),
               shellQuote(cachePath).c_str());
}

void RunTerminal::finished(const job::RunRequest& o, const job::RunSummary& s) {
  if (o.verbose && !s.processes.exchanges.empty())
    std::printf("  %s\n", s.processes.exchanges.c_str());
  const run::Simulation& sim = s.sim;
  const solver::StepProfile& prof = sim.profile();
  const double wall = s.wallSeconds;
  std::printf(
      "done: simulated %.4g s in %llu steps (mean dt %.3g s), %zu fluid particles at the end\n",
      sim.time(), static_cast<unsigned long long>(prof.steps),
      prof.steps ? sim.time() / prof.steps : 0.0, s.endParticles);
  if (sim.lostParticles() > 0) {
    std::printf(
        "  %llu particles left the domain and were removed (solver.max_lost_particles = %llu)\n",
        static_cast<unsigned long long>(sim.lostParticles()),
        static_cast<unsigned long long>(sim.params().maxLostParticles));
  }
  if (const solver::PressureSolveStats& ds = sim.solveStats(); ds.steps > 0) {
    std::printf("  dfsph: %.2f density and %.2f divergence iterations per step\n",
                static_cast<double>(ds.totalDensityIterations) / ds.steps,
                static_cast<double>(ds.totalDivergenceIterations) / ds.steps);
  }
  std::printf("  wall time %s, %s particle-steps/s, %.3g ms per step\n", humanSeconds(wall).c_str(),
              humanCount(wall > 0 ? s.particleSteps / wall : 0).c_str(),
              prof.steps ? 1e3 * wall / prof.steps : 0.0);
  if (o.verbose) printPassSplit(prof);
  if (!s.cacheSummary.empty()) std::printf("  %s\n", io::oneLine(s.cacheSummary).c_str());
  if (s.processes.framesTogether)
    std::printf("  frames written by all %d ranks together (parallel HDF5, MPI-IO: %s)\n",
                s.processes.ranks, s.processes.mpiIo.c_str());
  if (!o.verbose || s.processes.frameSeconds < 0) return;
  std::printf("  frames: %.3g s on rank 0 to %s\n", s.processes.frameSeconds,
              s.processes.framesTogether ? "write them together" : "gather and write them");
  const ranks::HaloStats& hs = *s.processes.haloStats;
  if (s.processes.framesTogether && hs.placesCalls > 0)
    std::printf(
        "  their places (Halo::globalPlaces): %.3g ms, %llu bytes received and %llu "
        "keys sent to be placed a frame on rank 0\n",
        1e3 * hs.placesSeconds / hs.placesCalls,
        static_cast<unsigned long long>(hs.placesBytesReceived / hs.placesCalls),
        static_cast<unsigned long long>(hs.placesStrays / hs.placesCalls));
  if (s.processes.rainCellBytesPerFrame >= 0)
    std::printf(
        "  rain: %.0f bytes of water cells received a frame on rank 0 from the other ranks "
        "(the drops meet their union; no particle is gathered)\n",
        s.processes.rainCellBytesPerFrame);
}

}  // namespace sph::app
