#pragma once
// The space open to the outside of a cloud of particles: which empty space an
// outer particle faces. Each particle fills a ball of its own size on a
// uniform grid; the empty cells that connect to the grid's border (a margin
// round the cloud's box) are open, the empty cells enclosed by filled ones are
// not (a void inside risen crumb holds no oven air). Used by SPH surface
// detection (docs/physics.md, "Surface particles"): a particle the colour test
// flags keeps its flag only if open space lies along its outward normal.
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace bakesim {

class OpenSpaceGrid {
 public:
  // Fill the grid of cell size `cell` from the particles at `positions`, each
  // filling the ball of radius `radii[i]` round it, and flood the empty cells
  // from the border. Buffers are kept between calls (no allocation once the
  // cloud's box stops growing).
  void build(const std::vector<Vec3>& positions, const std::vector<Real>& radii, Real cell);
  // A grid of more than this many cells is not built (a stray particle far
  // from the rest in a huge domain): every place then counts as open.
  static constexpr std::size_t kMaxCells = std::size_t(1) << 26;
  // Whether an open cell lies on the segment from x along the unit direction
  // `dir` up to `reach` (sampled every half cell).
  bool open_along(const Vec3& x, const Vec3& dir, Real reach) const;
  // Whether the cell holding x is open (outside the grid counts as open).
  bool open_at(const Vec3& x) const;

 private:
  enum : std::uint8_t { kEmpty = 0, kFilled = 1, kOpen = 2 };
  std::int64_t index_of(const Vec3& x) const;  // −1 outside the grid
  Vec3 origin_ = Vec3::Zero();
  Real cell_ = 1;
  bool built_ = false;
  std::int64_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint8_t> state_;
  std::vector<std::int64_t> queue_;
};

}  // namespace bakesim
