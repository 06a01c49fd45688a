#pragma once
// Pressure gradient pair term (thesis Eq 3.18, the symmetric form that
// conserves momentum): a_i −= Σ_j m_j (P_i/ρ_i² + P_j/ρ_j²) ∇_i W_ij.
#include "core/types.hpp"

namespace bakesim::sph::forces {

// m_j (P_i/ρ_i² + P_j/ρ_j²) ∇_i W_ij; subtracted from the acceleration.
inline Vec3 pressure_gradient(Real mass_j, Real p_over_rho2_i, Real p_over_rho2_j, const Vec3& grad_w) {
  return (mass_j * (p_over_rho2_i + p_over_rho2_j)) * grad_w;
}

}  // namespace bakesim::sph::forces
