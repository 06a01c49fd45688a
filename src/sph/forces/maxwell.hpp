#pragma once
// Divergence of the Maxwell viscoelastic stress (thesis Eq 2.18 in SPH form,
// symmetric like the pressure term): a_i += Σ_j m_j (S_i/ρ_i² + S_j/ρ_j²) ∇_i W_ij.
#include "core/types.hpp"

namespace bakesim::sph::forces {

inline Vec3 stress_divergence(Real mass_j, const Mat3& stress_over_rho2_i, const Mat3& stress_over_rho2_j,
                              const Vec3& grad_w) {
  return mass_j * ((stress_over_rho2_i + stress_over_rho2_j) * grad_w);
}

}  // namespace bakesim::sph::forces
