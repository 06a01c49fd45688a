// Phase G2P: grid to particle transfer of velocity and the APIC affine field,
// the trial deformation gradient, the move, push-out of thin colliders, and with
// heat the FLIP temperature, water and the boundary share (spec 4.2, 4.3, 4.5).
#include "mpm/solver.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cstddef>
#include <limits>

#include "core/parallel.hpp"
#include "mpm/transfer.hpp"

namespace bakesim::mpm {

static_assert(offsetof(HeatState, theta) < 8 * sizeof(Real) && offsetof(HeatState, saturation) < 8 * sizeof(Real) &&
                  offsetof(HeatState, vapour_density) < 8 * sizeof(Real) &&
                  offsetof(HeatState, air_area) < 8 * sizeof(Real) && offsetof(HeatState, fill) < 8 * sizeof(Real),
              "G2P takes the moments of HeatState's first two vectors only: the fields whose gradients it reads");

// Spec 4.5: v_p = Σ w v_i, C_p = D⁻¹ Σ w v_i (x_i − x_p)ᵀ (D = Δx²/4 for
// quadratic B-splines); C_p is also the MLS velocity gradient, so the trial
// F = (I + Δt C_p) F; x += Δt v_p.
// With heat: θ_p += Σ w Δθ_i (FLIP), ∇θ_p = D⁻¹ Σ w θ_i (x_i − x_p) and
// ∇s_p likewise for the next step's fluxes, m_w ← m_w (1 + Σ w r_i)
// (spec 4.2), and the particle's share of the boundary: S β = V_p Σ w k_i.
template <bool kThermal>
void MpmSolver::g2p(Real dt) {
  const Vec3 origin = grid_origin_;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real d_inv = 4.0 * inv_dx_;  // D⁻¹ (x_i − x_p) with offsets in cells: 4/Δx² · Δx
  const Aabb domain = setup_.domain;
  const bool periodic = periodicity_.any();
  const GridNode* const grid = grid_.data();
  const HeatState* const heat = heat_state_.data();
  if constexpr (kThermal) face_depth_.resize(x_.size());
  parallel_for(
      x_.size(),
      [&](std::size_t p) {
        const Vec3 g = (x_[p] - origin) * inv_dx_;
        const Stencil st{axis_weights(g.x()), axis_weights(g.y()), axis_weights(g.z()), nz, syz};
        // GridNode lanes after the grid update: {m, v_x, v_y, v_z}; lane 0 unused.
        const StencilMoments<1> mv = gather_moments<1>(grid, st);
        const Vec3 vp(mv.sum[0][1], mv.sum[0][2], mv.sum[0][3]);
        Mat3 c;
        c.col(0) = d_inv * Vec3(mv.x[0][1], mv.x[0][2], mv.x[0][3]);
        c.col(1) = d_inv * Vec3(mv.y[0][1], mv.y[0][2], mv.y[0][3]);
        c.col(2) = d_inv * Vec3(mv.z[0][1], mv.z[0][2], mv.z[0][3]);
        v_[p] = vp;
        c0_[p] = c.col(0), c1_[p] = c.col(1), c2_[p] = c.col(2);
        const Mat3 df = Mat3::Identity() + dt * c;
        set_deformation_gradient(p, df * deformation_gradient(p));
        j_[p] *= df.determinant();
        x_[p] += dt * vp;
        // Nearly every point stays inside the domain: one test before the full treatment
        // (which a periodic domain always needs, to wrap points that left it).
        if (periodic || !domain.contains(x_[p])) push_inside_domain(p);
        if (!near_collider_.empty()) {
          // The node nearest the particle's old position (it moves less than a cell). Through
          // int: a double's conversion to an unsigned 64-bit integer is a branch and two
          // conversions on x86 without AVX-512.
          const std::size_t nearest =
              std::size_t(int(g.x() + 0.5)) * syz + std::size_t(int(g.y() + 0.5)) * nz + std::size_t(int(g.z() + 0.5));
          if (near_collider_[nearest]) push_out_of_colliders(p);
        }
        if constexpr (kThermal) {
          // Thermal gathers over HeatState: Σ w of Δθ (FLIP), the exchange
          // conductance and drive, r, r_v, the air-facing and exchanging areas and
          // the fill; Σ w o of θ, s, ρ_v (their gradients), of the air-facing area
          // (the centroid of the particle's face) and of the fill (its gradient).
          const StencilMoments<3> hm = gather_moments<2>(heat, st);  // the last vector: sums only
          const HeatState sum = as_record<HeatState>(hm.sum), mx = as_record<HeatState>(hm.x),
                          my = as_record<HeatState>(hm.y), mz = as_record<HeatState>(hm.z);
          const Real volume = j_[p] * volume0_[p];
          // FLIP: θ_p += Σ w Δθ_i (spec 4.3), kept within the coldest and hottest
          // temperatures in the scene (particles, air, colliders) before the step:
          // where the material was cut (the lava cake's knife) FLIP increments took
          // particles to 6 °C in a 20–25 °C room.
          temperature_[p] = std::clamp(temperature_[p] + sum.dtheta, flip_bounds_[0], flip_bounds_[1]);
          // The particle's share of the boundary, S β, in series with conduction
          // across its depth d below the face, 1/(1/β + d/κ) per area: the nodes
          // of the face spread the exchange over points up to two cells in,
          // colder than the face while heat flows in, and taking it at their own
          // temperature overstated it by 1 + β d/κ (+24% over Fo 0.25 for a slab
          // on a tray at β Δx/κ = 1.2; docs/physics.md). The face is the fill's
          // level 1/2, d = (φ − 1/2)/|∇φ| from the point.
          const Real area = volume * sum.exchange_area;
          Real series = 1, depth = 0;
          if (sum.exchange > 0 && area > 0) {
            const Real grad = d_inv * Vec3(mx.fill, my.fill, mz.fill).norm();
            depth = grad > 0 ? std::clamp((sum.fill - Real(0.5)) / grad, Real(0), 2 * dx_) : 2 * dx_;
            const Real kappa = point_conductivity(p);
            const Real beta = volume * sum.exchange / area;
            if (kappa > 0) series = 1 / (1 + beta * depth / kappa);
          }
          face_depth_[p] = depth;
          exchange_[p] = series * volume * sum.exchange;
          exchange_t_[p] = series * volume * sum.exchange_theta;
          // Moisture (physics/water.hpp): the water that arrives or leaves as vapour
          // condenses or evaporates here, giving or taking h_fg; then the boiling cap.
          const Real vapour_gain = water_[p] * sum.vapour_ratio;
          // Never below none: a strong surface sink at a corner node can ask a step for a little more than its
          // points hold (a factor of −1e-66 was seen with h_m 0.5 m/s), which the health check refuses.
          water_[p] *= std::max(Real(0), 1 + sum.water_ratio + sum.vapour_ratio);
          air_area_[p] = volume * sum.air_area;
          // The area-weighted mean offset of the nodes that give the particle its area: the face,
          // seen from the particle (cells; the area profile of ∇φ is centred on the face).
          air_depth_[p] =
              sum.air_area > 0 ? dx_ * Vec3(mx.air_area, my.air_area, mz.air_area).norm() / sum.air_area : 0;
          grad_theta_[p] = d_inv * Vec3(mx.theta, my.theta, mz.theta);
          grad_s_[p] = d_inv * Vec3(mx.saturation, my.saturation, mz.saturation);
          if (moist_) {
            grad_vapour_[p] = d_inv * Vec3(mx.vapour_density, my.vapour_density, mz.vapour_density);
            const PoreWater& pw = setup_.materials[material_[p]].moisture;
            Real latent = 0;
            if (pw.active()) {
              const PhaseChange c =
                  condense_and_boil(pw, heat_capacity_[p], temperature_[p], water_[p], vapour_gain, m_[p]);
              temperature_[p] = c.temperature;
              water_[p] = c.water;
              latent = c.latent;
              boiled_step_[p] = c.boiled;
            }
            latent_step_[p] = latent;
          }
        }
      },
      1024);
}

// Grid contact alone lets material seep through a collider only one or two
// cells thick (nodes inside it are sparse; the pancake's receiving pan let
// 5.8% of the batter into or through its floor). A particle that ends a step inside a collider is put
// back on its surface, and its velocity relative to the collider gets the
// same contact condition as the grid nodes (docs/physics.md). Sticky
// colliders are left out: grips hold the material that lies inside them.
void MpmSolver::push_out_of_colliders(std::size_t p) {
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci) {
    const Collider& c = setup_.colliders[ci];
    if (c.contact.mode == ContactMode::sticky) continue;  // grips hold material inside them
    const RigidPose& pose = collider_poses_[ci];
    const WallContact w = signed_distance(c.geometry, pose.to_rest(x_[p]));
    if (w.distance >= 0) continue;
    const Vec3 n = pose.rotation * w.normal;
    x_[p] -= w.distance * n;
    const Vec3 vc = pose.velocity_at(x_[p]);
    Vec3 rel = v_[p] - vc;
    apply_contact(rel, n, c.contact);
    v_[p] = rel + vc;
  }
}

// The domain walls in the same way: a point that ends a step beyond a domain
// face is put back on it with the domain's contact law on its velocity, so
// material rests on the domain floor instead of sinking into the guard layer.
void MpmSolver::push_inside_domain(std::size_t p) {
  const Aabb& d = setup_.domain;
  if (periodicity_.any()) x_[p] = periodicity_.wrap(x_[p]);  // out through one periodic face, in through the other
  for (int k = 0; k < 3; ++k) {
    if (periodicity_.along(k)) continue;
    const Real lo = x_[p][k] - d.min[k], hi = d.max[k] - x_[p][k];
    if (lo >= 0 && hi >= 0) continue;
    const Vec3 n = lo < 0 ? Vec3(Vec3::Unit(k)) : Vec3(-Vec3::Unit(k));
    x_[p][k] = lo < 0 ? d.min[k] : d.max[k];
    apply_contact(v_[p], n, setup_.domain_contact);
  }
}

void MpmSolver::phase_g2p(Real dt) {
  ScopedPhase t(timers_, t_g2p_);
  if (!thermal()) return g2p<false>(dt);
  // The hottest and coldest temperatures a particle may take this step.
  const Real inf = std::numeric_limits<Real>::infinity();
  Real lo = deterministic_reduce(
      x_.size(), inf,
      [&](std::size_t b, std::size_t e) { return *std::min_element(&temperature_[b], &temperature_[b] + (e - b)); },
      [](Real a, Real c) { return std::min(a, c); });
  Real hi = deterministic_reduce(
      x_.size(), -inf,
      [&](std::size_t b, std::size_t e) { return *std::max_element(&temperature_[b], &temperature_[b] + (e - b)); },
      [](Real a, Real c) { return std::max(a, c); });
  for (const Real air : {setup_.oven.air_at(time_), setup_.oven.air_at(time_ + dt)})
    lo = std::min(lo, air), hi = std::max(hi, air);
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci)
    if (setup_.colliders[ci].temperature)
      lo = std::min(lo, collider_temperatures_[ci]), hi = std::max(hi, collider_temperatures_[ci]);
  flip_bounds_ = {lo, hi};
  if (moist_) latent_step_.assign(x_.size(), 0), boiled_step_.assign(x_.size(), 0);
  g2p<true>(dt);
  if (moist_) {
    // What the particles gave as latent heat and boiled off this step (deterministic sums).
    budget_.latent_out += deterministic_sum(x_.size(), [&](std::size_t i) { return latent_step_[i]; });
    const Real boiled = deterministic_sum(x_.size(), [&](std::size_t i) { return boiled_step_[i]; });
    budget_.boiled += boiled;
    budget_.evaporated += boiled;
  }
}

}  // namespace bakesim::mpm
