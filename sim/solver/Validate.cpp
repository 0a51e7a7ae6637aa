#include "sim/solver/Validate.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace sph::solver {

std::size_t firstNonFinite(const Particles& fluid) {
  const std::size_t n = fluid.size();
  std::size_t first = n;
  fluid.forEachField([&](const auto& field) {
    for (std::size_t i = 0; i < std::min(n, first); ++i) {
      if (!std::isfinite(static_cast<double>(field[i]))) first = i;
    }
  });
  return first;
}

std::string checkState(const Particles& fluid, std::uint32_t nextId) {
  const std::size_t n = fluid.size();
  std::ostringstream out;
  std::size_t field = 0;
  fluid.forEachField([&](const auto& values) {
    if (values.size() != n && out.tellp() == 0)
      out << "field " << field << " holds " << values.size() << " values for " << n << " particles";
    ++field;
  });
  if (out.tellp() != 0) return out.str();
  const std::size_t bad = firstNonFinite(fluid);
  if (bad < n) {
    out << "particle " << fluid.id[bad] << " has a non-finite field (position " << fluid.x[bad]
        << ", " << fluid.y[bad] << ", " << fluid.z[bad] << "; rho " << fluid.rho[bad] << ", p "
        << fluid.p[bad] << ", a " << fluid.ax[bad] << ", " << fluid.ay[bad] << ", " << fluid.az[bad]
        << ")";
    return out.str();
  }
  std::vector<bool> seen(nextId, false);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t id = fluid.id[i];
    if (id >= nextId) {
      out << "particle " << id << " has an id the run has not handed out yet (next " << nextId
          << ")";
      return out.str();
    }
    if (seen[id]) {
      out << "two particles have id " << id;
      return out.str();
    }
    seen[id] = true;
  }
  return "";
}

std::string checkDensity(const Particles& fluid, const DerivedParams& d,
                         scene::DensityKernel kernel) {
  float self = 0;
  withDensityShape(kernel, d.kernels, [&](auto shape, float factor) {
    self = factor * d.mass * d.densityNormalisation * shape(0.0f);
  });
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    const float rho = fluid.rho[i];
    // 1e-4: the pass sums in a different order and with approximate square roots.
    if (!std::isfinite(rho) || rho < self * (1 - 1e-4f)) {
      std::ostringstream out;
      out << "particle " << fluid.id[i] << " has density " << rho
          << " kg/m^3, less than its own contribution " << self;
      return out.str();
    }
  }
  return "";
}

}  // namespace sph::solver
