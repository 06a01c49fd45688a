// Phase G2P: grid to particle transfer of velocity and the APIC affine field,
// the trial deformation gradient, the move, push-out of thin colliders, and with
// heat the FLIP temperature, water and the boundary share (spec 4.2, 4.3, 4.5).
#include "mpm/solver.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <limits>

#include "core/parallel.hpp"

namespace bakesim::mpm {

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
  if constexpr (kThermal) face_depth_.resize(x_.size());
  parallel_for(
      x_.size(),
      [&](std::size_t p) {
        const Vec3 g = (x_[p] - origin) * inv_dx_;
        const Axis ax = axis_weights(g.x()), ay = axis_weights(g.y()), az = axis_weights(g.z());
        Real v[3] = {0, 0, 0};
        Real b[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};  // b[col][row] = Σ w v_row offset_col
        // Thermal gathers: Σ w of {Δθ, k, kθ, r, k_air} and Σ w o of {θ_new, s}.
        // (moisture: and Σ w r_v, Σ w o ρ_v)
        // (and Σ w o k_air: the centroid of the particle's air-facing area, the face;
        // Σ w a_x, Σ w φ and Σ w o φ: the area it exchanges through, the fill and its gradient)
        Real hs[8] = {0, 0, 0, 0, 0, 0, 0, 0}, hg[3][5] = {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}};
        for (int i = 0; i < 3; ++i) {
          Real vi[3] = {0, 0, 0}, bi[2][3] = {{0, 0, 0}, {0, 0, 0}};  // Σ over j, k at this i
          Real hsi[8] = {0, 0, 0, 0, 0, 0, 0, 0}, hgi[3][5] = {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}};
          for (int j = 0; j < 3; ++j) {
            const Real oy = j - ay.frac;
            const std::size_t row_index = std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base;
            const GridNode* row = &grid_[row_index];
            Real vj[3] = {0, 0, 0}, bz[3] = {0, 0, 0};
            for (int kk = 0; kk < 3; ++kk) {
              const Real w = az.w[kk], oz = kk - az.frac;
              for (int r = 0; r < 3; ++r) {
                const Real wv = w * row[kk].mv[r];
                vj[r] += wv;
                bz[r] += wv * oz;
              }
            }
            const Real wy = ay.w[j];
            for (int r = 0; r < 3; ++r) {
              vi[r] += wy * vj[r];
              bi[0][r] += wy * vj[r] * oy;
              bi[1][r] += wy * bz[r];
            }
            if constexpr (kThermal) {
              const HeatState* hrow = &heat_state_[row_index];
              Real sj[8] = {0, 0, 0, 0, 0, 0, 0, 0}, tj[5] = {0, 0, 0, 0, 0}, tz[5] = {0, 0, 0, 0, 0};
              for (int kk = 0; kk < 3; ++kk) {
                const Real w = az.w[kk], oz = kk - az.frac;
                const HeatState& f = hrow[kk];
                sj[0] += w * f.dtheta, sj[1] += w * f.exchange, sj[2] += w * f.exchange_theta,
                    sj[3] += w * f.water_ratio, sj[4] += w * f.air_area, sj[5] += w * f.vapour_ratio;
                tj[0] += w * f.theta, tj[1] += w * f.saturation, tj[2] += w * f.vapour_density;
                tz[0] += w * f.theta * oz, tz[1] += w * f.saturation * oz, tz[2] += w * f.vapour_density * oz;
                tj[3] += w * f.air_area, tz[3] += w * f.air_area * oz;
                sj[6] += w * f.exchange_area, sj[7] += w * f.fill;
                tj[4] += w * f.fill, tz[4] += w * f.fill * oz;
              }
              for (int q = 0; q < 8; ++q) hsi[q] += wy * sj[q];
              for (int q = 0; q < 5; ++q) {
                hgi[0][q] += wy * tj[q];  // carried to x below
                hgi[1][q] += wy * tj[q] * oy;
                hgi[2][q] += wy * tz[q];
              }
            }
          }
          const Real wx = ax.w[i], ox = i - ax.frac;
          for (int r = 0; r < 3; ++r) {
            v[r] += wx * vi[r];
            b[0][r] += wx * vi[r] * ox;
            b[1][r] += wx * bi[0][r];
            b[2][r] += wx * bi[1][r];
          }
          if constexpr (kThermal) {
            for (int q = 0; q < 8; ++q) hs[q] += wx * hsi[q];
            for (int q = 0; q < 5; ++q) {
              hg[0][q] += wx * hgi[0][q] * ox;
              hg[1][q] += wx * hgi[1][q];
              hg[2][q] += wx * hgi[2][q];
            }
          }
        }
        const Vec3 vp(v[0], v[1], v[2]);
        Mat3 c;
        for (int col = 0; col < 3; ++col)
          for (int r = 0; r < 3; ++r) c(r, col) = d_inv * b[col][r];
        v_[p] = vp;
        c0_[p] = c.col(0), c1_[p] = c.col(1), c2_[p] = c.col(2);
        const Mat3 df = Mat3::Identity() + dt * c;
        set_deformation_gradient(p, df * deformation_gradient(p));
        j_[p] *= df.determinant();
        x_[p] += dt * vp;
        push_inside_domain(p);
        if (!near_collider_.empty()) {
          // The node nearest the particle's old position (it moves less than a cell).
          const std::size_t nearest =
              std::size_t(g.x() + 0.5) * syz + std::size_t(g.y() + 0.5) * nz + std::size_t(g.z() + 0.5);
          if (near_collider_[nearest]) push_out_of_colliders(p);
        }
        if constexpr (kThermal) {
          const Real volume = j_[p] * volume0_[p];
          // FLIP: θ_p += Σ w Δθ_i (spec 4.3), kept within the coldest and hottest
          // temperatures in the scene (particles, air, colliders) before the step:
          // where the material was cut (the lava cake's knife) FLIP increments took
          // particles to 6 °C in a 20–25 °C room.
          temperature_[p] = std::clamp(temperature_[p] + hs[0], flip_bounds_[0], flip_bounds_[1]);
          // The particle's share of the boundary, S β, in series with conduction
          // across its depth d below the face, 1/(1/β + d/κ) per area: the nodes
          // of the face spread the exchange over points up to two cells in,
          // colder than the face while heat flows in, and taking it at their own
          // temperature overstated it by 1 + β d/κ (+24% over Fo 0.25 for a slab
          // on a tray at β Δx/κ = 1.2; docs/physics.md). The face is the fill's
          // level 1/2, d = (φ − 1/2)/|∇φ| from the point.
          const Real area = volume * hs[6];
          Real series = 1, depth = 0;
          if (hs[1] > 0 && area > 0) {
            const Real grad = d_inv * Vec3(hg[0][4], hg[1][4], hg[2][4]).norm();
            depth = grad > 0 ? std::clamp((hs[7] - Real(0.5)) / grad, Real(0), 2 * dx_) : 2 * dx_;
            const Real kappa = point_conductivity(p);
            const Real beta = volume * hs[1] / area;
            if (kappa > 0) series = 1 / (1 + beta * depth / kappa);
          }
          face_depth_[p] = depth;
          exchange_[p] = series * volume * hs[1];
          exchange_t_[p] = series * volume * hs[2];
          // Moisture (physics/water.hpp): the water that arrives or leaves as vapour
          // condenses or evaporates here, giving or taking h_fg; then the boiling cap.
          const Real vapour_gain = water_[p] * hs[5];
          water_[p] *= 1 + hs[3] + hs[5];
          air_area_[p] = volume * hs[4];
          // The area-weighted mean offset of the nodes that give the particle its area: the face,
          // seen from the particle (cells; the area profile of ∇φ is centred on the face).
          air_depth_[p] = hs[4] > 0 ? dx_ * Vec3(hg[0][3], hg[1][3], hg[2][3]).norm() / hs[4] : 0;
          grad_theta_[p] = d_inv * Vec3(hg[0][0], hg[1][0], hg[2][0]);
          grad_s_[p] = d_inv * Vec3(hg[0][1], hg[1][1], hg[2][1]);
          if (moist_) {
            grad_vapour_[p] = d_inv * Vec3(hg[0][2], hg[1][2], hg[2][2]);
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
