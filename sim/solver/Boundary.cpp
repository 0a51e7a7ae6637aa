#include "sim/solver/Boundary.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/solver/Kernels.h"
#include "sim/scene/Solid.h"

namespace sph::solver {
namespace {

// Number of lattice cells of about `spacing` that fit in [a, b], at least 1.
int cellsAlong(float a, float b, float spacing) {
  return std::max(1, static_cast<int>(std::lround((b - a) / spacing)));
}

// Tank (fluid inside) or Block (fluid outside): lattice points of the box grown by `layers`
// (Tank) or of the box itself (Block), keeping those within `layers` cells of a fluid-facing face.
void sampleBox(const scene::BoundaryShape& s, float spacing, int layers, std::vector<Vec3>& out) {
  const bool tank = s.kind == scene::BoundaryShape::Kind::Tank;
  int n[3];
  float step[3];
  for (int a = 0; a < 3; ++a) {
    n[a] = cellsAlong(s.lo[a], s.hi[a], spacing);
    step[a] = (s.hi[a] - s.lo[a]) / n[a];  // fitted so the lattice meets both faces
  }
  const int grow = tank ? layers : 0;
  for (int k = -grow; k < n[2] + grow; ++k) {
    for (int j = -grow; j < n[1] + grow; ++j) {
      if (tank && s.openTop && j >= n[1]) continue;  // no lid
      for (int i = -grow; i < n[0] + grow; ++i) {
        const int c[3] = {i, j, k};
        bool keep;
        if (tank) {
          keep = false;  // outside the interior on some axis
          for (int a = 0; a < 3; ++a) keep = keep || c[a] < 0 || c[a] >= n[a];
        } else {
          int depth = std::numeric_limits<int>::max();  // cells to the nearest face
          for (int a = 0; a < 3; ++a) depth = std::min({depth, c[a], n[a] - 1 - c[a]});
          keep = depth < layers;
        }
        if (keep) {
          out.emplace_back(s.lo.x() + (i + 0.5f) * step[0], s.lo.y() + (j + 0.5f) * step[1],
                           s.lo.z() + (k + 0.5f) * step[2]);
        }
      }
    }
  }
}

// Open-top cylinder: rings for the wall (also below the floor, to close the corner) and a square
// lattice for the floor inside the inner radius.
void sampleCup(const scene::BoundaryShape& s, float spacing, int layers, std::vector<Vec3>& out) {
  const Vec3 c = s.centre;
  const int wallCells = cellsAlong(0, s.height, spacing);
  const float dy = s.height / wallCells;
  for (int layer = 0; layer < layers; ++layer) {
    const float r = s.radius + (layer + 0.5f) * spacing;
    const int around = std::max(6, static_cast<int>(std::lround(2 * kPi * r / spacing)));
    for (int j = -layers; j < wallCells; ++j) {
      const float y = c.y() + (j + 0.5f) * (j < 0 ? spacing : dy);
      const float phase = (j & 1) ? 0.5f : 0.0f;  // stagger rings so columns do not line up
      for (int a = 0; a < around; ++a) {
        const float phi = static_cast<float>(2 * kPi) * (a + phase) / around;
        out.emplace_back(c.x() + r * std::cos(phi), y, c.z() + r * std::sin(phi));
      }
    }
  }
  const int half = static_cast<int>(std::ceil(s.radius / spacing));
  for (int layer = 0; layer < layers; ++layer) {
    const float y = c.y() - (layer + 0.5f) * spacing;
    for (int k = -half; k < half; ++k) {
      for (int i = -half; i < half; ++i) {
        const float px = (i + 0.5f) * spacing, pz = (k + 0.5f) * spacing;
        if (px * px + pz * pz < s.radius * s.radius) out.emplace_back(c.x() + px, y, c.z() + pz);
      }
    }
  }
}

// Infinite plane: a lattice in the plane over the domain's shadow, `layers` deep.
void samplePlane(const scene::BoundaryShape& s, const Aabb& domain, float spacing, int layers,
                 std::vector<Vec3>& out) {
  const scene::PlanePatch patch = planeOverDomain(s, domain);
  const Vec3 &n = patch.n, &t1 = patch.t1, &t2 = patch.t2;
  const int i0 = static_cast<int>(std::floor(patch.lo1 / spacing)) - 1;
  const int i1 = static_cast<int>(std::ceil(patch.hi1 / spacing)) + 1;
  const int k0 = static_cast<int>(std::floor(patch.lo2 / spacing)) - 1;
  const int k1 = static_cast<int>(std::ceil(patch.hi2 / spacing)) + 1;
  for (int layer = 0; layer < layers; ++layer) {
    for (int k = k0; k < k1; ++k) {
      for (int i = i0; i < i1; ++i) {
        out.push_back(s.point + ((i + 0.5f) * spacing) * t1 + ((k + 0.5f) * spacing) * t2 -
                      ((layer + 0.5f) * spacing) * n);
      }
    }
  }
}

// Solid sphere: Fibonacci-spiral shells inside the surface.
void sampleSphere(const scene::BoundaryShape& s, float spacing, int layers,
                  std::vector<Vec3>& out) {
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int layer = 0; layer < layers; ++layer) {
    const double r = s.radius - (layer + 0.5) * spacing;
    if (r <= 0) break;
    const int count =
        std::max(1, static_cast<int>(std::lround(4 * kPi * r * r / (spacing * spacing))));
    for (int i = 0; i < count; ++i) {
      const double yy = 1.0 - 2.0 * (i + 0.5) / count;
      const double ring = std::sqrt(std::max(0.0, 1.0 - yy * yy));
      const double phi = golden * i;
      out.emplace_back(s.centre + Vec3(static_cast<float>(r * ring * std::cos(phi)),
                                       static_cast<float>(r * yy),
                                       static_cast<float>(r * ring * std::sin(phi))));
    }
  }
}

}  // namespace

std::vector<Vec3> sampleBoundaryShape(const scene::BoundaryShape& shape, const Aabb& domain,
                                      float spacing, int layers) {
  std::vector<Vec3> out;
  switch (shape.kind) {
    case scene::BoundaryShape::Kind::Tank:
    case scene::BoundaryShape::Kind::Block:
      sampleBox(shape, spacing, layers, out);
      break;
    case scene::BoundaryShape::Kind::Cup:
      sampleCup(shape, spacing, layers, out);
      break;
    case scene::BoundaryShape::Kind::Plane:
      samplePlane(shape, domain, spacing, layers, out);
      break;
    case scene::BoundaryShape::Kind::Sphere:
      sampleSphere(shape, spacing, layers, out);
      break;
  }
  return out;
}

double countBoundarySamples(const scene::BoundaryShape& s, const Aabb& domain, float spacing,
                            int layers) {
  switch (s.kind) {
    case scene::BoundaryShape::Kind::Tank:
    case scene::BoundaryShape::Kind::Block: {  // sampleBox(): the kept cells of its lattice, in
                                               // closed
                                               // form
      double n[3];
      for (int a = 0; a < 3; ++a) n[a] = cellsAlong(s.lo[a], s.hi[a], spacing);
      if (s.kind == scene::BoundaryShape::Kind::Block) {
        double inner = 1;
        for (int a = 0; a < 3; ++a) inner *= std::max(0.0, n[a] - 2.0 * layers);
        return n[0] * n[1] * n[2] - inner;
      }
      const double g = layers;
      const double rows = s.openTop ? n[1] + g : n[1] + 2 * g;
      return (n[0] + 2 * g) * rows * (n[2] + 2 * g) - n[0] * n[1] * n[2];
    }
    case scene::BoundaryShape::Kind::Cup: {  // sampleCup(): rings, then the floor's disc
      const double wallCells = cellsAlong(0, s.height, spacing);
      double count = 0;
      for (int layer = 0; layer < layers; ++layer) {
        const double r = s.radius + (layer + 0.5) * spacing;
        count += std::max(6.0, std::round(2 * kPi * r / spacing)) * (wallCells + layers);
      }
      return count + layers * kPi * s.radius * s.radius / (double(spacing) * spacing);
    }
    case scene::BoundaryShape::Kind::Plane: {  // samplePlane(): the domain's shadow, `layers` deep
      const Vec3 d = domain.hi - domain.lo;
      const double diagonal = d.norm() / spacing + 4;
      return layers * diagonal * diagonal;
    }
    case scene::BoundaryShape::Kind::Sphere: {  // sampleSphere(): one shell per layer
      double count = 0;
      for (int layer = 0; layer < layers; ++layer) {
        const double r = s.radius - (layer + 0.5) * spacing;
        if (r <= 0) break;
        count += std::max(1.0, std::round(4 * kPi * r * r / (double(spacing) * spacing)));
      }
      return count;
    }
  }
  return 0;
}

Boundary::Boundary(const std::vector<scene::BoundaryShape>& shapes, const Aabb& domain,
                   float spacing, int layers, float supportRadius)
    : spacing_(spacing), layers_(layers) {
  Aabb reach = domain;
  reach.lo -= Vec3::Constant(supportRadius);
  reach.hi += Vec3::Constant(supportRadius);
  std::vector<Vec3> samples;
  for (const scene::BoundaryShape& shape : shapes) {
    solids_.emplace_back(shape, layers * spacing);
    for (const Vec3& p : sampleBoundaryShape(shape, domain, spacing, layers)) {
      if (reach.contains(p)) samples.push_back(p);
    }
  }
  std::vector<float> x(samples.size()), y(samples.size()), z(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    x[i] = samples[i].x(), y[i] = samples[i].y(), z[i] = samples[i].z();
  }
  std::vector<std::uint32_t> order;
  grid_.build(x.data(), y.data(), z.data(), samples.size(), supportRadius, order);
  particles_.x.resize(samples.size());
  particles_.y.resize(samples.size());
  particles_.z.resize(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    particles_.x[i] = x[order[i]], particles_.y[i] = y[order[i]], particles_.z[i] = z[order[i]];
  }
}

float Boundary::distance(const Vec3& p) const {
  float d = std::numeric_limits<float>::infinity();
  for (const scene::Solid& s : solids_) d = std::min(d, s.distance(p));
  return d;
}

bool Boundary::enforce(const Vec3& xOld, Vec3& xNew, Vec3& v) const {
  bool moved = false;
  const float step = 0.5f * std::max(1, layers_) * spacing_;
  for (const scene::Solid& s : solids_) moved |= keepOutside(s, xOld, xNew, v, step);
  return moved;
}

}  // namespace sph::solver
