#pragma once
// Colour-field surface tension (thesis Eq 3.28–3.30): with the colour gradient
// N = ∇C (pointing into the fluid) and its Laplacian ∇²C,
//   a_i = −(σ/ρ_i) ∇²C N/|N|,
// applied only where |N| h exceeds a threshold (a stable direction).
#include "core/types.hpp"

namespace bakesim::sph::forces {

// `normal_length` is |N| (> 0).
inline Vec3 surface_tension(Real sigma, Real rho_i, Real colour_laplacian, const Vec3& normal, Real normal_length) {
  return (-sigma / rho_i * colour_laplacian / normal_length) * normal;
}

}  // namespace bakesim::sph::forces
