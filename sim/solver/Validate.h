// The solver's invariants as checks (STYLE.md rule 10, Box2D's b2ValidateSolverSets): each
// returns "" when it holds, else one line saying what is wrong, naming a particle by id. The step
// runs them through validate() (sim/Assert.h) in SPH_VALIDATE builds; the tests call them
// directly in every build.
#pragma once

#include <cstdint>
#include <string>

#include "sim/Particles.h"
#include "sim/solver/SceneSetup.h"
#include "sim/scene/SolverParams.h"

namespace sph::solver {

// Index of the first particle with a non-finite value in any field, or fluid.size() if none.
std::size_t firstNonFinite(const Particles& fluid);

// After a step that passed the guard: every field of every particle finite (the guard checks
// positions and velocities; a non-finite density, pressure or acceleration left behind is a bug),
// and the ids unique and below nextId.
std::string checkState(const Particles& fluid, std::uint32_t nextId);

// After the density pass: every density finite and at least the particle's own contribution
// m W(0) (the sum includes the particle itself and every other term is >= 0).
std::string checkDensity(const Particles& fluid, const DerivedParams& derived,
                         scene::DensityKernel kernel);

}  // namespace sph::solver
