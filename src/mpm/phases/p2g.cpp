// Phase P2G: particle to grid transfer of mass, APIC momentum and the MLS
// stress force, and with heat the heat and water sums (spec 4.1–4.4).
#include "mpm/solver.hpp"

#include <cstddef>

#include "core/parallel.hpp"
#include "mpm/transfer.hpp"

namespace bakesim::mpm {

// Spec 4.1 and 4.4: m_i = Σ w m_p, (m v)_i = Σ w m_p (v_p + C_p (x_i − x_p))
// (APIC), and the stress force. The force uses the MLS-MPM gradient
// ∇w_ip ≈ w_ip D⁻¹ (x_i − x_p), D⁻¹ = 4/Δx² for quadratic B-splines, so it
// folds into the affine term: (m v)_i += w (m_p v_p + A_p (x_i − x_p)) with
// A_p = m_p C_p − Δt V⁰_p D⁻¹ τ_p (Hu et al. 2018, Eq. 16–17).
// With heat (spec 4.1–4.3): M_i = Σ w m c, E_i = Σ w m c θ, V_i = Σ w V_p,
// W_i = Σ w m_w and the rates Q_i = Σ w S β (θ_amb − θ) − Σ V κ ∇θ_p · ∇w_ip,
// ΔW_i = −Σ w E(θ) s S_air + Σ V q_w · ∇w_ip, with the same MLS gradient
// (∇w_ip = w (4/Δx) o, o the node offset in cells).
static_assert(offsetof(HeatSums, heat_capacity) == 0 && offsetof(HeatSums, water) == 3 * sizeof(Real) &&
                  offsetof(HeatSums, volume) == 4 * sizeof(Real) && offsetof(HeatSums, vapour_rate) == 7 * sizeof(Real),
              "P2G fills HeatSums as the lanes {M, E, Q, W | V, dW, V rho_v, dW_v}");

template <bool kThermal>
void MpmSolver::p2g(Real dt) {
  // The sums start from zero. HeatState is not cleared (half the bytes of a
  // clear of every node each step, about 8% of P2G's time at 600K points): the
  // grid update writes it on every node with mass, and G2P reads it only at
  // its particles' stencil nodes, which all have mass but for one of weight
  // exactly zero.
  parallel_for(
      grid_.size(),
      [&](std::size_t k) {
        grid_[k] = GridNode{0, {0, 0, 0}};
        if constexpr (kThermal) {
          heat_sums_[k] = HeatSums{};
          if (!implicit_mass_.empty()) implicit_mass_[k] = 0;
        }
      },
      1 << 14);
  const Vec3 origin = grid_origin_;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real d_inv = 4.0 * inv_dx_ * inv_dx_;
  const Real inertial_dt = setup_.mass_scaling.impulse_step(dt);
  GridNode* const grid = grid_.data();
  HeatSums* const sums = heat_sums_.data();
  blocks_.for_each_by_colour(x_, origin, inv_dx_, [&](std::uint32_t p, const Axis& ax, const Axis& ay, const Axis& az) {
    const Stencil st{ax, ay, az, nz, syz};
    const Real mp = m_[p];
    // A Δx, so that A (x_i − x_p) = (A Δx) · offset-in-cells. With mass
    // scaling the force's impulse is Δt/s (the inertia s m_p, the momentum
    // m_p v_p: the node's velocity gains Δt f / (s m)).
    const Real s = -inertial_dt * volume0_[p] * d_inv;
    const Vec3 td = tau_diag_[p], to = tau_off_[p];
    Real a[3][3];  // a[col][row]
    const Vec3 cc[3] = {c0_[p], c1_[p], c2_[p]};
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) a[col][row] = mp * cc[col][row];
    a[0][0] += s * td.x(), a[1][1] += s * td.y(), a[2][2] += s * td.z();
    a[1][0] += s * to.x(), a[0][1] += s * to.x();
    a[2][0] += s * to.y(), a[0][2] += s * to.y();
    a[2][1] += s * to.z(), a[1][2] += s * to.z();
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) a[col][row] *= dx_;
    // GridNode lanes {m, (m v)_x, (m v)_y, (m v)_z}: node += w ((m_p, m_p v_p) + (0, A Δx) o),
    // o the offset in cells (the mass has no affine part).
    scatter_affine(grid, st, {Lane4(mp, mp * v_[p].x(), mp * v_[p].y(), mp * v_[p].z())},
                   {Lane4(0, a[0][0], a[0][1], a[0][2])}, {Lane4(0, a[1][0], a[1][1], a[1][2])},
                   {Lane4(0, a[2][0], a[2][1], a[2][2])});
    if constexpr (kThermal) {
      // HeatSums lanes {M, E, Q, W | V, ΔW, V ρ_v, ΔW_v}: the heat, water and vapour
      // rates carry their flux terms q · ∇w as slopes in the offset.
      const Real volume = j_[p] * volume0_[p];
      const Vec3 q = heat_vec_[p], qw = water_vec_[p], qv = vapour_vec_[p];
      scatter_affine(sums, st,
                     {Lane4(heat_capacity_[p], heat_capacity_[p] * temperature_[p], heat_src_[p], water_[p]),
                      Lane4(volume, water_src_[p], volume * vapour_density_[p], vapour_src_[p])},
                     {Lane4(0, 0, q.x(), 0), Lane4(0, qw.x(), 0, qv.x())},
                     {Lane4(0, 0, q.y(), 0), Lane4(0, qw.y(), 0, qv.y())},
                     {Lane4(0, 0, q.z(), 0), Lane4(0, qw.z(), 0, qv.z())});
    }
  });
}

// The wall's traction at sticky planes. A node within a cell and a half of
// the plane has part of its stencil behind it, where no material is, so the
// stress force it gathers lacks the wall's share (the boundary term of the
// weak form, N_i σ n on the face): the wall held the nodes on and behind it
// but did not drag the first row in front of it, and the flow beside the
// plate ran fast (+3.7 mm/s at a wall stress of 500 Pa in the channel tests,
// whatever the rheology). Each particle within 1.5 Δx of the plane lends its
// stress to a ghost at its mirror image behind it, which adds its MLS force to
// the nodes in front of the plane only: the stress is continued evenly
// through the face (the shear stress beside a no-slip wall, whose velocity
// the grid continues oddly, mirror_sticky_planes, is even; so is the
// pressure). Ghosts carry no mass or momentum. The distances are found in
// parallel, the ghosts scattered serially: their stencils cross the
// colouring of the blocks, and only a layer of particles has one.
void MpmSolver::add_wall_ghost_stress(Real dt) {
  if (sticky_planes_.empty()) return;
  const Vec3 origin = grid_origin_;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real d_inv = 4.0 * inv_dx_ * inv_dx_, reach = 1.5 * dx_, on_face = kNodeOnFace * dx_;
  for (std::size_t ci : sticky_planes_) {
    // The plane at this step's pose, in world coordinates (its normal is unit).
    const WorldPlane plane = world_plane(ci, setup_.colliders[ci].motion.at(time_));
    const Vec3 n = plane.normal;
    ghost_distance_.resize(x_.size());
    parallel_for(x_.size(), [&](std::size_t p) {
      const Real d = plane.distance(x_[p]);
      ghost_distance_[p] = d > 0 && d < reach ? d : Real(0);
    });
    for (std::size_t p = 0; p < x_.size(); ++p) {
      if (ghost_distance_[p] == 0) continue;
      const Vec3 ghost = x_[p] - 2 * ghost_distance_[p] * n;
      const Vec3 g = (ghost - origin) * inv_dx_;
      const Axis ax = axis_weights(g.x()), ay = axis_weights(g.y()), az = axis_weights(g.z());
      const Real s = -setup_.mass_scaling.impulse_step(dt) * volume0_[p] * d_inv * dx_;
      const Vec3 td = tau_diag_[p], to = tau_off_[p];
      Mat3 tau;
      tau << td.x(), to.x(), to.y(), to.x(), td.y(), to.z(), to.y(), to.z(), td.z();
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          for (int k = 0; k < 3; ++k) {
            const long ix = long(ax.base) + i, iy = long(ay.base) + j, iz = long(az.base) + k;
            if (ix < 0 || iy < 0 || iz < 0 || ix >= nx_ || iy >= ny_ || iz >= nz_) continue;
            const Vec3 xi = origin + dx_ * Vec3(Real(ix), Real(iy), Real(iz));
            if (plane.distance(xi) < on_face) continue;  // on or behind the plane: set by the grid update
            const Vec3 offset(i - ax.frac, j - ay.frac, k - az.frac);
            const Vec3 f = (ax.w[i] * ay.w[j] * az.w[k] * s) * (tau * offset);
            GridNode& node = grid_[std::size_t(ix) * syz + std::size_t(iy) * nz + std::size_t(iz)];
            for (int r = 0; r < 3; ++r) node.mv[r] += f[r];
          }
    }
  }
}

void MpmSolver::phase_p2g(Real dt) {
  ScopedPhase t(timers_, t_p2g_);
  if (thermal()) {
    p2g<true>(dt);
    if (periodicity_.any()) {
      fold_periodic(heat_sums_, [](HeatSums& to, const HeatSums& from) {
        to.heat_capacity += from.heat_capacity, to.energy += from.energy, to.heat_rate += from.heat_rate;
        to.water += from.water, to.volume += from.volume, to.water_rate += from.water_rate;
        to.vapour += from.vapour, to.vapour_rate += from.vapour_rate;
      });
      copy_periodic(heat_sums_);
    }
    // What the boundary terms put in this step (spec 4.2, 4.3 bookkeeping).
    const Real dtb = setup_.oven.bake_step(dt);
    // (implicit heat books the energy its solve puts in)
    if (setup_.settings.heat == HeatMethod::explicit_)
      budget_.heat_in += dtb * deterministic_sum(x_.size(), [&](std::size_t i) { return heat_src_[i]; });
    budget_.evaporated -= dtb * deterministic_sum(x_.size(), [&](std::size_t i) { return water_src_[i]; });
    // Vapour leaving through the surface (its latent heat is booked where G2P takes it from the particles).
    if (moist_) budget_.evaporated -= dtb * deterministic_sum(x_.size(), [&](std::size_t i) { return vapour_src_[i]; });
  } else {
    p2g<false>(dt);
  }
  add_wall_ghost_stress(dt);  // after P2G cleared and filled the grid, before the periodic fold
  if (periodicity_.any()) {
    fold_periodic(grid_, [](GridNode& to, const GridNode& from) {
      to.mass += from.mass;
      for (int r = 0; r < 3; ++r) to.mv[r] += from.mv[r];
    });
    copy_periodic(grid_);
  }
}

}  // namespace bakesim::mpm
