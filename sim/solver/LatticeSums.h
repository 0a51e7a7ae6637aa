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

// Largest eigenvalue of DFSPH's Jacobi iteration on the lattice (sim/solver/Dfsph.cpp: each pass
// adds alpha_i e_i to particle i's stiffness, alpha_i the inverse of the diagonal of the density
// change a stiffness makes). A stiffness field cos(q . x) changes the density by lambda(q) alpha^-1
// times itself, with
//   lambda(q) = |sum_j g_j sin(q . (x_j - x_i))|^2 / sum_j |g_j|^2,  g_j the spiky gradient at j,
// so a pass multiplies that part of the error by 1 - lambda(q). Read on a grid of q over the
// lattice's Brillouin zone (its cubic symmetry: 0 <= q_x <= q_y <= q_z <= pi / dx, 24 intervals;
// 0.1% below the maximum on a grid four times as fine). It grows with the support: 2 at 1-1.4
// spacings (six neighbours), 2.82 at 2, 4.19 at 2.5, 6.72 at 3, 14.4 at 4.
double latticeJacobiEigenvalue(const Kernels& k, float dx);

}  // namespace sph::solver
