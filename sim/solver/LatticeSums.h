// Sums over the rest lattice: the cubic lattice of spacing dx a scene's fluid starts on, seen
// from one of its points. They calibrate the SPH sums so that this arrangement reads exactly what
// it should: the solver's density normalisation and pressure-gradient correction
// (SceneSetup.cpp, DerivedParams) and the renderer's density field (render/splat/DensityField.cpp,
// "the rest lattice reads rest_density").
#pragma once

#include <limits>

#include "sim/solver/Kernels.h"
#include "sim/scene/SolverParams.h"

namespace sph::solver {

// maxLayer of latticeKernelSum for the whole lattice.
inline constexpr int kAllLayers = std::numeric_limits<int>::max();

// Sum of the density kernel W over the lattice points (a, b, c) dx (integers a, b, c; the centre
// included), using Kernels' full functions in float, summed in double with a outermost and c
// innermost. Only the layers b <= maxLayer count: kAllLayers is the bulk, 0 a particle in the top
// layer of a flat free surface whose normal is +y.
double latticeKernelSum(const Kernels& k, scene::DensityKernel kernel, float dx,
                        int maxLayer = kAllLayers);

// First moment of the spiky gradient over the lattice, K = sum_j V (x_j - x_i)_x d/dx W(x_i - x_j)
// with volume V per point (m^3): the factor by which the SPH gradient of a linear field differs
// from the exact one on that lattice (1 for a perfect quadrature).
double latticeGradientMoment(const Kernels& k, float dx, double volume);

}  // namespace sph::solver
