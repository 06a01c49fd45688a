#pragma once
// Neighbour search (thesis 3.1.2). Two methods behind one result type:
//  - a uniform grid with cell size h; particles are sorted by cell (counting
//    sort), so each 3×3×3 block is nine contiguous runs of memory;
//  - a kd-tree (nanoflann).
// Lists hold, for each particle, the indices of the other particles closer
// than h (self excluded) and their distances, in ascending index order, in a fixed stride that
// grows when needed. The grid's cells are h/2 wide: fewer candidates per
// particle than h-wide cells.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "geometry/periodic.hpp"

namespace bakesim::sph {

enum class NeighbourMethod { grid, kdtree };

// Cell coordinate of a scaled position, clamped to [0, n); NaN maps to 0 and
// huge values to n − 1 (a float-to-int conversion out of range is undefined).
inline int clamp_cell(Real v, int n) {
  if (!(v >= 0)) return 0;
  if (v >= Real(n - 1)) return n - 1;
  return static_cast<int>(v);
}
NeighbourMethod parse_neighbour_method(const std::string& s);
std::string to_string(NeighbourMethod m);

class NeighbourLists {
 public:
  std::uint32_t count(std::size_t i) const { return count_[i]; }
  const std::uint32_t* begin(std::size_t i) const { return ids_.data() + i * stride_; }
  const std::uint32_t* end(std::size_t i) const { return begin(i) + count_[i]; }
  // Distances |x_i − x_j| of the same pairs, in the same order.
  const float* distances(std::size_t i) const { return dist_.data() + i * stride_; }
  std::size_t size() const { return count_.size(); }
  std::size_t stride() const { return stride_; }
  std::size_t max_count() const;
  double mean_count() const;
  static NeighbourLists from_lists(const std::vector<std::vector<std::uint32_t>>& lists);

 private:
  friend class NeighbourSearch;
  std::vector<std::uint32_t> ids_;
  std::vector<float> dist_;
  std::vector<std::uint32_t> count_;
  std::size_t stride_ = 64;
};

// Cell grid over a fixed box; particles outside are clamped to border cells.
class CellGrid {
 public:
  void configure(const Aabb& box, Real cell_size);
  // Stable counting sort by cell: fills `order` (new[i] = old[order[i]]) and
  // the cell ranges valid once positions are permuted by `order`.
  void sort(const std::vector<Vec3>& x, std::vector<std::uint32_t>& order);
  std::int64_t cell_of(const Vec3& p) const;
  void cell_coords(const Vec3& p, int& cx, int& cy, int& cz) const;
  // Calls fn(j) for every particle in cells that a sphere around p touches
  // (after sort()); candidates still need a distance test.
  template <class Fn>
  void for_each_within(const Vec3& p, Real radius, Fn&& fn) const;
  Real cell_size() const { return cell_; }

 private:
  Aabb box_;
  Real cell_ = 1, inv_cell_ = 1;
  int nx_ = 1, ny_ = 1, nz_ = 1;
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> cell_index_;
  std::vector<std::uint32_t> cell_fill_;  // the sort's next free slot per cell
};

class NeighbourSearch {
 public:
  NeighbourSearch(NeighbourMethod method, const Aabb& domain, Real support);
  NeighbourMethod method() const { return method_; }
  // Computes the order that sorts particles by cell (both methods use it for
  // memory locality). Call, permute the particles, then call find().
  void sort_order(const std::vector<Vec3>& x, std::vector<std::uint32_t>& order);
  // Fills lists for positions already permuted by the last sort_order():
  // the pairs closer than the support plus `skin` (0: the neighbours).
  void find(const std::vector<Vec3>& x, NeighbourLists& lists, Real skin = 0);
  // Variable support (Eq 3.56): j is a neighbour of i when |x_i − x_j| <
  // (h_i + h_j)/2 (+ skin), so lists stay symmetric. `support` is permuted with x.
  void find(const std::vector<Vec3>& x, const std::vector<Real>& support, NeighbourLists& lists, Real skin = 0);
  // Verlet lists (Verlet 1967): of candidates found with a skin on earlier
  // positions, keeps those closer than the support now, in candidate order
  // (so lists stay in ascending index order), with their distances. Exact
  // while every pair that is a neighbour now was a candidate: while twice the
  // largest displacement since the search plus the largest growth of a
  // support stays below the skin (the caller checks).
  void keep_within(const NeighbourLists& candidates, const std::vector<Vec3>& x, NeighbourLists& lists) const;
  void keep_within(const NeighbourLists& candidates, const std::vector<Vec3>& x, const std::vector<Real>& support,
                   NeighbourLists& lists) const;
  const CellGrid& grid() const { return grid_; }
  Real support() const { return h_; }
  // Along periodic axes, pairs are also found across the box faces (their
  // distance is the nearest image's). Positions must lie inside the box.
  void set_periodicity(const Periodicity& periodicity) { periodicity_ = periodicity; }
  // Calls fn(shift) for the zero shift and each whole-box shift that brings
  // an image of p within `radius` of the box: the queries to make at p + shift.
  template <class Fn>
  void for_each_image(const Vec3& p, Real radius, Fn&& fn) const;

 private:
  template <class Query>
  void fill(std::size_t n, NeighbourLists& lists, Query&& query);
  template <class Within>
  void keep(const NeighbourLists& candidates, const std::vector<Vec3>& x, NeighbourLists& lists, Within&& within) const;
  static void sort_lists(NeighbourLists& lists);
  NeighbourMethod method_;
  Real h_;
  CellGrid grid_;
  Periodicity periodicity_;
};

template <class Fn>
void NeighbourSearch::for_each_image(const Vec3& p, Real radius, Fn&& fn) const {
  fn(Vec3::Zero().eval());
  if (!periodicity_.any()) return;
  // Per axis: 0, or the one shift (±L) whose image lies within radius.
  Real shift[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    if (!periodicity_.along(k)) continue;
    const Real length = periodicity_.box.max[k] - periodicity_.box.min[k];
    if (p[k] - periodicity_.box.min[k] < radius)
      shift[k] = length;
    else if (periodicity_.box.max[k] - p[k] < radius)
      shift[k] = -length;
  }
  for (int mask = 1; mask < 8; ++mask) {
    Vec3 s = Vec3::Zero();
    bool valid = true;
    for (int k = 0; k < 3 && valid; ++k)
      if (mask & (1 << k)) {
        valid = shift[k] != 0;
        s[k] = shift[k];
      }
    if (valid) fn(s);
  }
}

// Reference O(N²) search, for tests.
NeighbourLists brute_force_neighbours(const std::vector<Vec3>& x, Real support);

template <class Fn>
void CellGrid::for_each_within(const Vec3& p, Real radius, Fn&& fn) const {
  // Visit only rows of cells (contiguous in memory after sort()) that the
  // sphere of the given radius touches, clipped in x to the sphere.
  auto cl = [](Real v, int n) { return clamp_cell(v, n); };
  const int x0 = cl((p.x() - radius - box_.min.x()) * inv_cell_, nx_);
  const int x1 = cl((p.x() + radius - box_.min.x()) * inv_cell_, nx_);
  const int y0 = cl((p.y() - radius - box_.min.y()) * inv_cell_, ny_);
  const int y1 = cl((p.y() + radius - box_.min.y()) * inv_cell_, ny_);
  const int z0 = cl((p.z() - radius - box_.min.z()) * inv_cell_, nz_);
  const int z1 = cl((p.z() + radius - box_.min.z()) * inv_cell_, nz_);
  const Real r2 = radius * radius;
  for (int z = z0; z <= z1; ++z) {
    // Border cells also hold particles clamped from outside the grid box, so
    // they reach to infinity on their outer side.
    const Real zlo = z == 0 ? -1e300 : box_.min.z() + z * cell_;
    const Real zhi = z == nz_ - 1 ? 1e300 : box_.min.z() + (z + 1) * cell_;
    const Real dz = std::max({0.0, zlo - p.z(), p.z() - zhi});
    for (int y = y0; y <= y1; ++y) {
      const Real ylo = y == 0 ? -1e300 : box_.min.y() + y * cell_;
      const Real yhi = y == ny_ - 1 ? 1e300 : box_.min.y() + (y + 1) * cell_;
      const Real dy = std::max({0.0, ylo - p.y(), p.y() - yhi});
      if (dy * dy + dz * dz >= r2) continue;
      const std::size_t row = std::size_t(nx_) * (std::size_t(y) + std::size_t(ny_) * z);
      const std::uint32_t b = cell_start_[row + x0], e = cell_start_[row + x1 + 1];
      for (std::uint32_t j = b; j < e; ++j) fn(j);
    }
  }
}

}  // namespace bakesim::sph
