// Phase forces: pressure gradient, viscoelastic stress divergence, viscosity,
// artificial viscosity and stress, surface tension, gravity and the wall
// half-space pressure (Eq 3.18, 2.18, 3.19, 3.35–3.41, 3.28–3.30). The pair
// terms are the laws of src/sph/forces/ (one file each, unit-tested alone);
// this phase owns the one fused loop over the neighbours that sums them.
#include "sph/solver.hpp"

#include <cmath>

#include "core/parallel.hpp"
#include "sph/forces/artificial_stress.hpp"
#include "sph/forces/artificial_viscosity.hpp"
#include "sph/forces/maxwell.hpp"
#include "sph/forces/pressure.hpp"
#include "sph/forces/surface_tension.hpp"
#include "sph/forces/viscosity.hpp"

namespace bakesim::sph {

// Per particle, the viscous pull of the sticky analytic colliders within h:
// Σ G(d) and Σ G(d) v_wall (the wall's velocity where the particle is).
void SphSolver::compute_wall_drag() {
  wall_drag_.assign(x_.size(), 0.0);
  wall_drag_velocity_.assign(x_.size(), Vec3::Zero());
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        // S_visc scales as 1/h² with the support (adaptive smoothing).
        for_each_no_slip_wall(i, [&](Real d0, Real scale, const WallContact&, const Vec3& v_wall) {
          const Real g = wall_viscosity_(d0) * scale * scale;
          wall_drag_[i] += g;
          wall_drag_velocity_[i] += g * v_wall;
        });
      },
      1024);
}

void SphSolver::phase_forces() {
  ScopedPhase t(timers_, t_forces_);
  const Settings& s = setup_.settings;
  const Vec3* x = x_.data();
  const Vec3* v = v_.data();
  const Real* m = m_.data();
  const Real* rho = rho_.data();
  const Real* p = p_.data();
  const Real* mu = mu_.data();
  const Real c = s.speed_of_sound;
  const Real h = h_;
  const Real av_eps_h2 = s.av_epsilon * h * h;
  const bool artificial = s.av_alpha != 0.0 || s.av_beta != 0.0;
  const bool any_tension = surface_tension_;
  const Vec3 g = setup_.gravity;
  // The divergence-free solves give the walls' pressure themselves.
  const bool wall_corr = s.wall_density_correction && !divergence_free_;

  const Real* p_rho2 = p_over_rho2_.data();
  const Real* vol = volume_.data();
  const bool explicit_visc = !implicit_viscosity_;
  const bool no_slip = no_slip_walls_;
  if (no_slip) compute_wall_drag();
  const bool elastic = elastic_;
  const Mat3* s_rho2 = elastic ? stress_rho2_.data() : nullptr;
  const bool symmetric_stress = elastic && !corrected_maxwell();  // else add_corrected_stress_divergence
  const Real visc_c = visc_lap_.coefficient();                    // Eq 3.8 (all listed pairs have r < h)
  const Real* hsup = smoothing_.data();
  const bool adaptive = adaptive_;
  const bool periodic = periodic_;
  const Periodicity& periodicity = periodicity_;
  // Monaghan (2000) artificial stress: R_i = Q diag(−ε max(σ'_a, 0)/ρ_i²) Qᵀ
  // from the principal stresses σ'_a of the total stress S − p I.
  const bool art_stress = elastic && s.artificial_stress > 0.0;
  const Real art_n = s.artificial_stress_exponent;
  if (art_stress) {
    artificial_stress_.resize(x_.size());
    const Real eps = s.artificial_stress;
    parallel_for(
        x_.size(),
        [&](std::size_t i) { artificial_stress_[i] = forces::artificial_stress_tensor(s_rho2[i], p_rho2[i], eps); },
        1024);
  }
  const Mat3* art = art_stress ? artificial_stress_.data() : nullptr;
  // f = W(r)/W(Δp) with the pair's W from the density phase; with adaptive h
  // the spacing scales with h_ij, and W_hij(Δp h_ij/h) = W_h(Δp) (h/h_ij)³.
  const Real inv_w_dp = 1.0 / kernel_.w(s.spacing);
  const Real inv_h3 = 1.0 / (h * h * h);
  parallel_for(x_.size(), [&](std::size_t i) {
    const Vec3 xi = x[i], vi = v[i];
    const Real hi = hsup[i];
    const Real lap_w0 = adaptive ? CubicSpline(hi).laplacian(0.0) : kernel_.laplacian(0.0);
    const Real rhoi = rho[i], pi_rho2 = p_rho2[i], mui = mu[i];
    Vec3 acc_p = Vec3::Zero(), acc_v = Vec3::Zero(), acc_av = Vec3::Zero(), acc_s = Vec3::Zero();
    const Vec3 normal = any_tension ? colour_grad_[i] : Vec3::Zero();  // kept every step only for tension
    // The colour sums run over all j including i (Eq 3.28); the self term of
    // the Laplacian is large and negative, without it ∇²C is biased positive
    // and the force would point outwards.
    Real lap_c = vol[i] * lap_w0;
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pr = lists_.distances(i);
    const float* pd = pair_dwr_.data() + i * lists_.stride();
    const float* pw = pair_w_.data() + i * lists_.stride();
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const Real r = pr[k];
      const Vec3 xij = periodic ? periodicity.nearest_image(xi - x[j]) : Vec3(xi - x[j]);
      const Vec3 grad = Real(pd[k]) * xij;  // zero for coincident particles
      // Eq 3.56: the pair's support (the global h unless adaptive).
      const Real hij = adaptive ? 0.5 * (hi + hsup[j]) : h;
      // Eq 3.18: symmetric pressure gradient.
      acc_p -= forces::pressure_gradient(m[j], pi_rho2, p_rho2[j], grad);
      // Eq 3.19: pairwise-averaged viscosity with the viscosity-kernel Laplacian.
      const Vec3 vij = vi - v[j];
      if (explicit_visc) {
        const Real vc = adaptive ? visc_lap_.coefficient_for(hij) : visc_c;
        acc_v -= forces::viscosity_weight(mui, mu[j], vol[j], vc, hij, r) * vij;
      }
      // Divergence of the viscoelastic stress (Eq 2.18 in SPH form):
      // Σ m_j (S_i/ρ_i² + S_j/ρ_j²) ∇_i W_ij.
      if (symmetric_stress) acc_s += forces::stress_divergence(m[j], s_rho2[i], s_rho2[j], grad);
      // Artificial stress: m_j f_ij^n (R_i + R_j) ∇_i W_ij, f = W(r)/W(Δp).
      if (art_stress) {
        const Real f = Real(pw[k]) * inv_w_dp * (adaptive ? hij * hij * hij * inv_h3 : 1.0);
        acc_s += forces::artificial_stress(m[j], f, art_n, art[i], art[j], grad);
      }
      // Eq 3.35–3.41: artificial viscosity, only for approaching pairs
      // (branch-free: min(v·x, 0) makes Π vanish for receding pairs).
      if (artificial) {
        const Real eps_h2 = adaptive ? s.av_epsilon * hij * hij : av_eps_h2;
        const Real pi_ij =
            forces::artificial_viscosity(vij, xij, r, hij, eps_h2, rhoi, rho[j], s.av_alpha, s.av_beta, c);
        acc_av -= (m[j] * pi_ij) * grad;
      }
      // Eq 3.29: colour field Laplacian (the gradient, Eq 3.28, comes from the surface phase).
      if (any_tension) lap_c += vol[j] * (adaptive ? CubicSpline(hij).laplacian(r) : kernel_.laplacian(r));
    }
    // No-slip walls: Eq 3.19 continued through the wall (WallGhostSum).
    if (explicit_visc && no_slip) acc_v -= mui * (wall_drag_[i] * vi - wall_drag_velocity_[i]);
    Vec3 acc = acc_p + acc_v / rhoi + acc_av + acc_s + g;
    if (any_tension) {
      const Real sigma = setup_.materials[material_[i]].surface_tension;
      const Real nn = normal.norm();
      // Eq 3.30, only where |N| is large enough for a stable direction.
      if (sigma != 0.0 && nn * hi > s.surface_threshold) acc += forces::surface_tension(sigma, rhoi, lap_c, normal, nn);
    }
    if (wall_corr && p[i] > 0) {
      // Pressure of the wall half-space mirrored at the particle's pressure.
      const Real rho0 = setup_.materials[material_[i]].rest_density;
      const Real coef = p[i] * (1.0 / (rhoi * rhoi) + 1.0 / (rho0 * rho0)) * rho0;
      Vec3 grad_share;
      if (wall_share(xi, &grad_share) > 0) acc -= coef * grad_share;
    }
    a_[i] = acc;
  });
  if (corrected_maxwell()) add_corrected_stress_divergence();
}

// With the stress-form viscosity the Maxwell stress's divergence is the same
// operator as the viscous stress's (phase viscosity): minus the adjoint of
// the corrected velocity gradient its rate reads,
//   a_k += (1/ρ_k) Σ_j V_j (S_k C_k + S_j C_j) ∇_k W_kj,
// so its work is exactly the stress power Σ V S : D of those gradients and a
// free surface or a wall's side is traction-free in the same sense for both.
// The symmetric form Σ m_j (S_i/ρ_i² + S_j/ρ_j²) ∇W pairs with the
// uncorrected gradient instead; mixed with the corrected one, a body's
// boundary layers take stress they are not given (docs/physics.md).
void SphSolver::add_corrected_stress_divergence() {
  const std::size_t n = x_.size();
  const std::size_t stride = lists_.stride();
  update_gradient_correction();
  stress_times_correction_.resize(n);
  parallel_for(
      n, [&](std::size_t i) { stress_times_correction_[i] = stress(i) * correction_[i]; }, 1024);
  parallel_for(n, [&](std::size_t k) {
    const std::uint32_t* nb = lists_.begin(k);
    const std::uint32_t count = lists_.count(k);
    const Vec3* g = pair_volume_gradient_.data() + k * stride;
    Vec3 force = Vec3::Zero();
    for (std::uint32_t q = 0; q < count; ++q)
      force += (stress_times_correction_[k] + stress_times_correction_[nb[q]]) * g[q];
    a_[k] += force / rho_[k];
  });
}

}  // namespace bakesim::sph
