// Phases neighbours (sort by cell, neighbour lists, thesis 3.1.2) and density
// (Eq 3.13 with the wall half-space), and the wall share both use.
#include "sph/solver.hpp"

#include <cmath>

#include "core/buffers.hpp"
#include "core/parallel.hpp"

namespace bakesim::sph {

void SphSolver::phase_neighbours() {
  // Verlet lists: search on the current positions only when some pair may
  // have come within the support since the last search; otherwise keep the
  // candidates closer than the support. After a restore, the candidates come
  // back from the anchors (already in cell order: the sort keeps the order).
  // Without a skin the search gives the lists themselves, every step.
  const bool search = skin_ <= 0 || !anchors_valid_ || moved_past_skin();
  anchors_moved_ = search;
  if (search || !candidates_valid_) {
    {
      ScopedPhase t(timers_, t_sort_);
      search_.sort_order(search ? x_ : anchor_, order_);
      particles_.permute(order_);
      if (search) anchor_ = x_, anchor_support_ = smoothing_;
    }
    ScopedPhase t(timers_, t_neigh_);
    NeighbourLists& found = skin_ > 0 ? candidates_ : lists_;
    if (adaptive_)
      search_.find(anchor_, anchor_support_, found, skin_);
    else
      search_.find(anchor_, found, skin_);
    candidates_valid_ = anchors_valid_ = skin_ > 0;
    searches_ += search;
  }
  if (skin_ > 0) {
    ScopedPhase t(timers_, t_neigh_);
    if (adaptive_)
      search_.keep_within(candidates_, x_, smoothing_, lists_);
    else
      search_.keep_within(candidates_, x_, lists_);
  }
  parallel_for(
      x_.size(), [&](std::size_t i) { ncount_[i] = static_cast<std::int32_t>(lists_.count(i)); }, 4096);
}

// Pairs closer than their support now were closer than support + skin at the
// anchors while 2·(largest displacement) + (largest growth of a support) < skin.
bool SphSolver::moved_past_skin() const {
  struct Reach {
    Real d2 = 0, growth = 0;
  };
  const Reach r = deterministic_reduce(
      x_.size(), Reach{},
      [&](std::size_t b, std::size_t e) {
        Reach out;
        for (std::size_t i = b; i < e; ++i) {
          const Vec3 d = pair_offset_of(x_[i], anchor_[i]);
          out.d2 = std::max(out.d2, d.squaredNorm());
          out.growth = std::max(out.growth, smoothing_[i] - anchor_support_[i]);
        }
        return out;
      },
      [](Reach a, Reach b) {
        return Reach{std::max(a.d2, b.d2), std::max(a.growth, b.growth)};
      });
  return 2.0 * std::sqrt(r.d2) + r.growth >= skin_;
}

// Eq 3.13, plus the mass of a wall half-space at rest density for particles
// near analytic walls (see docs/physics.md, "wall density correction").
void SphSolver::phase_density() {
  ScopedPhase t(timers_, t_density_);
  const bool wall_corr = setup_.settings.wall_density_correction;
  const Real w0 = kernel_.w(0.0);
  const Vec3* x = x_.data();
  const Real* m = m_.data();
  const std::size_t stride = lists_.stride();
  resize_with_headroom(pair_w_, x_.size() * stride);
  resize_with_headroom(pair_dwr_, x_.size() * stride);
  parallel_for(x_.size(), [&](std::size_t i) {
    Real rho = m[i] * w0;
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pr = lists_.distances(i);
    float* pw = pair_w_.data() + i * stride;
    float* pd = pair_dwr_.data() + i * stride;
    if (adaptive_) {
      // Eq 3.56: the pair's kernel has support (h_i + h_j)/2; the self term h_i.
      rho = m[i] * CubicSpline(smoothing_[i]).w(0.0);
      for (std::uint32_t k = 0; k < count; ++k) {
        const Real r = pr[k];
        const CubicSpline pair_kernel(0.5 * (smoothing_[i] + smoothing_[nb[k]]));
        const Real w = pair_kernel.w(r);
        rho += m[nb[k]] * w;
        pw[k] = static_cast<float>(w);
        pd[k] = static_cast<float>(r > 0 ? pair_kernel.dw_dr_over_r(r) : 0.0);
      }
    } else {
      for (std::uint32_t k = 0; k < count; ++k) {
        const Real r = pr[k];
        const Real w = kernel_.w(r);
        rho += m[nb[k]] * w;
        pw[k] = static_cast<float>(w);
        pd[k] = static_cast<float>(r > 0 ? kernel_.dw_dr_over_r(r) : 0.0);
      }
    }
    if (wall_corr) rho += setup_.materials[material_[i]].rest_density * wall_share(x[i], nullptr);
    rho_[i] = rho;
  });
}

Real SphSolver::wall_share(const Vec3& x, Vec3* gradient) const {
  // Few walls are ever within reach; keep their fractions on the stack.
  constexpr int kMax = 16;
  Real f[kMax];
  Vec3 n[kMax];
  Real df[kMax];
  int count = 0;
  for (std::size_t c = 0; c < walls_.size(); ++c)
    for_each_wall_of(c, x, h_, [&](const WallContact& w, const Vec3&) {
      if (count < kMax) {
        f[count] = wall_share_.fraction(w.distance);
        df[count] = wall_share_.slope(w.distance);
        n[count] = w.normal;
        ++count;
      }
    });
  if (gradient) gradient->setZero();
  if (count == 0) return 0.0;
  Real keep = 1.0;
  for (int k = 0; k < count; ++k) keep *= 1.0 - f[k];
  if (gradient)
    for (int k = 0; k < count; ++k) {
      Real others = 1.0;
      for (int l = 0; l < count; ++l)
        if (l != k) others *= 1.0 - f[l];
      // d f_k / dx = −slope(d_k) · n_k (d grows along the wall normal).
      *gradient -= others * df[k] * n[k];
    }
  return 1.0 - keep;
}

}  // namespace bakesim::sph
