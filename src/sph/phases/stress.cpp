// Phase stress: the Maxwell viscoelastic stress update (Eq 3.20–3.27),
// explicit or semi-implicit (solver.sph.elasticity_solver).
#include "sph/solver.hpp"

#include <cmath>

#include "core/parallel.hpp"
#include "physics/maxwell.hpp"

namespace bakesim::sph {

// Eq 3.20–3.27: the Maxwell stress follows the velocity gradient of the
// half-step velocities at the new positions. Implicit elasticity: only the
// relaxation here; the elastic increment w μ_e D' acts in the viscosity solve
// as the viscosity w μ_e / 2, and the forcing w (R + μ_e D') is added with
// the solved velocities (phase_stress_increment).
void SphSolver::phase_stress(Real dt) {
  if (!elastic_) return;
  ScopedPhase t(timers_, t_stress_);
  if (!implicit_elasticity_) {
    parallel_for(
        x_.size(),
        [&](std::size_t i) {
          if (elasticity_[i] == 0.0 && stress_diag_[i].isZero() && stress_off_[i].isZero()) return;
          set_stress(i, maxwell_stress_step(stress(i), velocity_gradient(i), elasticity_[i], relaxation_[i], dt));
        },
        256);
    return;
  }
  solve_viscosity_.resize(x_.size());
  forcing_weight_.resize(x_.size());
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        forcing_weight_[i] = maxwell_forcing_weight(relaxation_[i], dt);
        solve_viscosity_[i] = mu_[i] + maxwell_step_viscosity(elasticity_[i], forcing_weight_[i]);
        if (stress_diag_[i].isZero() && stress_off_[i].isZero()) return;
        const Real decay = std::exp(-dt / relaxation_[i]);
        stress_diag_[i] *= decay;
        stress_off_[i] *= decay;
      },
      256);
}

// The densities have not changed since the pressure phase: its volumes m/ρ serve.
void SphSolver::phase_stress_increment() {
  if (!implicit_elasticity_) return;
  ScopedPhase t(timers_, t_stress_);
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        if (elasticity_[i] == 0.0 && stress_diag_[i].isZero() && stress_off_[i].isZero()) return;
        set_stress(i, maxwell_forcing_step(stress(i), velocity_gradient(i, volume_.data()), elasticity_[i],
                                           forcing_weight_[i]));
      },
      256);
}

}  // namespace bakesim::sph
