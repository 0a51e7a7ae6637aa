#include "sim/grid/NeighbourGrid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "sim/Assert.h"
#include "sim/Parallel.h"

namespace sph::grid {

void NeighbourGrid::build(const float* x, const float* y, const float* z, std::size_t n,
                          float cellSize, std::vector<std::uint32_t>& order, std::size_t maxCells) {
  SPH_ASSERT(cellSize > 0);
  order.resize(n);
  if (n == 0) {
    cellStart_.clear();  // no cells: every query finds nothing
    nx_ = ny_ = nz_ = 0;
    ox_ = oy_ = oz_ = 0;
    cellSize_ = cellSize;
    invCell_ = 1.0 / cellSize;
    return;
  }
  // Bounding box. Min/max are exact operations, so the serial loop's result equals any split.
  float lo[3] = {x[0], y[0], z[0]}, hi[3] = {x[0], y[0], z[0]};
  for (std::size_t i = 1; i < n; ++i) {
    lo[0] = std::min(lo[0], x[i]), hi[0] = std::max(hi[0], x[i]);
    lo[1] = std::min(lo[1], y[i]), hi[1] = std::max(hi[1], y[i]);
    lo[2] = std::min(lo[2], z[i]), hi[2] = std::max(hi[2], z[i]);
  }
  cellSize = cellSizeFor(lo, hi, n, cellSize, maxCells);
  cellSize_ = cellSize;
  invCell_ = 1.0 / static_cast<double>(cellSize);
  const CellCoord a = cellOf(lo[0], lo[1], lo[2]), b = cellOf(hi[0], hi[1], hi[2]);
  ox_ = a[0], oy_ = a[1], oz_ = a[2];
  nx_ = b[0] - a[0] + 1, ny_ = b[1] - a[1] + 1, nz_ = b[2] - a[2] + 1;
  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_ * nz_;
  SPH_ASSERT(n < std::numeric_limits<std::uint32_t>::max());

  cellOfPoint_.resize(n);
  parallelFor(n, [&](std::size_t i) {
    const CellCoord g = cellOf(x[i], y[i], z[i]);
    cellOfPoint_[i] = static_cast<std::uint32_t>(localIndex(g[0] - ox_, g[1] - oy_, g[2] - oz_));
  });

  // Counting sort: histogram, exclusive prefix sum, stable scatter.
  cellStart_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++cellStart_[cellOfPoint_[i] + 1];
  for (std::size_t c = 0; c < cells; ++c) cellStart_[c + 1] += cellStart_[c];
  cursor_.assign(cellStart_.begin(), cellStart_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    order[cursor_[cellOfPoint_[i]]++] = static_cast<std::uint32_t>(i);
  }
  validate("the neighbour grid's sort", [&] { return checkSorted(x, y, z, n, order); });
}

float NeighbourGrid::cellSizeFor(const float lo[3], const float hi[3], std::size_t n,
                                 float cellSize, std::size_t maxCells) {
  if (maxCells == 0) maxCells = std::max<std::size_t>(8 * n, std::size_t(1) << 20);
  // Grow the cell until the box fits in maxCells cells (a spray of a few particles must not
  // allocate a grid the size of the sky).
  for (;;) {
    const double inv = 1.0 / static_cast<double>(cellSize);
    double cells = 1;
    for (int a = 0; a < 3; ++a) {
      const int from = static_cast<int>(std::floor(static_cast<double>(lo[a]) * inv));
      const int to = static_cast<int>(std::floor(static_cast<double>(hi[a]) * inv));
      cells *= static_cast<double>(to - from + 1);
    }
    if (cells <= static_cast<double>(maxCells)) return cellSize;
    cellSize *= static_cast<float>(std::cbrt(cells / static_cast<double>(maxCells))) * 1.01f;
  }
}

std::string NeighbourGrid::checkSorted(const float* x, const float* y, const float* z,
                                       std::size_t n,
                                       const std::vector<std::uint32_t>& order) const {
  std::ostringstream out;
  if (order.size() != n || pointCount() != n) {
    out << "the grid holds " << pointCount() << " points and the order " << order.size() << ", for "
        << n << " points";
    return out.str();
  }
  std::vector<bool> seen(n, false);
  for (std::size_t c = 0; c < cellCount(); ++c) {
    if (cellBegin(c) > cellEnd(c)) {
      out << "cell " << c << " ends before it begins";
      return out.str();
    }
    const CellCoord g = globalOf(c);
    for (std::uint32_t s = cellBegin(c); s < cellEnd(c); ++s) {
      const std::uint32_t i = order[s];
      if (i >= n || seen[i]) {
        out << "sorted slot " << s << " holds point " << i
            << (i >= n ? ", past the end" : ", which another slot holds too");
        return out.str();
      }
      seen[i] = true;
      if (cellOf(x[i], y[i], z[i]) != g) {
        out << "point " << i << " at (" << x[i] << ", " << y[i] << ", " << z[i]
            << ") is sorted into cell (" << g[0] << ", " << g[1] << ", " << g[2]
            << "), not its own";
        return out.str();
      }
      if (s > cellBegin(c) && order[s - 1] > i) {
        out << "points " << order[s - 1] << " and " << i << " swapped order in cell " << c;
        return out.str();
      }
    }
  }
  return "";
}

}  // namespace sph::grid
