// Uniform-grid neighbour search (DESIGN.md, "Neighbour search"). Cells are cubes of edge
// cellSize >= h on the global lattice floor(x / cellSize), so two grids built over different
// point sets (the moving fluid, the static boundary) agree on which cell a point is in. A grid
// covers the bounding box of its points only, so memory follows the particles, not the domain.
//
// build() counting-sorts the points by cell (x fastest, then y, then z): after the caller applies
// the returned order, the 3 cells x-1..x+1 of one (y, z) row are one contiguous index range, and
// the 27 cells around a point are 9 ranges.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sph::grid {

using CellCoord = std::array<int, 3>;

class NeighbourGrid {
 public:
  // Bins n points into cells of edge `cellSize` (grown if the bounding box would need more than
  // `maxCells` cells; larger cells stay correct, only slower). Writes into `order` the stable
  // counting-sort permutation: sorted[i] = original[order[i]].
  void build(const float* x, const float* y, const float* z, std::size_t n, float cellSize,
             std::vector<std::uint32_t>& order, std::size_t maxCells = 0);
  // The cell size build() settles on for n points in the box [lo, hi]: `cellSize`, grown while
  // the box would need more than maxCells cells (0: max(8 n, 2^20)). A distributed run's ranks
  // call it with the global box and count so they all build the single process's lattice.
  static float cellSizeFor(const float lo[3], const float hi[3], std::size_t n, float cellSize,
                           std::size_t maxCells = 0);
  // No growth: build(..., kExactCellSize) uses the cell size it is given.
  static constexpr std::size_t kExactCellSize = ~std::size_t(0);

  // The invariants build() establishes, for the points it was given and the order it returned:
  // the cell ranges tile [0, n) in cell order, `order` is a permutation, the point at each sorted
  // slot lies in the cell whose range holds that slot (so every point is in exactly one cell),
  // and within a cell the original order is kept (a stable sort). "" when they hold, else the
  // first violation. Run after every build in SPH_VALIDATE builds (sim/Assert.h).
  std::string checkSorted(const float* x, const float* y, const float* z, std::size_t n,
                          const std::vector<std::uint32_t>& order) const;

  float cellSize() const { return cellSize_; }
  std::size_t cellCount() const { return cellStart_.empty() ? 0 : cellStart_.size() - 1; }
  std::size_t pointCount() const { return cellStart_.empty() ? 0 : cellStart_.back(); }
  CellCoord dims() const { return {nx_, ny_, nz_}; }
  CellCoord origin() const { return {ox_, oy_, oz_}; }

  // Global cell of a position, computed in double so the cell never depends on rounding.
  CellCoord cellOf(float px, float py, float pz) const {
    return {static_cast<int>(std::floor(static_cast<double>(px) * invCell_)),
            static_cast<int>(std::floor(static_cast<double>(py) * invCell_)),
            static_cast<int>(std::floor(static_cast<double>(pz) * invCell_))};
  }

  // Index range [begin, end) of sorted points in local cell (i, j, k) (no bounds check).
  std::uint32_t cellBegin(std::size_t localCell) const { return cellStart_[localCell]; }
  std::uint32_t cellEnd(std::size_t localCell) const { return cellStart_[localCell + 1]; }
  std::size_t localIndex(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(nx_) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(ny_) * k);
  }
  // Global coordinate of a local cell index.
  CellCoord globalOf(std::size_t localCell) const {
    const int i = static_cast<int>(localCell % nx_);
    const int j = static_cast<int>((localCell / nx_) % ny_);
    const int k = static_cast<int>(localCell / (static_cast<std::size_t>(nx_) * ny_));
    return {ox_ + i, oy_ + j, oz_ + k};
  }

  // Calls visit(begin, end) for each non-empty x-row range of the cells that intersect the box
  // [lo, hi] (m).
  template <class Visit>
  void forEachRangeInBox(const float lo[3], const float hi[3], Visit&& visit) const {
    if (cellStart_.empty()) return;
    const CellCoord a = cellOf(lo[0], lo[1], lo[2]), b = cellOf(hi[0], hi[1], hi[2]);
    const int i0 = std::max(a[0] - ox_, 0), i1 = std::min(b[0] - ox_, nx_ - 1);
    const int j0 = std::max(a[1] - oy_, 0), j1 = std::min(b[1] - oy_, ny_ - 1);
    const int k0 = std::max(a[2] - oz_, 0), k1 = std::min(b[2] - oz_, nz_ - 1);
    if (i0 > i1) return;
    for (int k = k0; k <= k1; ++k) {
      for (int j = j0; j <= j1; ++j) {
        const std::uint32_t begin = cellStart_[localIndex(i0, j, k)];
        const std::uint32_t end = cellStart_[localIndex(i1, j, k) + 1];
        if (begin < end) visit(begin, end);
      }
    }
  }

  // Calls visit(begin, end) for each non-empty x-row range of the 3x3x3 cells around global cell
  // g (at most 9 calls). Points outside the grid's box simply find fewer cells.
  template <class Visit>
  void forEachNeighbourRange(const CellCoord& g, Visit&& visit) const {
    if (cellStart_.empty()) return;
    const int i0 = std::max(g[0] - 1 - ox_, 0), i1 = std::min(g[0] + 1 - ox_, nx_ - 1);
    if (i0 > i1) return;
    for (int dk = -1; dk <= 1; ++dk) {
      const int k = g[2] + dk - oz_;
      if (k < 0 || k >= nz_) continue;
      for (int dj = -1; dj <= 1; ++dj) {
        const int j = g[1] + dj - oy_;
        if (j < 0 || j >= ny_) continue;
        const std::uint32_t begin = cellStart_[localIndex(i0, j, k)];
        const std::uint32_t end = cellStart_[localIndex(i1, j, k) + 1];
        if (begin < end) visit(begin, end);
      }
    }
  }

 private:
  float cellSize_ = 0;
  double invCell_ = 0;
  int ox_ = 0, oy_ = 0, oz_ = 0;  // global coordinate of local cell (0, 0, 0)
  int nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint32_t> cellStart_;    // cellCount + 1 prefix sums
  std::vector<std::uint32_t> cellOfPoint_;  // scratch: local cell of each unsorted point
  std::vector<std::uint32_t> cursor_;       // scratch: next free slot per cell while scattering
};

// The neighbour predicate shared by tests and non-hot code: |xi - xj| < h with the coordinate
// differences taken in float (as the solver does) and the squares summed in double, where float
// products are exact, so the answer never depends on FMA contraction.
inline bool withinRadius(float dx, float dy, float dz, float h) {
  const double r2 =
      static_cast<double>(dx) * dx + static_cast<double>(dy) * dy + static_cast<double>(dz) * dz;
  return r2 < static_cast<double>(h) * h;
}

}  // namespace sph::grid
