#include "sim/solver/LatticeSums.h"

#include <algorithm>
#include <cmath>

namespace sph::solver {
namespace {

// Sum of term(a, b, c) over the lattice offsets within the kernel's reach, layers b <= maxLayer,
// in a fixed order (the sums above are exact to the last bit from run to run).
template <class Term>
double sumOverLattice(const Kernels& k, float dx, int maxLayer, Term&& term) {
  const int reach = static_cast<int>(std::ceil(k.h / dx));
  double sum = 0;
  for (int a = -reach; a <= reach; ++a)
    for (int b = -reach; b <= std::min(reach, maxLayer); ++b)
      for (int c = -reach; c <= reach; ++c) sum += term(a, b, c);
  return sum;
}

}  // namespace

double latticeKernelSum(const Kernels& k, scene::DensityKernel kernel, float dx, int maxLayer) {
  return sumOverLattice(k, dx, maxLayer, [&](int a, int b, int c) {
    const float r2 = dx * dx * static_cast<float>(a * a + b * b + c * c);
    return kernel == scene::DensityKernel::Spiky ? k.spiky(std::sqrt(r2)) : k.poly6(r2);
  });
}

double latticeGradientMoment(const Kernels& k, float dx, double volume) {
  const double sum = sumOverLattice(k, dx, kAllLayers, [&](int a, int b, int c) {
    const double xj = a * dx;
    const float r = dx * std::sqrt(static_cast<float>(a * a + b * b + c * c));
    // gradW(x_i - x_j) = s (x_i - x_j) with x_i = 0: its x component is -s xj.
    return volume * xj * (-k.spikyGradScale(r) * -xj);
  });
  return -sum;
}

}  // namespace sph::solver
