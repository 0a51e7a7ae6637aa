#include "sim/solver/LatticeSums.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

double latticeJacobiEigenvalue(const Kernels& k, float dx) {
  struct Neighbour {
    double d[3], g[3];
  };
  std::vector<Neighbour> neighbours;
  double diagonal = 0;
  sumOverLattice(k, dx, kAllLayers, [&](int a, int b, int c) {
    const float r = dx * std::sqrt(static_cast<float>(a * a + b * b + c * c));
    const double s = k.spikyGradScale(r);  // 0 at the centre and outside the support
    if (s == 0) return 0.0;
    const Neighbour n{{double(a), double(b), double(c)}, {s * a, s * b, s * c}};
    diagonal += n.g[0] * n.g[0] + n.g[1] * n.g[1] + n.g[2] * n.g[2];
    neighbours.push_back(n);
    return 0.0;
  });
  if (diagonal == 0) return 0;
  constexpr int kIntervals = 24;
  double largest = 0;
  for (int u = 0; u <= kIntervals; ++u)
    for (int v = u; v <= kIntervals; ++v)
      for (int w = v; w <= kIntervals; ++w) {
        const double q[3] = {kPi * u / kIntervals, kPi * v / kIntervals, kPi * w / kIntervals};
        double sx = 0, sy = 0, sz = 0;
        for (const Neighbour& n : neighbours) {
          const double phase = std::sin(q[0] * n.d[0] + q[1] * n.d[1] + q[2] * n.d[2]);
          sx += phase * n.g[0], sy += phase * n.g[1], sz += phase * n.g[2];
        }
        largest = std::max(largest, (sx * sx + sy * sy + sz * sz) / diagonal);
      }
  return largest;
}

}  // namespace sph::solver
