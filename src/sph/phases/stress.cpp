// Phase stress: the Maxwell viscoelastic stress update (Eq 3.20–3.27).
#include "sph/solver.hpp"

#include "core/parallel.hpp"
#include "physics/maxwell.hpp"

namespace bakesim::sph {

// Eq 3.20–3.27: the Maxwell stress follows the velocity gradient of the
// half-step velocities at the new positions.
void SphSolver::phase_stress(Real dt) {
  if (!elastic_) return;
  ScopedPhase t(timers_, t_stress_);
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        if (elasticity_[i] == 0.0 && stress_diag_[i].isZero() && stress_off_[i].isZero()) return;
        set_stress(i, maxwell_stress_step(stress(i), velocity_gradient(i), elasticity_[i], relaxation_[i], dt));
      },
      256);
}

}  // namespace bakesim::sph
