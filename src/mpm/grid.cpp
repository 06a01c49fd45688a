#include "mpm/grid.hpp"

#include <algorithm>

namespace bakesim::mpm {

void BlockOrder::resize(int nx, int ny, int nz) {
  bx_ = (nx + kBlock - 1) / kBlock;
  by_ = (ny + kBlock - 1) / kBlock;
  bz_ = (nz + kBlock - 1) / kBlock;
}

void BlockOrder::sort(const std::vector<Vec3>& x, const Vec3& origin, Real inv_dx) {
  const std::size_t n = x.size();
  const std::size_t blocks = std::size_t(bx_) * by_ * bz_;
  block_key_.resize(n);
  parallel_for(
      n,
      [&](std::size_t i) {
        const Vec3 g = (x[i] - origin) * inv_dx;
        int c[3];
        for (int d = 0; d < 3; ++d) c[d] = std::max(0, static_cast<int>(std::floor(g[d] - 0.5))) / kBlock;
        c[0] = std::min(c[0], bx_ - 1);
        c[1] = std::min(c[1], by_ - 1);
        c[2] = std::min(c[2], bz_ - 1);
        block_key_[i] = static_cast<std::uint32_t>((std::size_t(c[0]) * by_ + c[1]) * bz_ + c[2]);
      },
      4096);
  block_start_.assign(blocks + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++block_start_[block_key_[i] + 1];
  for (std::size_t b = 0; b < blocks; ++b) block_start_[b + 1] += block_start_[b];
  order_.resize(n);
  block_fill_.assign(block_start_.begin(), block_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order_[block_fill_[block_key_[i]]++] = static_cast<std::uint32_t>(i);
}

void BlockOrder::set_identity() {
  for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<std::uint32_t>(i);
}

void BlockOrder::block_index(std::size_t b, std::size_t ijk[3]) const {
  ijk[2] = b % bz_;
  ijk[1] = (b / bz_) % by_;
  ijk[0] = b / (std::size_t(bz_) * by_);
}

void BlockOrder::colour() {
  const std::size_t blocks = std::size_t(bx_) * by_ * bz_;
  colour_blocks_.resize(8);
  // Each list holds at most the blocks of its parity, reserved once: a body that grows into new blocks
  // (a rising loaf) then takes no allocation in a later step.
  const std::size_t most = std::size_t((bx_ + 1) / 2) * ((by_ + 1) / 2) * ((bz_ + 1) / 2);
  for (auto& list : colour_blocks_) {
    list.clear();  // keeps their capacity: no allocation per step
    list.reserve(most);
  }
  for (std::size_t b = 0; b < blocks; ++b) {
    if (block_start_[b] == block_start_[b + 1]) continue;
    std::size_t ijk[3];
    block_index(b, ijk);
    colour_blocks_[(ijk[0] & 1) | ((ijk[1] & 1) << 1) | ((ijk[2] & 1) << 2)].push_back(static_cast<std::uint32_t>(b));
  }
}

}  // namespace bakesim::mpm
