#pragma once
// Viscosity pair term (thesis Eq 3.19 with the viscosity kernel's Laplacian,
// Eq 3.8, ∇²W_visc(r) = C (h − r)): ρ_i a_i −= Σ_j μ̄_ij V_j ∇²W_visc(r) (v_i − v_j),
// μ̄_ij = (μ_i + μ_j)/2. Every listed pair has r < h, so the weight is ≥ 0.
#include "core/types.hpp"

namespace bakesim::sph::forces {

// μ̄_ij V_j C (h − r): the weight of (v_i − v_j); `coefficient` is C of Eq 3.8 for support h.
inline Real viscosity_weight(Real mu_i, Real mu_j, Real volume_j, Real coefficient, Real support, Real r) {
  return 0.5 * (mu_i + mu_j) * volume_j * coefficient * (support - r);
}

}  // namespace bakesim::sph::forces
