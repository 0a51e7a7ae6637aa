// The tests' still tank run and read the same way by every still-tank test of DFSPH
// (tests/test_dfsph.cpp, test_viscosity_form.cpp, test_density_solve.cpp): the shipped scene
// narrowed, settled, read by the floor sensor (tests/StillTankFloor.h), and checked for rest.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "sim/scene/Scene.h"
#include "tests/StillTankFloor.h"

namespace sph::test {

// The tests' still tank: scenes/still_tank.json narrowed to 0.12 m square (0.3 m of water,
// 4,320 particles), with `more` edits.
scene::Scene narrowStillTank(std::vector<std::string> more);

// That tank under DFSPH (with `more` edits), read by the floor sensor from `from` to `end` (s),
// its readings printed under `name`. An edit settle=S settles it first (the scene key: the clock
// then starts again at 0).
StillTankFloor readDfsphStillTank(const std::vector<std::string>& more, double from, double end,
                                  const char* name);

// The tank read by `floor` stayed at rest: no heave, its surface within 1 mm, at most `fast`
// particles ever over 1 cm/s (of its 4,320).
void expectStillTank(const StillTankFloor& floor, std::size_t fast);

}  // namespace sph::test
