#include "geometry/open_space.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/parallel.hpp"

namespace bakesim {

void OpenSpaceGrid::build(const std::vector<Vec3>& positions, const std::vector<Real>& radii, Real cell) {
  cell_ = cell;
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    lo = lo.cwiseMin(positions[i] - Vec3::Constant(radii[i]));
    hi = hi.cwiseMax(positions[i] + Vec3::Constant(radii[i]));
  }
  if (positions.empty()) lo = hi = Vec3::Zero();
  // Two empty cells of margin on every side: the border is open and the flood starts there.
  origin_ = lo - Vec3::Constant(2 * cell);
  const Vec3 extent = hi - lo + Vec3::Constant(4 * cell);
  nx_ = std::int64_t(std::ceil(extent.x() / cell)) + 1;
  ny_ = std::int64_t(std::ceil(extent.y() / cell)) + 1;
  nz_ = std::int64_t(std::ceil(extent.z() / cell)) + 1;
  const std::size_t cells = std::size_t(nx_ * ny_ * nz_);
  built_ = cells <= kMaxCells;
  if (!built_) return;
  if (state_.capacity() < cells) state_.reserve(cells + cells / 2);  // slack: the cloud's box moves
  state_.assign(cells, kEmpty);
  if (queue_.capacity() < cells) queue_.reserve(state_.capacity());

  // Fill: every cell whose centre lies in a particle's ball.
  parallel_for(
      positions.size(),
      [&](std::size_t i) {
        const Vec3 p = (positions[i] - origin_) / cell;  // in cells; cell c spans [c, c+1)
        const Real r = radii[i] / cell, r2 = r * r;
        const std::int64_t x0 = std::max<std::int64_t>(0, std::int64_t(std::floor(p.x() - r - 0.5)));
        const std::int64_t x1 = std::min<std::int64_t>(nx_ - 1, std::int64_t(std::floor(p.x() + r - 0.5)) + 1);
        const std::int64_t y0 = std::max<std::int64_t>(0, std::int64_t(std::floor(p.y() - r - 0.5)));
        const std::int64_t y1 = std::min<std::int64_t>(ny_ - 1, std::int64_t(std::floor(p.y() + r - 0.5)) + 1);
        const std::int64_t z0 = std::max<std::int64_t>(0, std::int64_t(std::floor(p.z() - r - 0.5)));
        const std::int64_t z1 = std::min<std::int64_t>(nz_ - 1, std::int64_t(std::floor(p.z() + r - 0.5)) + 1);
        for (std::int64_t z = z0; z <= z1; ++z)
          for (std::int64_t y = y0; y <= y1; ++y)
            for (std::int64_t x = x0; x <= x1; ++x) {
              const Vec3 c(Real(x) + 0.5, Real(y) + 0.5, Real(z) + 0.5);
              if ((c - p).squaredNorm() > r2) continue;
              // Many particles write the same value to a cell: relaxed atomic stores keep it race-free.
              std::atomic_ref<std::uint8_t>(state_[std::size_t((z * ny_ + y) * nx_ + x)])
                  .store(kFilled, std::memory_order_relaxed);
            }
      },
      512);

  // Flood the empty cells from the border (the margin is empty, so the corner cell starts it).
  queue_.clear();
  queue_.push_back(0);
  state_[0] = kOpen;
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const std::int64_t k = queue_[head];
    const std::int64_t x = k % nx_, y = (k / nx_) % ny_, z = k / (nx_ * ny_);
    const std::int64_t steps[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const auto& s : steps) {
      const std::int64_t a = x + s[0], b = y + s[1], c = z + s[2];
      if (a < 0 || b < 0 || c < 0 || a >= nx_ || b >= ny_ || c >= nz_) continue;
      const std::int64_t j = (c * ny_ + b) * nx_ + a;
      if (state_[std::size_t(j)] != kEmpty) continue;
      state_[std::size_t(j)] = kOpen;
      queue_.push_back(j);
    }
  }
}

std::int64_t OpenSpaceGrid::index_of(const Vec3& x) const {
  const Vec3 p = (x - origin_) / cell_;
  const std::int64_t a = std::int64_t(std::floor(p.x())), b = std::int64_t(std::floor(p.y())),
                     c = std::int64_t(std::floor(p.z()));
  if (a < 0 || b < 0 || c < 0 || a >= nx_ || b >= ny_ || c >= nz_) return -1;
  return (c * ny_ + b) * nx_ + a;
}

bool OpenSpaceGrid::open_at(const Vec3& x) const {
  const std::int64_t k = built_ ? index_of(x) : -1;
  return k < 0 || state_[std::size_t(k)] == kOpen;
}

bool OpenSpaceGrid::open_along(const Vec3& x, const Vec3& dir, Real reach) const {
  const Real step = 0.5 * cell_;
  for (Real d = step; d <= reach + 1e-12 * cell_; d += step)
    if (open_at(x + d * dir)) return true;
  return false;
}

}  // namespace bakesim
