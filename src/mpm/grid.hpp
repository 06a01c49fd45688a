#pragma once
// The MPM background grid: quadratic B-spline weights (spec 4.1), the node
// records the transfers fill, and the block order that lets P2G scatter in
// parallel without atomics.
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/parallel.hpp"
#include "core/types.hpp"

namespace bakesim::mpm {

// Quadratic B-spline weights along one axis for a particle at grid coordinate
// xi (in cells): nodes base, base+1, base+2 at offsets (x_node − x_p)/Δx = k − frac.
struct Axis {
  int base;
  Real frac;
  Real w[3];
};

inline Axis axis_weights(Real xi) {
  Axis a;
  a.base = static_cast<int>(std::floor(xi - 0.5));
  const Real f = xi - a.base;
  a.frac = f;
  a.w[0] = 0.5 * (1.5 - f) * (1.5 - f);
  a.w[1] = 0.75 - (f - 1.0) * (f - 1.0);
  a.w[2] = 0.5 * (f - 0.5) * (f - 0.5);
  return a;
}

// Grid contact: a node takes a collider's or wall's condition when its signed
// distance from the solid is below this many cells, so a face lying on a node
// plane acts the same whichever side of it round-off puts the node.
inline constexpr Real kNodeOnFace = 1e-3;

// Mass and momentum after P2G; the grid update replaces the momentum by the
// new velocity. Four doubles: one node is half a cache line.
struct GridNode {
  Real mass;
  Real mv[3];
};
// Heat and water sums a node receives in P2G (spec 4.1–4.3).
struct HeatSums {
  Real heat_capacity;  // M = Σ w m c, J/K
  Real energy;         // E = Σ w m c θ, J
  Real heat_rate;      // Q = Σ w S β (θ_amb − θ) − Σ V κ ∇θ · ∇w, W
  Real water;          // W = Σ w m_w, kg
  Real volume;         // Σ w V_p, m³
  Real water_rate;     // ΔW = −Σ w evaporation + Σ V q_w · ∇w, kg/s
  Real vapour;         // Σ w V_p ρ_v,p, kg (moisture: the node's vapour density times its volume)
  Real vapour_rate;    // ΔW_v = −Σ w m_surface + Σ V q_v · ∇w, kg/s (moves as vapour: carries h_fg)
};

// What the grid update leaves on a node for G2P and the implicit heat solve.
// G2P takes the first moments (gradients, the face's centroid) of the fields
// of the first two 4-lane vectors only (mpm/transfer.hpp): the last vector
// holds the fields it needs as sums alone.
struct HeatState {
  Real theta;           // θ after the step, °C
  Real saturation;      // s of the node, for the next water flux
  Real vapour_density;  // ρ_v of the node, for the next vapour flux, kg/m³
  Real air_area;        // area facing the air per volume, 1/m
  Real fill;            // φ = V / Δx³, the volume fraction whose level 1/2 is the face
  Real dtheta;          // Δθ of this step (FLIP increment), K
  Real exchange;        // Σ a β / V: boundary conductance per volume, W/(K m³)
  Real exchange_theta;  // Σ a β θ_out / V, W/m³
  Real exchange_area;   // Σ a / V over the faces that exchange (air and hot colliders), 1/m
  Real water_ratio;     // r = Δt ΔW / W (never below −1)
  Real vapour_ratio;    // r_v = Δt ΔW_v / W (r + r_v never below −1)
  Real unused = 0;      // pads the record to three 4-lane vectors (mpm/transfer.hpp)
};

// Particles grouped by blocks of kBlock³ cells, and the blocks coloured 2×2×2
// so that blocks of one colour never share a node: P2G runs each colour's
// blocks in parallel and scatters without races.
class BlockOrder {
 public:
  static constexpr int kBlock = 4;

  // Blocks over a grid of nx × ny × nz nodes.
  void resize(int nx, int ny, int nz);
  // Groups the particles by the block of their lowest stencil node (counting sort of an index array).
  void sort(const std::vector<Vec3>& x, const Vec3& origin, Real inv_dx);
  // The order is the identity (after the particle memory itself was permuted into it).
  void set_identity();
  // Lists the non-empty blocks of each colour.
  void colour();
  const std::vector<std::uint32_t>& order() const { return order_; }
  // Block of each colour, for tests: indices (i, j, k) of block b.
  void block_index(std::size_t b, std::size_t ijk[3]) const;
  const std::vector<std::vector<std::uint32_t>>& colour_blocks() const { return colour_blocks_; }

  // Calls fn(p, ax, ay, az) for every particle, colour by colour.
  template <class Fn>
  void for_each_by_colour(const std::vector<Vec3>& x, const Vec3& origin, Real inv_dx, Fn&& fn) const {
    for (const auto& blocks : colour_blocks_) {
      parallel_for(
          blocks.size(),
          [&](std::size_t bi) {
            const std::uint32_t b = blocks[bi];
            for (std::uint32_t k = block_start_[b]; k < block_start_[b + 1]; ++k) {
              const std::uint32_t p = order_[k];
              const Vec3 g = (x[p] - origin) * inv_dx;
              fn(p, axis_weights(g.x()), axis_weights(g.y()), axis_weights(g.z()));
            }
          },
          1);
    }
  }

 private:
  int bx_ = 0, by_ = 0, bz_ = 0;
  std::vector<std::uint32_t> order_;        // particle indices sorted by block
  std::vector<std::uint32_t> block_start_;  // per block, into order_ (size blocks + 1)
  std::vector<std::uint32_t> block_key_;
  std::vector<std::vector<std::uint32_t>> colour_blocks_;  // non-empty blocks per colour
  std::vector<std::uint32_t> block_fill_;                  // counting-sort cursors, reused
};

}  // namespace bakesim::mpm
