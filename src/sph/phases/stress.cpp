// Phase stress: the Maxwell viscoelastic stress update (Eq 3.20–3.27),
// explicit or semi-implicit (solver.sph.elasticity_solver).
#include "sph/solver.hpp"

#include <cmath>

#include "core/parallel.hpp"
#include "physics/maxwell.hpp"
#include "physics/rheology.hpp"
#include "sph/curve_temperature.hpp"

namespace bakesim::sph {

// Eq 3.20–3.27: the Maxwell stress follows the velocity gradient of the
// half-step velocities at the new positions. Implicit elasticity: only the
// relaxation here; the elastic increment w μ_e D' acts in the viscosity solve
// as the viscosity w μ_e / 2, and the forcing w (R + μ_e D') is added with
// the solved velocities (phase_stress_increment).
void SphSolver::phase_stress(Real dt) {
  if (!elastic_) return;
  ScopedPhase t(timers_, t_stress_);
  const bool corrected = corrected_maxwell();
  if (corrected) update_gradient_correction();
  if (!implicit_elasticity_) {
    parallel_for(
        x_.size(),
        [&](std::size_t i) {
          if (elasticity_[i] == 0.0 && stress_diag_[i].isZero() && stress_off_[i].isZero()) return;
          set_stress(i, maxwell_stress_step(stress(i), velocity_gradient(i, nullptr, corrected), elasticity_[i],
                                            relaxation_[i], dt));
        },
        256);
    plastic_return(dt);
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
void SphSolver::phase_stress_increment(Real dt) {
  if (!implicit_elasticity_) return;
  ScopedPhase t(timers_, t_stress_);
  const bool corrected = corrected_maxwell();  // correction_ is the solve's, of these positions
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        if (elasticity_[i] == 0.0 && stress_diag_[i].isZero() && stress_off_[i].isZero()) return;
        set_stress(i, maxwell_forcing_step(stress(i), velocity_gradient(i, volume_.data(), corrected), elasticity_[i],
                                           forcing_weight_[i]));
      },
      256);
  plastic_return(dt);
}

// Elastoviscoplastic materials (Saramito 2007; material.herschel_bulkley.form):
// where the updated Maxwell stress's √J₂ = |S|/√2 exceeds τ_y, the Perzyna
// flow γ̇_p = ((√J₂ − τ_y)/K)^{1/n} acts for the step (backward Euler, the
// return MPM's herschel_bulkley plasticity takes: HerschelBulkley::
// relaxed_overstress with the shear modulus G = μ_e/2, since dS/dt = μ_e D'
// gives a shear stress rate G γ̇), scaling S back along itself. Steady simple
// shear at γ̇ then carries τ_y + K γ̇ⁿ; below τ_y the stress is elastic.
void SphSolver::plastic_return(Real dt) {
  for (std::size_t mi = 0; mi < setup_.materials.size(); ++mi) {
    const Material& mat = setup_.materials[mi];
    if (!elastoviscoplastic(mat)) continue;
    const CurveTemperature at(mat.set, temperature_, peak_temperature_);
    for_each_yield_law(mat, int(mi), material_, at, [&](std::size_t i, const HerschelBulkley& law) {
      const Mat3 s = stress(i);
      const Real tau = std::sqrt(0.5 * s.squaredNorm());
      if (tau <= law.yield_stress) return;
      const Real returned = law.yield_stress + law.relaxed_overstress(tau - law.yield_stress, 0.5 * elasticity_[i], dt);
      set_stress(i, (returned / tau) * s);
    });
  }
}

}  // namespace bakesim::sph
