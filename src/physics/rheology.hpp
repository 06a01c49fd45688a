#pragma once
// Yield-stress flow: the Herschel–Bulkley law of doughs and batters,
//   τ = τ_y + K γ̇ⁿ  where the material flows (|τ| > τ_y), rigid below τ_y,
// with the shear yield stress τ_y, the consistency K and the flow index n
// (Bingham: n = 1, K the plastic viscosity; Newtonian: τ_y = 0, n = 1).
// A solver with a viscosity (SPH) uses the apparent viscosity τ/γ̇ with
// Papanastasiou's (1987) exponential regularisation, which keeps it finite at
// rest:
//   μ(γ̇) = τ_y (1 − e^{−γ̇/γ̇_r}) / γ̇ + K max(γ̇, γ̇_r)^{n−1},
// μ(0) = τ_y/γ̇_r + K γ̇_r^{n−1}; γ̇_r (1/s) is the regularisation rate, far
// below the shear rates of the flow. A solver with a yield surface (MPM's von
// Mises return) uses τ_y and K directly: von_mises_equivalent() gives its
// parameters, whose steady simple shear is τ = τ_y + K γ̇ for n = 1.
// Both solvers read τ_y and K at the particle's temperature from the
// material's curves; this law is what they share.
#include <algorithm>
#include <cmath>

#include "core/types.hpp"

namespace bakesim {

struct HerschelBulkley {
  Real yield_stress = 0;       // τ_y, shear yield stress, Pa
  Real consistency = 1e-3;     // K, Pa·sⁿ
  Real flow_index = 1;         // n (< 1 shear-thinning, > 1 shear-thickening)
  Real regularisation = 1e-3;  // γ̇_r, 1/s

  // τ(γ̇) of steady simple shear above the yield stress.
  Real shear_stress(Real shear_rate) const {
    return yield_stress + consistency * std::pow(std::max(shear_rate, Real(0)), flow_index);
  }
  // The regularised apparent viscosity τ/γ̇ (Papanastasiou 1987), Pa·s.
  Real apparent_viscosity(Real shear_rate) const {
    const Real rate = std::max(shear_rate, Real(0));
    const Real x = rate / regularisation;
    // (1 − e^{−x})/x → 1 as x → 0 (expm1 keeps it exact for small x).
    const Real yield_part = x > 1e-8 ? -std::expm1(-x) / x : 1.0 - 0.5 * x;
    const Real power =
        flow_index == 1 ? consistency : consistency * std::pow(std::max(rate, regularisation), flow_index - 1);
    return yield_stress / regularisation * yield_part + power;
  }
  // The largest apparent viscosity (at rest), for time-step and solver choices.
  Real viscosity_at_rest() const { return apparent_viscosity(0); }

  // A solver with a yield surface (MPM): one backward-Euler step of the
  // Perzyna overstress flow. Given the trial shear overstress x_tr = τ_tr − τ_y
  // of an elastic predictor with shear modulus G, returns the overstress x
  // left after the plastic shear rate γ̇_p = (x/K)^{1/n} has acted for dt:
  //   x + G dt (x/K)^{1/n} = x_tr,
  // so that in steady shear at rate γ̇ the stress is exactly τ_y + K γ̇ⁿ.
  // n = 1: x = x_tr / (1 + G dt / K). The left side increases with x, so a
  // Newton step safeguarded by bisection on [0, x_tr] converges.
  Real relaxed_overstress(Real trial_overstress, Real shear_modulus, Real dt) const {
    if (trial_overstress <= 0) return trial_overstress;
    if (consistency <= 0) return 0;  // rate-independent: back onto the yield surface
    const Real c = shear_modulus * dt, m = 1 / flow_index;
    if (flow_index == 1) return trial_overstress / (1 + c / consistency);
    Real lo = 0, hi = trial_overstress, x = trial_overstress;
    for (int it = 0; it < 100; ++it) {
      const Real rate = std::pow(x / consistency, m);
      const Real f = x + c * rate - trial_overstress;
      if (f > 0)
        hi = x;
      else
        lo = x;
      if (std::abs(f) <= 1e-13 * trial_overstress || hi - lo <= 1e-15 * trial_overstress) break;
      const Real df = 1 + c * m * rate / std::max(x, Real(1e-300));
      Real next = x - f / df;
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      x = next;
    }
    return x;
  }
};

// The von Mises viscoplastic parameters (uniaxial yield stress and the
// relaxation viscosity η of the MPM return) whose steady simple shear is this
// Bingham law: q = √3 τ_y, η = 2K (docs/physics.md, "Viscoplastic flow").
struct VonMisesEquivalent {
  Real uniaxial_yield_stress, viscosity;
};
inline VonMisesEquivalent von_mises_equivalent(const HerschelBulkley& law) {
  return {std::sqrt(3.0) * law.yield_stress, 2.0 * law.consistency};
}

}  // namespace bakesim
