// Phase pressure: Tait, rising bubbles and risen dough (Eq 3.17, 3.48–3.52).
#include "sph/solver.hpp"

#include "core/parallel.hpp"
#include "physics/bubbles.hpp"

namespace bakesim::sph {

// Eq 3.17 (Tait, γ = 7); Eq 3.48–3.51 for rising bubbles; Eq 3.52 once the
// rise has ended (reference density ρ_f keeps the risen volume). With
// `vent_at_surface` a rising bubble that faced the oven air in the last heat
// phase (air_facing_, a surface particle facing the air more than a collider) is
// open to it and presses by Tait like dough: its gas escapes.
// With the divergence-free pressure the force phase has no pressure (the
// solves apply it) and this phase prepares the solves' factors.
void SphSolver::phase_pressure() {
  ScopedPhase t(timers_, t_pressure_);
  const Real gamma = setup_.settings.gamma;
  const bool clamp = setup_.settings.clamp_negative_pressure;
  const bool elastic = elastic_;
  p_over_rho2_.resize(x_.size());
  volume_.resize(x_.size());
  if (elastic) stress_rho2_.resize(x_.size());
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        const Real inv_rho2 = 1.0 / (rho_[i] * rho_[i]);
        volume_[i] = m_[i] / rho_[i];
        if (elastic) stress_rho2_[i] = stress(i) * inv_rho2;
        if (divergence_free_) {  // p_ is the density solve's
          p_over_rho2_[i] = 0;
          return;
        }
        const int mat = material_[i];
        const Real rho0 = setup_.materials[mat].rest_density;
        Real p;
        if (rise_state_[i] == 2) {
          Real reference = set_density_[i];
          if (bubble_[i] && setup_.bodies[body_[i]].bubbles.contract_on_cooling)
            reference = contracted_reference_density(reference, temperature_[i], set_temperature_[i]);
          p = tait_pressure(tait_b_[mat], rho_[i], reference, gamma);
        } else if (rise_state_[i] == 1 && !(setup_.bodies[body_[i]].bubbles.vent_at_surface && air_facing_[i])) {
          const Body& b = setup_.bodies[body_[i]];
          p = bubble_pressure(bubble_b_[body_[i]], rho_[i], rho0, temperature_[i], b.temperature);
        } else {
          p = tait_pressure(tait_b_[mat], rho_[i], rho0, gamma);
        }
        if (clamp && p < 0) p = 0;
        p_[i] = p;
        p_over_rho2_[i] = p * inv_rho2;
      },
      1024);
  if (divergence_free_) update_pressure_factors();
}

}  // namespace bakesim::sph
