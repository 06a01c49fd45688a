#pragma once
// Non-linear (upper-convected in the Jaumann sense) Maxwell viscoelastic
// stress, thesis Eq 3.20–3.27:
//   dS/dt = R + μ_e D' − S/λ,   R = W S − S W
// with L = ∇v (L_ab = ∂v_a/∂x_b), strain rate ε̇ = ½(L + Lᵀ), spin
// W = ½(L − Lᵀ) and the traceless D' = ε̇ − tr(ε̇)/3 I. The seed's
// R = ½(S·ω − ω·S) with ω = ∇v − ∇vᵀ in its index convention equals W S − S W.
// See docs/physics.md for the one departure (D' is made traceless as the seed
// says it is; the printed ½D − tr(D)/3 I is not).
#include <cmath>

#include "core/types.hpp"

namespace bakesim {

struct MaxwellRates {
  Mat3 strain_rate_deviator;  // D'
  Mat3 rotation;              // R = W S − S W
};

inline MaxwellRates maxwell_rates(const Mat3& stress, const Mat3& velocity_gradient) {
  const Mat3 eps = 0.5 * (velocity_gradient + velocity_gradient.transpose());
  const Mat3 spin = 0.5 * (velocity_gradient - velocity_gradient.transpose());
  MaxwellRates r;
  r.strain_rate_deviator = eps - (eps.trace() / 3.0) * Mat3::Identity();
  r.rotation = spin * stress - stress * spin;
  return r;
}

// dS/dt (Eq 3.20).
inline Mat3 maxwell_stress_rate(const Mat3& stress, const Mat3& velocity_gradient, Real elasticity,
                                Real relaxation_time) {
  const MaxwellRates r = maxwell_rates(stress, velocity_gradient);
  return r.rotation + elasticity * r.strain_rate_deviator - stress / relaxation_time;
}

// w = λ(1 − e^{−dt/λ}): the weight of the forcing over one step (→ dt for
// λ ≫ dt), written as dt · (1 − e^{−x})/x to stay accurate for small x.
inline Real maxwell_forcing_weight(Real relaxation_time, Real dt) {
  const Real x = dt / relaxation_time;
  return x > 1e-8 ? -std::expm1(-x) / x * dt : dt;
}

// One step of Eq 3.20 with the relaxation term integrated exactly
// (exponential integrator; the forcing R + μ_e D' is held over the step):
//   S(t+dt) = e^{−dt/λ} S + w (R + μ_e D'),  w = λ (1 − e^{−dt/λ}).
// Exact for pure relaxation (S decays as e^{−t/λ}) and stable for any dt/λ.
inline Mat3 maxwell_stress_step(const Mat3& stress, const Mat3& velocity_gradient, Real elasticity,
                                Real relaxation_time, Real dt) {
  const MaxwellRates r = maxwell_rates(stress, velocity_gradient);
  const Real decay = std::exp(-dt / relaxation_time);
  return decay * stress +
         maxwell_forcing_weight(relaxation_time, dt) * (r.rotation + elasticity * r.strain_rate_deviator);
}

// The same step split for a semi-implicit integration (solver.sph.elasticity_solver
// implicit): the relaxation e^{−dt/λ} S is taken before the velocity solve,
// the forcing w (R + μ_e D') after it, with the velocity gradient of the
// solved velocities (maxwell_forcing_step). In the solve the elastic part of
// that forcing acts as a viscous stress 2 η D' with η = w μ_e / 2
// (maxwell_step_viscosity): backward Euler for the elastic shear waves, so
// they no longer bound the step. The rotation R is then that of the relaxed
// stress, a difference of order dt²/λ from maxwell_stress_step. Both take the
// step's forcing weight w = maxwell_forcing_weight(λ, dt), computed once.
inline Real maxwell_step_viscosity(Real elasticity, Real forcing_weight) { return 0.5 * forcing_weight * elasticity; }

inline Mat3 maxwell_forcing_step(const Mat3& relaxed_stress, const Mat3& velocity_gradient, Real elasticity,
                                 Real forcing_weight) {
  const MaxwellRates r = maxwell_rates(relaxed_stress, velocity_gradient);
  return relaxed_stress + forcing_weight * (r.rotation + elasticity * r.strain_rate_deviator);
}

}  // namespace bakesim
