// Resolved solver parameters of one run. Every field carries its unit; the scene format
// (docs/scene-format.md) documents the same names and defaults.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/Types.h"
#include "sim/scene/EnumNames.h"

namespace sph::scene {

enum class EquationOfState {
  Tait,    // p = B((rho/rho0)^7 - 1), B = rho0 c^2 / 7 (Monaghan 1994; Becker & Teschner 2007)
  Linear,  // p = k (rho - rho0), k = c^2 (Müller et al. 2003)
};
// Scene key solver.eos (sim/scene/EnumNames.h).
constexpr const char* nameOf(EquationOfState v) {
  switch (v) {
    case EquationOfState::Tait:
      return "tait";
    case EquationOfState::Linear:
      return "linear";
  }
  return nullptr;
}

// Kernel of the density sum. The pressure force always uses the spiky gradient (Müller et al.
// 2003); with the spiky density the force is the exact gradient of the density it comes from, so
// the discrete system conserves energy. Poly6 density with the spiky gradient (Müller's original
// recipe, seed 003) is kept as an option: with a stiff EOS that mismatch gains energy in a closed
// tank unless viscosity damps it (tests/test_energy.cpp measures both).
enum class DensityKernel { Spiky, Poly6 };
// Scene key solver.density_kernel.
constexpr const char* nameOf(DensityKernel v) {
  switch (v) {
    case DensityKernel::Spiky:
      return "spiky";
    case DensityKernel::Poly6:
      return "poly6";
  }
  return nullptr;
}

// What moves the particles between collision passes.
enum class SolverModel {
  Sph,        // the SPH stage (DESIGN.md)
  Particles,  // the paper's plain particle system (seed 000): gravity only, fixed step
              // max_time_step
};
// Scene key solver.model.
constexpr const char* nameOf(SolverModel v) {
  switch (v) {
    case SolverModel::Sph:
      return "sph";
    case SolverModel::Particles:
      return "particles";
  }
  return nullptr;
}

// Scene key solver.walls: the names of SolverParams::noSlipWalls (true = NoSlip).
enum class Walls {
  NoSlip,  // walls drag the fluid with the viscosity term (v_wall = 0)
  Slip,    // walls only push (the pressure term)
};
constexpr const char* nameOf(Walls v) {
  switch (v) {
    case Walls::NoSlip:
      return "no-slip";
    case Walls::Slip:
      return "slip";
  }
  return nullptr;
}

// Scene key solver.viscosity_form: how a pair of DFSPH particles shares the viscosity.
enum class ViscosityForm {
  Laplacian,  // Müller et al. 2003's Laplacian of the velocity: every relative motion of the pair,
              // shear included
  Monaghan,   // Monaghan 1992's form as the DFSPH papers' peer writes it: the pair's approach or
              // separation along the line between them only, so shear passes undamped
};
constexpr const char* nameOf(ViscosityForm v) {
  switch (v) {
    case ViscosityForm::Laplacian:
      return "laplacian";
    case ViscosityForm::Monaghan:
      return "monaghan";
  }
  return nullptr;
}

// Scene key solver.density_solve: how DFSPH's constant-density solver iterates
// (sim/solver/Dfsph.cpp, solveDensity()).
enum class DensitySolve {
  Increments,  // the papers' Jacobi: increments that only add, on top of a warm start that stays
  Projected,   // a relaxed Jacobi with momentum on the whole stiffness, kept >= 0: it may give the
               // warm start back where the flow no longer needs it
};
constexpr const char* nameOf(DensitySolve v) {
  switch (v) {
    case DensitySolve::Increments:
      return "increments";
    case DensitySolve::Projected:
      return "projected";
  }
  return nullptr;
}

// Scene key solver.pressure: what makes the fluid incompressible.
enum class PressureSolver {
  Wcsph,  // weakly compressible: an equation of state, step bound by the speed of sound
  Dfsph,  // divergence-free SPH (Bender & Koschier 2015, 2017): two Jacobi pressure solvers, step
          // bound by the flow speed (sim/solver/Dfsph.cpp)
};
constexpr const char* nameOf(PressureSolver v) {
  switch (v) {
    case PressureSolver::Wcsph:
      return "wcsph";
    case PressureSolver::Dfsph:
      return "dfsph";
  }
  return nullptr;
}

// Scene key solver.wall_pressure: the pressure a wall's boundary particles push back with.
enum class WallPressure {
  Extrapolated,  // the pressure the fluid around it extrapolates to it, with the hydrostatic term
                 // (Adami et al. 2012): DFSPH's at every iteration (sim/solver/DfsphWalls.cpp),
                 // WCSPH's as a slow correction of its own (sim/solver/WcsphWalls.cpp)
  Summation,     // WCSPH only: the pressure of its own summation density, as a fluid particle's
  None,          // DFSPH only: none of its own; a wall pair pushes with the fluid particle's
                 // stiffness alone (Akinci et al. 2012's boundary particles as the DFSPH papers
                 // use them)
};
constexpr const char* nameOf(WallPressure v) {
  switch (v) {
    case WallPressure::Extrapolated:
      return "extrapolated";
    case WallPressure::Summation:
      return "summation";
    case WallPressure::None:
      return "none";
  }
  return nullptr;
}

// The default max_time_step of "dfsph" (s): SPlisHSPlasH's; the flow speed and gravity bound the
// step below it (sim/solver/SceneSetup.cpp, timeStep()).
constexpr float kDfsphMaxTimeStep = 5e-3f;

struct SolverParams {
  SolverModel model = SolverModel::Sph;
  PressureSolver pressure = PressureSolver::Wcsph;
  // DFSPH only (sim/solver/Dfsph.cpp). Errors are relative, in percent: the constant-density solver
  // iterates until the mean predicted compression (rho*/rho0 - 1, compressed particles only)
  // is at most maxDensityError; the divergence-free solver until the mean density change the
  // velocity field would make in one step (dt Drho/Dt / rho0) is at most maxDivergenceError.
  float maxDensityError = 0.05f;    // %
  float maxDivergenceError = 0.1f;  // %
  int minDensityIterations = 2;     // the constant-density solver's lower bound
  // The divergence-free solver's: at 0 a step whose warm start already meets the error takes no
  // iteration (one source pass checks it), where the papers always take one.
  int minDivergenceIterations = 1;
  // The constant-density solver's Jacobi iterations (docs/scene-format.md): the share of each
  // increment that is applied, in (0, 1] (1 is the papers', every particle's full correction; half
  // damps the overshoot that makes a still tank heave), and the share of the last step's stiffness
  // it starts from, in [0, 1) (half; more saves the iterations the damping costs, and at 0.8
  // quiets a still tank but runs a fine dam break's front ahead).
  float densityRelaxation = 1.0f;
  float densityWarmStart = 0.5f;
  // The constant-density solver's iterations of the papers' Jacobi before it turns to a relaxed
  // Jacobi with momentum (sim/solver/Dfsph.cpp, solveDensity()); at max_density_iterations or
  // more, the papers' solve throughout.
  int densityMomentumAfter = 4;
  DensitySolve densitySolve = DensitySolve::Increments;
  int maxDensityIterations = 100;   // caps: a step that hits one goes on with the error it has
  int maxDivergenceIterations = 100;
  WallPressure wallPressure = WallPressure::Extrapolated;
  float spacing = 0.01f;        // m, particle spacing dx of the initial lattice
  float support = 2.0f;         // kernel support radius h as a multiple of spacing (h = support dx)
  float restDensity = 1000.0f;  // kg/m^3, rho0
  float viscosity = -1.0f;      // m^2/s, kinematic viscosity of the Müller Laplacian term;
                                // < 0 = automatic: 0.002 h c, i.e. Monaghan's artificial
                                // viscosity alpha = 0.02 (nu = alpha h c / 10)
  // DFSPH only. Monaghan's form takes kMonaghanShare times `viscosity` between fluid particles
  // (alpha 0.05 with the automatic one); no-slip walls drag with `viscosity` in either form.
  ViscosityForm viscosityForm = ViscosityForm::Laplacian;
  static constexpr float kMonaghanShare = 2.5f;
  bool noSlipWalls = true;      // walls drag the fluid with the same viscosity (v_wall = 0)
  EquationOfState eos = EquationOfState::Tait;
  DensityKernel densityKernel = DensityKernel::Spiky;
  float speedOfSound =
      0.0f;  // m/s, c; 0 = automatic (soundSpeedFactor x the largest expected speed)
  float soundSpeedFactor = 10.0f;     // dimensionless, automatic c over the largest expected speed;
                                      // density varies ~1/factor^2 (10 -> ~1%, Monaghan 1994)
  float stiffness = 0.0f;             // Tait: B (Pa); linear: k (m^2/s^2); 0 = derived from c
  bool clampNegativePressure = true;  // p = max(p, 0): no tensile instability at the surface
  float cfl = 0.4f;                   // dimensionless, dt <= cfl h / (c + v_max)
  float maxTimeStep = 1e-3f;          // s, upper bound of the adaptive step (DFSPH: 5e-3,
                                      // kDfsphMaxTimeStep)
  Vec3 gravity = Vec3(0.0f, -9.81f, 0.0f);  // m/s^2
  double endTime = 1.0;                     // s, simulated time of a run
  int boundaryLayers = 0;  // boundary particle layers; 0 = enough to cover the support
  // Particles that leave the domain are removed and counted; past this many the run stops
  // (StabilityError). < 0 = automatic: 1% of the particles the scene can make.
  long long maxLostParticles = -1;

  float supportRadius() const { return support * spacing; }  // h (m)
  // Layers of boundary particles behind each wall: boundaryLayers, or enough to cover the support.
  int wallLayers() const {
    return boundaryLayers > 0 ? boundaryLayers : std::max(1, static_cast<int>(std::ceil(support)));
  }
  // m: how deep the boundary particles reach behind a wall's surface (solids are drawn and lights
  // placed with it).
  float wallThickness() const { return wallLayers() * spacing; }
};

}  // namespace sph::scene
