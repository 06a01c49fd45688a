#pragma once
// Monaghan's artificial viscosity (thesis Eq 3.35–3.41): for approaching pairs
// (v_ij · x_ij < 0), with φ = h v_ij·x_ij / (r² + ε h²),
//   Π_ij = (−α c φ + β φ²) / ρ̄_ij,     a_i −= Σ_j m_j Π_ij ∇_i W_ij;
// zero for receding pairs. Written branch-free: min(v·x, 0).
#include <algorithm>

#include "core/types.hpp"

namespace bakesim::sph::forces {

// Π_ij. `eps_h2` is ε h² of the pair's support h.
inline Real artificial_viscosity(const Vec3& v_ij, const Vec3& x_ij, Real r, Real support, Real eps_h2, Real rho_i,
                                 Real rho_j, Real alpha, Real beta, Real speed_of_sound) {
  const Real vx = std::min(v_ij.dot(x_ij), 0.0);
  const Real denom = r * r + eps_h2;
  const Real inv = 1.0 / (denom * denom * 0.5 * (rho_i + rho_j));
  const Real hvx = support * vx;
  return (-alpha * speed_of_sound * hvx * denom + beta * hvx * hvx) * inv;
}

}  // namespace bakesim::sph::forces
