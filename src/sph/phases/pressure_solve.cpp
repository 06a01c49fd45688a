// Phases density solve and divergence solve: the divergence-free pressure
// (DFSPH; Bender & Koschier 2015, "Divergence-free smoothed particle
// hydrodynamics", and 2017, "Divergence-free SPH for incompressible and
// viscous fluids", Algorithms 2 and 3), with the walls as the half-space
// whose mass the density phase already counts (docs/physics.md,
// "Divergence-free pressure").
//
// The pressure acceleration is Eq 3.18 written with κ = p/ρ²:
//   a_i = −Σ_j m_j (κ_i + κ_j) ∇W_ij − κ_i b_i G_i,
// G_i = ρ0 ∇f(x_i) the wall half-space's Σ_b m_b ∇W_ib and b_i = 1 + ρ_i²/ρ0²
// its pressure mirrored at p_i (the weakly compressible wall term of the
// forces phase). The density changes at
//   Dρ_i/Dt = Σ_j m_j (v_i − v_j)·∇W_ij + G_i·v_i.
// A pressure κ_i alone changes Dρ_i/Dt by −dt κ_i D_i with
//   D_i = (S_i + b_i G_i)·(S_i + G_i) + m_i Σ_j m_j |∇W_ij|²,  S_i = Σ_j m_j ∇W_ij,
// so each Jacobi iteration sets κ_i = e_i / (dt² D_i) for the error e_i it
// must remove (ρ_i + dt Dρ_i/Dt − ρ0 for the density, dt Dρ_i/Dt for the
// divergence, neither below zero: a free surface may expand) and moves every
// velocity by dt a_i. D_i is Bender & Koschier's 1/α_i, exact here for
// particles of different masses and for the wall.
#include "sph/solver.hpp"

#include <algorithm>

#include "core/parallel.hpp"

namespace bakesim::sph {

void SphSolver::update_pressure_factors() {
  const std::size_t n = x_.size();
  pressure_factor_.resize(n);
  wall_mass_gradient_.resize(n);
  wall_mirror_.resize(n);
  const bool walls = setup_.settings.wall_density_correction;
  const Real* m = m_.data();
  parallel_for(n, [&](std::size_t i) {
    Vec3 sum = Vec3::Zero();
    Real squares = 0;
    for_each_kernel_gradient(i, [&](std::uint32_t j, const Vec3& grad) {
      sum += m[j] * grad;
      squares += m[j] * grad.squaredNorm();
    });
    const Real rho0 = setup_.materials[material_[i]].rest_density;
    Vec3 g = Vec3::Zero();
    if (walls && wall_share(x_[i], &g) > 0) g *= rho0;
    const Real b = 1 + rho_[i] * rho_[i] / (rho0 * rho0);
    const Real d = (sum + b * g).dot(sum + g) + m[i] * squares;
    wall_mass_gradient_[i] = g;
    wall_mirror_[i] = b;
    pressure_factor_[i] = d > 0 ? 1 / d : 0;
  });
}

// v_i −= dt (Σ_j m_j (κ_i + κ_j) ∇W_ij + κ_i b_i G_i) for the given κ.
void SphSolver::apply_pressure(Real dt, const std::vector<Real>& kappa) {
  const Real* m = m_.data();
  parallel_for(x_.size(), [&](std::size_t i) {
    const Real ki = kappa[i];
    Vec3 acc = -(ki * wall_mirror_[i]) * wall_mass_gradient_[i];
    for_each_kernel_gradient(i, [&](std::uint32_t j, const Vec3& grad) { acc -= (m[j] * (ki + kappa[j])) * grad; });
    v_[i] += dt * acc;
  });
}

SphSolver::PressureSolve SphSolver::solve_pressure(Real dt, bool density, Real tolerance,
                                                   std::vector<Real>& kappa_total) {
  const std::size_t n = x_.size();
  kappa_.resize(n);
  const Real* m = m_.data();
  const Real inv_dt2 = 1 / (dt * dt);
  const int most = setup_.settings.pressure_max_iterations;
  // The divergence error is Dρ/Dt over a fixed step (max_dt), so that a
  // shorter step does not loosen it.
  const Real error_step = setup_.settings.max_dt;
  // The density's drift from rest is taken back over max_dt, not within a
  // shorter step (Baumgarte): its velocity would grow as 1/dt.
  const Real drift_share = std::min<Real>(1, dt / error_step);
  const Real measure = density ? 1.0 : error_step / dt;
  // The density solve starts from last step's pressure, which holds a column
  // still; the divergence solve from none (last step's correction, applied
  // again, would be noise the iterations must take out).
  if (density)
    apply_pressure(dt, kappa_total);
  else
    std::fill(kappa_total.begin(), kappa_total.end(), 0.0);
  PressureSolve result;
  for (;; ++result.iterations) {
    // The error e_i the current velocities leave. It counts on the expanded
    // side only under pressure (its κ is then too large); elsewhere (a free
    // surface, an unpressed particle) only compression counts.
    const Real sum = deterministic_sum(n, [&](std::size_t i) {
      const Vec3 vi = v_[i];
      Real rate = wall_mass_gradient_[i].dot(vi);
      for_each_kernel_gradient(i, [&](std::uint32_t j, const Vec3& grad) { rate += m[j] * grad.dot(vi - v_[j]); });
      const Real rho0 = setup_.materials[material_[i]].rest_density;
      const Real e = density ? drift_share * (rho_[i] - rho0) + dt * rate : dt * rate;
      kappa_[i] = e;
      return (kappa_total[i] > 0 ? std::abs(e) : std::max<Real>(e, 0)) / rho0;
    });
    result.error = measure * sum / Real(std::max<std::size_t>(n, 1));
    if (result.error <= tolerance || result.iterations >= most) break;
    // Relaxed Jacobi, projected on κ ≥ 0: the pressure never pulls.
    parallel_for(
        n,
        [&](std::size_t i) {
          const Real next = std::max<Real>(kappa_total[i] + kRelaxation * kappa_[i] * inv_dt2 * pressure_factor_[i], 0);
          kappa_[i] = next - kappa_total[i];
          kappa_total[i] = next;
        },
        4096);
    apply_pressure(dt, kappa_);
  }
  return result;
}

// Before the drift: the pressure that brings ρ_i + dt Dρ_i/Dt to rest, with
// the velocities after the other forces (Algorithm 3). Its κ is the step's
// pressure, p = κ ρ² (the particles' "pressure").
void SphSolver::phase_density_solve(Real dt) {
  ScopedPhase t(timers_, t_density_solve_);
  const std::size_t n = x_.size();
  if (pressure_factor_.size() != n) update_pressure_factors();
  const PressureSolve solve = solve_pressure(dt, true, setup_.settings.density_tolerance, density_kappa_);
  density_iterations_ = solve.iterations;
  density_error_ = solve.error;
  parallel_for(
      n, [&](std::size_t i) { p_[i] = density_kappa_[i] * rho_[i] * rho_[i]; }, 4096);
}

// After the drift, at the new positions: the pressure that makes the
// velocity field divergence-free (Algorithm 2).
void SphSolver::phase_divergence_solve(Real dt) {
  ScopedPhase t(timers_, t_divergence_solve_);
  divergence_kappa_.resize(x_.size());
  divergence_iterations_ =
      solve_pressure(dt, false, setup_.settings.divergence_tolerance, divergence_kappa_).iterations;
}

}  // namespace bakesim::sph
