#pragma once
// Monaghan's artificial stress (J. Comput. Phys. 159, 2000; Gray, Monaghan and
// Swift 2001) against the tensile instability of elastic SPH. Per particle,
// from the principal stresses σ'_a of the total stress (S − P I)/ρ²:
//   R_i = Q diag(−ε max(σ'_a, 0)) Qᵀ   (only tensile directions),
// and per pair a short-range repulsion
//   a_i += Σ_j m_j f_ij^n (R_i + R_j) ∇_i W_ij,  f_ij = W(r)/W(Δp).
#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/types.hpp"

namespace bakesim::sph::forces {

inline Mat3 artificial_stress_tensor(const Mat3& stress_over_rho2, Real p_over_rho2, Real epsilon) {
  const Mat3 sigma = stress_over_rho2 - p_over_rho2 * Mat3::Identity();
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(sigma);
  const Vec3 r = (-epsilon * eig.eigenvalues().cwiseMax(0.0)).eval();
  return eig.eigenvectors() * r.asDiagonal() * eig.eigenvectors().transpose();
}

// m_j f^n (R_i + R_j) ∇_i W_ij with f = W(r)/W(Δp) (n = 4 without pow).
inline Vec3 artificial_stress(Real mass_j, Real f, Real exponent, const Mat3& r_i, const Mat3& r_j,
                              const Vec3& grad_w) {
  const Real fn = exponent == 4.0 ? (f * f) * (f * f) : std::pow(f, exponent);
  return (mass_j * fn) * ((r_i + r_j) * grad_w);
}

}  // namespace bakesim::sph::forces
