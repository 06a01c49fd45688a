// Implicit viscosity: the viscous term of Eq 3.19 integrated by backward
// Euler, so that doughs of 10³–10⁴ Pa·s (thesis Table 4.1) do not force the
// explicit viscous time step (h²/ν, ~10⁻⁷ s) on the whole bake. With implicit
// elasticity the solve's viscosity is μ plus the step's elastic viscosity
// w μ_e / 2 (phase stress), which makes the Maxwell stress's elastic
// increment backward Euler too.
//
// Multiplying Eq 3.19 by m_i gives a symmetric graph Laplacian:
//   m_i dv_i/dt = Σ_j w_ij (v_j − v_i),  w_ij = μ̄_ij V_i V_j ∇²W_visc(r_ij) ≥ 0,
// so (M + dt K) v^{n+1} = M v* is symmetric positive definite and is solved
// by conjugate gradients with a Jacobi preconditioner, the three velocity
// components side by side (core/pcg.hpp, shared with the MPM implicit heat).
// The weights dt·w_ij are computed once per step and kept in single
// precision (the products read them every iteration; 7 significant digits
// are far below the solve's tolerance), the sums in double. Rows of K sum
// to zero: momentum is conserved to the solver tolerance. A no-slip wall
// adds dt μ_i V_i G(d) to its particles' diagonal and the same times the
// wall's velocity to the right-hand side (WallGhostSum): still symmetric
// positive definite.
//
// Stress form (solver.sph.viscosity_operator = stress): the force is the
// divergence of the deviatoric viscous stress S_i = 2 μ_i dev D_i, with
// D_i = sym(Σ_j V_j (v_j − v_i) ⊗ C_i ∇_i W_ij) and C_i = M_i^{−T},
// M_i = Σ_j V_j (x_j − x_i) ⊗ ∇_i W_ij (exact velocity gradients of linear
// fields, also where a free surface cuts the support). The force is minus the
// derivative of the dissipation Φ = Σ_i V_i μ_i |dev D_i|²,
//   f_k = V_k Σ_j V_j (S_k C_k + S_j C_j) ∇_k W_kj,
// so K = −∂f/∂v is symmetric positive semidefinite and (M + dt K) v = M v*
// is solved by conjugate gradients over all 3n unknowns at once (the
// components are coupled). A free surface is traction-free by construction
// (the natural boundary condition of Φ), which is what lets a viscous or
// yield-stress column carry its weight.
#include <fmt/format.h>

#include <Eigen/LU>
#include <cmath>

#include "core/buffers.hpp"
#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/pcg.hpp"
#include "sph/solver.hpp"

namespace bakesim::sph {

void SphSolver::phase_viscosity(Real step) {
  viscosity_iterations_ = 0;
  if (!implicit_viscosity_) return;
  // Backward Euler of the momentum over the step: with mass scaling the
  // inertia is s M, (s M + Δt K) v = s M v*, solved as (M + (Δt/s) K) v = M v*.
  const Real dt = setup_.mass_scaling.impulse_step(step);
  ScopedPhase t(timers_, t_viscosity_);
  const std::size_t n = x_.size();
  const std::size_t stride = lists_.stride();
  const Real visc_c = visc_lap_.coefficient();
  resize_with_headroom(pair_visc_, n * stride);
  std::vector<Real>& diag = dtemp_;  // free until the heat phase
  const std::vector<Real>& mu = viscosity_in_solve();
  // Weights dt·w_ij and the preconditioner diagonal m_i + dt Σ_j w_ij (the
  // volumes m/ρ of the pressure phase: the densities have not changed since).
  parallel_for(n, [&](std::size_t i) {
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pr = lists_.distances(i);
    float* w = pair_visc_.data() + i * stride;
    const Real vi = m_[i] / rho_[i];
    Real d = m_[i];
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const Real hij = adaptive_ ? 0.5 * (smoothing_[i] + smoothing_[j]) : h_;  // Eq 3.56
      const Real vc = adaptive_ ? visc_lap_.coefficient_for(hij) : visc_c;
      w[k] = float(dt * 0.5 * (mu[i] + mu[j]) * vi * volume_[j] * vc * (hij - Real(pr[k])));
      d += Real(w[k]);  // the rounded weight, as the product uses it
    }
    if (no_slip_walls_) d += dt * mu[i] * vi * wall_drag_[i];  // the wall's row entry (v_wall on the right)
    diag[i] = d;
  });
  if (setup_.settings.stress_viscosity) {
    solve_stress_viscosity(dt, diag);
    return;
  }
  auto apply = [&](const std::vector<Vec3>& in, std::vector<Vec3>& out) {
    parallel_for(n, [&](std::size_t i) {
      const std::uint32_t* nb = lists_.begin(i);
      const std::uint32_t count = lists_.count(i);
      const float* w = pair_visc_.data() + i * stride;
      // Σ_j w_ij (v_i − v_j) = (Σ_j w_ij) v_i − Σ_j w_ij v_j: the row sum is
      // the diagonal less the mass (and the wall's entry).
      const Vec3 vi = in[i];
      Vec3 off = Vec3::Zero();
      for (std::uint32_t k = 0; k < count; ++k) off += Real(w[k]) * in[nb[k]];
      out[i] = diag[i] * vi - off;
    });
  };
  const Vec3 b_norm2 = build_viscosity_rhs(dt);
  start_viscous_guess();
  // The Laplacian form leaves the walls to the pressure (no supports): with
  // them its three component systems become one coupled system, and on the
  // full bread-roll bake the solve took 12.6 instead of 7.3 ms a step (the
  // whole bake 480 s against 395 s, one run each) for the same bake
  // (docs/physics.md, "Walls in the implicit viscous solve").
  supported_ = 0;
  solve_supported<false>(apply, diag, b_norm2, "implicit viscosity");
  keep_viscous_change();
}

// b = M v* (plus the no-slip walls' v_wall terms); the Laplacian solve starts
// from v* plus the last solve's change (start_viscous_guess). Returns |b|² per
// component for the stopping test: the momentum M v* plus the momentum one
// step of gravity adds (m g dt per particle), so a body nearly at rest does
// not demand a solve far below what its next step changes anyway.
Vec3 SphSolver::build_viscosity_rhs(Real dt) {
  const std::size_t n = x_.size();
  const std::vector<Real>& mu = viscosity_in_solve();
  viscosity_rhs_.resize(n);
  parallel_for(
      n,
      [&](std::size_t i) {
        viscosity_rhs_[i] = m_[i] * v_[i];
        if (no_slip_walls_) viscosity_rhs_[i] += dt * mu[i] * (m_[i] / rho_[i]) * wall_drag_velocity_[i];
      },
      4096);
  const Real floor_v = std::max(setup_.gravity.norm(), 1.0) * dt;
  return pcg_sum<Vec3>(n, [&](std::size_t i) {
    return Vec3((m_[i] * v_[i]).cwiseAbs2() + Vec3::Constant(m_[i] * m_[i] * floor_v * floor_v));
  });
}

// The solve starts from v* plus the change the last solve made (kept per
// particle in the registry, so it follows sorts and checkpoints): in a bake
// the viscous and elastic correction changes slowly from step to step.
void SphSolver::start_viscous_guess() {
  viscosity_start_.resize(x_.size());
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        viscosity_start_[i] = v_[i];
        v_[i] += viscous_change_[i];
      },
      4096);
}

void SphSolver::keep_viscous_change() {
  parallel_for(
      x_.size(), [&](std::size_t i) { viscous_change_[i] = v_[i] - viscosity_start_[i]; }, 4096);
}

void SphSolver::solve_stress_viscosity(Real dt, const std::vector<Real>& diag) {
  const std::size_t n = x_.size();
  const std::size_t stride = lists_.stride();
  const std::vector<Real>& mu = viscosity_in_solve();
  stress_times_correction_.resize(n);
  update_gradient_correction();
  auto apply = [&](const std::vector<Vec3>& in, std::vector<Vec3>& out) {
    parallel_for(n, [&](std::size_t i) {
      const std::uint32_t* nb = lists_.begin(i);
      const std::uint32_t count = lists_.count(i);
      const Vec3* g = pair_volume_gradient_.data() + i * stride;
      Mat3 grad = Mat3::Zero();
      for (std::uint32_t k = 0; k < count; ++k) grad += (in[nb[k]] - in[i]) * g[k].transpose();
      grad = grad * correction_[i].transpose();  // L_i = Σ V_j (v_j − v_i) (C_i ∇W)ᵀ
      const Mat3 d = 0.5 * (grad + grad.transpose());
      const Mat3 s = 2 * mu[i] * (d - (d.trace() / 3) * Mat3::Identity());
      stress_times_correction_[i] = s * correction_[i];
    });
    parallel_for(n, [&](std::size_t k) {
      if (measuring_reactions_ && support_normal_[k].isZero()) return;  // only the supported rows are read
      const std::uint32_t* nb = lists_.begin(k);
      const std::uint32_t count = lists_.count(k);
      const Vec3* g = pair_volume_gradient_.data() + k * stride;
      const Real vk = m_[k] / rho_[k];
      Vec3 force = Vec3::Zero();
      for (std::uint32_t q = 0; q < count; ++q)
        force += (stress_times_correction_[k] + stress_times_correction_[nb[q]]) * g[q];
      Vec3 acc = m_[k] * in[k] - dt * vk * force;
      if (no_slip_walls_) acc += (dt * mu[k] * vk * wall_drag_[k]) * in[k];
      remove_supported_normal(k, acc);
      out[k] = acc;
    });
  };
  const Vec3 b_norm2 = Vec3::Constant(build_viscosity_rhs(dt).sum());  // one system: the components summed
  // Started from v* (not warm): the stress form conserves angular momentum,
  // and a warm start's last change, stopped within the tolerance, would
  // leave the same small error every step (a spinning ball's change turns
  // with it), which adds up (3.5e-5 of L in StressViscosity.ARigidly... over
  // 0.05 s, where the cold start keeps 1e-6).
  find_wall_supports();
  solve_supported<true>(apply, diag, b_norm2, "implicit stress-form viscosity");
}

// V_j ∇_i W_ij per pair and C_i = M_i^{−T}, M_i = Σ_j V_j (x_j − x_i) ⊗ ∇_i W_ij,
// once per step (the stress phase of an elastic body and the stress-form
// solve share them: nothing moves between the two). Where the support holds
// too little to invert M (a particle nearly alone), the uncorrected gradient.
void SphSolver::update_gradient_correction() {
  if (correction_fresh_ && correction_.size() == x_.size()) return;
  correction_fresh_ = true;
  const std::size_t n = x_.size();
  const std::size_t stride = lists_.stride();
  correction_.resize(n);
  resize_with_headroom(pair_volume_gradient_, n * stride);
  parallel_for(n, [&](std::size_t i) {
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pd = pair_dwr_.data() + i * stride;
    Vec3* g = pair_volume_gradient_.data() + i * stride;
    Mat3 m = Mat3::Zero();
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const Vec3 xij = pair_offset(i, j);
      g[k] = (m_[j] / rho_[j]) * (Real(pd[k]) * xij);
      m -= xij * g[k].transpose();
    }
    Mat3 inverse;
    bool invertible = false;
    Real det = 0;
    m.computeInverseAndDetWithCheck(inverse, det, invertible);
    correction_[i] = invertible && det > 0.05 ? Mat3(inverse.transpose()) : Mat3::Identity();
  });
}

// The walls a body rests on hold it inside the viscous solve: a particle
// touching a wall and not moving away from it keeps the wall's normal
// velocity, so the solve carries the wall's reaction through the body
// instead of leaving it to the next step's pressure (docs/physics.md, "Walls
// in the implicit viscous solve"). Conjugate gradients filtered as Baraff & Witkin
// (1998, "Large steps in cloth simulation", §5.3) do: the right-hand side,
// the start and every product are projected on the free directions. A wall
// pushes and never pulls: where the solved velocity needs the wall to hold a
// particle down (its reaction (A v − b)·n < 0), the particle is let go and
// the solve goes on from where it stopped (at most two more rounds).
template <bool Coupled, class Apply>
void SphSolver::solve_supported(Apply& apply, const std::vector<Real>& diag, const Vec3& b_norm2, const char* what) {
  const std::size_t n = x_.size();
  const Real tol = setup_.settings.implicit_tolerance;
  const Vec3 stop = (tol * tol) * b_norm2;
  if (supported_ > 0)
    parallel_for(
        n,
        [&](std::size_t i) {
          const Vec3& normal = support_normal_[i];
          if (normal.isZero()) return;
          support_push_[i] = viscosity_rhs_[i].dot(normal);
          remove_supported_normal(i, viscosity_rhs_[i]);
          v_[i] += (support_velocity_[i] - v_[i].dot(normal)) * normal;
        },
        4096);
  viscosity_iterations_ = 0;
  for (int round = 0;; ++round) {
    const PcgResult<Vec3> result = solve_pcg<Vec3, Coupled>(
        n, apply, [](std::size_t) { return true; }, diag, viscosity_rhs_, v_, stop,
        setup_.settings.implicit_max_iterations, viscosity_pcg_);
    viscosity_iterations_ += result.iterations;
    require_acceptable(
        result, b_norm2, [&] { return fmt::format("SPH step {} (t = {:.6g} s): {}", steps_, time_, what); },
        "solver.sph.implicit_viscosity.max_iterations");
    if (round == 2 || supported_ == 0) break;
    std::vector<Vec3>& product = viscosity_pcg_.ap;
    measuring_reactions_ = true;  // unfiltered, and only the supported rows
    apply(v_, product);
    measuring_reactions_ = false;
    const std::size_t released = std::size_t(deterministic_sum(n, [&](std::size_t i) {
      const Vec3& normal = support_normal_[i];
      if (normal.isZero() || product[i].dot(normal) - support_push_[i] >= 0) return 0.0;
      viscosity_rhs_[i] += support_push_[i] * normal;
      support_normal_[i] = Vec3::Zero();
      return 1.0;
    }));
    if (released == 0) break;
    supported_ -= released;
  }
}

// Particles touching an analytic wall and not moving away from it: their
// velocity normal to the wall is the wall's in the viscous solve.
void SphSolver::find_wall_supports() {
  const std::size_t n = x_.size();
  support_normal_.resize(n);
  support_velocity_.resize(n);
  support_push_.resize(n);
  // Within 5% of the contact distance: the pressure holds a resting layer a
  // little off the distance the collide phase puts it at.
  const Real reach = 1.05 * contact_distance_;
  supported_ = std::size_t(deterministic_sum(n, [&](std::size_t i) {
    Vec3 normal = Vec3::Zero();
    Real speed = 0, nearest = reach;
    for (std::size_t c = 0; c < walls_.size(); ++c)
      for_each_wall_of(c, x_[i], reach, [&](const WallContact& w, const Vec3& wall_velocity) {
        if (w.distance >= nearest || (v_[i] - wall_velocity).dot(w.normal) > 0) return;
        nearest = w.distance;
        normal = w.normal;
        speed = wall_velocity.dot(w.normal);
      });
    support_normal_[i] = normal;
    support_velocity_[i] = speed;
    return normal.isZero() ? 0.0 : 1.0;
  }));
}

void SphSolver::remove_supported_normal(std::size_t i, Vec3& value) const {
  if (measuring_reactions_ || support_normal_[i].isZero()) return;
  value -= value.dot(support_normal_[i]) * support_normal_[i];
}

}  // namespace bakesim::sph
