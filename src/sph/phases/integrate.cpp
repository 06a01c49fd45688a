// Phases kick and drift (leap-frog, thesis 3.4; symplectic Euler with the divergence-free pressure) and the XSPH velocity
// correction (Eq 3.34).
#include "sph/solver.hpp"

#include <algorithm>
#include <cmath>

#include "core/parallel.hpp"

namespace bakesim::sph {

// With mass scaling the inertia is s m: the forces' impulse over the kick is kick/s.
void SphSolver::phase_kick(Real kick) {
  ScopedPhase t(timers_, t_kick_);
  const Real impulse = setup_.mass_scaling.impulse_step(kick);
  parallel_for(
      x_.size(), [&](std::size_t i) { v_[i] += impulse * a_[i]; }, 4096);
}

void SphSolver::phase_drift(Real dt) {
  ScopedPhase t(timers_, t_drift_);
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        x_prev_[i] = x_[i];
        x_[i] += dt * v_[i];
      },
      4096);
}

// Eq 3.34 with the pairwise mean of ε (keeps the correction momentum-conserving),
// scaled by dt / dt_ref (dt_ref the CFL bound at rest, capped at 1): the
// thesis applies it once per step, so its smoothing per second grew with the
// number of steps and a bake's rise, crust and weight loss changed with the
// step (docs/physics.md, "XSPH"); at dt = dt_ref it is the thesis's.
void SphSolver::phase_xsph(Real dt) {
  ScopedPhase t(timers_, t_xsph_);
  bool any = false;
  for (const Material& m : setup_.materials) any |= !is_constant(m.xsph) || std::get<ConstantCurve>(m.xsph).value > 0;
  if (!any) return;
  const Vec3* v = v_.data();
  // A step longer than dt_ref (the divergence-free pressure's) compounds the
  // reference steps it spans: ε becomes 1 − (1 − ε)^(dt/dt_ref), the
  // smoothing per second of the weakly compressible run.
  const Real steps = dt / rest_cfl_step_;
  const Real share = std::min<Real>(1, steps);
  const Real* eps = eps_.data();
  if (steps > 1) {
    compounded_eps_.resize(x_.size());
    parallel_for(
        x_.size(),
        [&](std::size_t i) { compounded_eps_[i] = 1 - std::pow(1 - std::clamp<Real>(eps_[i], 0, 1), steps); }, 4096);
    eps = compounded_eps_.data();
  }
  parallel_for(x_.size(), [&](std::size_t i) {
    Vec3 corr = Vec3::Zero();
    const Vec3 vi = v[i];
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pw = pair_w_.data() + i * lists_.stride();
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const Real w = pw[k];
      corr += (0.5 * (eps[i] + eps[j]) * 2.0 * m_[j] / (rho_[i] + rho_[j]) * w) * (v[j] - vi);
    }
    dv_[i] = share * corr;
  });
  parallel_for(
      x_.size(), [&](std::size_t i) { v_[i] += dv_[i]; }, 4096);
}

}  // namespace bakesim::sph
