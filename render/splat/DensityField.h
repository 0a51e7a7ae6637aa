// The SPH density field of a particle set, as the renderer sees it (seed 003, sections 3-5):
//   D(x)      = sum_j m W_poly6(x - x_j)                       eq. (1) with A = rho, eq. (3)
//   gradC(x)  = sum_j m / rho_j gradW_poly6(x - x_j)           eq. (4): the splat normal, eq. (5)
// evaluated at the particles and at arbitrary points (the splat vertices of eq. (6), the
// reference ray-marcher). It has its own kernel radius (render.kernel_radius) and normalisation
// (the rest lattice reads rest_density: sim/solver/LatticeSums.h), independent of the solver's kernels.
//
// gradC points towards higher density, i.e. into the fluid; shading uses its opposite.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/solver/Kernels.h"
#include "sim/grid/NeighbourGrid.h"
#include "sim/Types.h"

namespace sph::render::splat {

class DensityField {
 public:
  // Builds the field of n particles (copied and sorted by cell). `spacing` is the particle
  // spacing of the simulation (m), `radius` the kernel radius in spacings.
  DensityField(const float* x, const float* y, const float* z, std::size_t n, float spacing,
               float radius, float restDensity = 1000.0f);

  std::size_t size() const { return x_.size(); }
  float kernelRadius() const { return kernels_.h; }  // m
  float spacing() const { return spacing_; }
  float restDensity() const { return restDensity_; }  // what the rest lattice reads (kg/m^3)

  // The mean density D over the particles, ID (each particle's own D: sortedDensity()).
  float meanDensity() const { return meanDensity_; }

  // D(p) and gradC(p) at an arbitrary point.
  float density(const Vec3& p) const;
  // D at `count` points (xs[i], y, z) of one line along x, sharing one neighbour search: the
  // candidates within the kernel radius of the line are gathered once (about 2.5x fewer kernel
  // evaluations than density() per point for 8 points 0.5 spacings apart; render/mesh). Equal
  // to density() up to the order of the sum (float rounding).
  void densityAlongX(const float* xs, int count, float y, float z, float* out) const;
  Vec3 gradient(const Vec3& p) const;
  void densityAndGradient(const Vec3& p, float& density, Vec3& gradient) const;
  // Also gradD(p) = sum_j m gradW_poly6(p - x_j), the gradient of the density itself.
  void densityAndGradients(const Vec3& p, float& density, Vec3& gradient,
                           Vec3& densityGradient) const;

  // D of a point just above a flat free surface of the rest lattice, as a fraction of the bulk:
  // the density a particle of the top layer sees (used for the automatic surface threshold).
  float flatSurfaceFraction() const { return flatSurfaceFraction_; }

  // The particles binned in cells of the kernel radius (sorted slots).
  const grid::NeighbourGrid& grid() const { return grid_; }

  const std::vector<float>& sortedX() const { return x_; }
  const std::vector<float>& sortedY() const { return y_; }
  const std::vector<float>& sortedZ() const { return z_; }
  const std::vector<float>& sortedDensity() const { return density_; }

 private:
  solver::Kernels kernels_;
  float spacing_ = 0, restDensity_ = 0, massNorm_ = 0;  // D = massNorm * sum poly6
  grid::NeighbourGrid grid_;
  std::vector<float> x_, y_, z_, density_, inverseDensity_;
  float meanDensity_ = 0, flatSurfaceFraction_ = 0;
};

}  // namespace sph::render::splat
