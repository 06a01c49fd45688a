#pragma once
// Finite-strain elastoplastic laws of the MPM solver (spec mpm-baking.md 3.1,
// 3.2): small value types, dispatched once per material group. Each maps the
// trial elastic deformation gradient F^E to the Kirchhoff stress τ = P Fᵀ and
// (for plasticity) projects F^E back onto the admissible set.
#include <variant>

#include "core/types.hpp"

namespace bakesim::mpm {

// Lamé parameters from Young's modulus E and Poisson's ratio ν.
struct Lame {
  Real mu, lambda;
  static Lame from_young(Real young, Real poisson) {
    return {young / (2 * (1 + poisson)), young * poisson / ((1 + poisson) * (1 - 2 * poisson))};
  }
};

// F = U diag(σ) Vᵀ with U, V rotations (det +1), σ sorted largest first; σ may
// have a negative last entry for an inverted F. Cyclic Jacobi eigen-decomposition
// of FᵀF, with Eigen's Jacobi SVD where a tiny σ (below 1e-4 of the largest)
// would lose its accuracy when squared.
struct Svd3 {
  Mat3 u, v;
  Vec3 sigma;
};
// svd3 is svd3x4 with f in every lane.
Svd3 svd3(const Mat3& f);
// The SVDs of four matrices at once (Jacobi sweeps, sort and U on 4-lane
// vectors, one matrix per lane, until every lane has converged); each result
// is within round-off of svd3 of its matrix.
void svd3x4(const Mat3 (&f)[4], Svd3 (&out)[4]);

// ψ = μ tr(ε²) + ½ λ (tr ε)², ε = log σ (Hencky strain); τ = U (2μ ε + λ tr ε I) Uᵀ.
struct Hencky {
  Lame lame;
};
// ψ = μ Σ(σ_i − 1)² + ½ λ (J − 1)²; τ = 2μ (F − R) Fᵀ + λ (J − 1) J I (Stomakhin et al. 2013).
struct FixedCorotated {
  Lame lame;
};
using ElasticLaw = std::variant<Hencky, FixedCorotated>;

// Kirchhoff stress of an elastic law at F (and its SVD). The solver calls the
// overload of the material's law inside one std::visit per material group.
Mat3 kirchhoff_stress(const Hencky& law, const Mat3& f, const Svd3& svd);
// The principal Hencky strains ε = log|σ| (|σ| at least 1e-12), and the Hencky
// stress from them and U: what the solver computes once per particle for the
// plastic return and the stress (each took its own logarithms before).
Vec3 hencky_strain(const Vec3& sigma);
// Back from strains to stretches, σ = e^ε; and both for four particles at
// once (the constitutive phase's chunk). Eigen's logarithm and exponential on
// 4-lane vectors, within round-off of std::log and std::exp.
Vec3 hencky_stretch(const Vec3& strain);
void hencky_strain_x4(const Svd3 (&svd)[4], Vec3 (&strain)[4]);
void hencky_stretch_x4(const Vec3 (&strain)[4], Vec3 (&sigma)[4]);
Mat3 hencky_stress(const Lame& lame, const Vec3& strain, const Mat3& u);
Mat3 kirchhoff_stress(const FixedCorotated& law, const Mat3& f, const Svd3& svd);
Mat3 kirchhoff_stress(const ElasticLaw& law, const Mat3& f, const Svd3& svd);
// Energy density ψ(F) (for tests against finite differences).
Real energy_density(const ElasticLaw& law, const Mat3& f);

struct NoPlasticity {};
// von Mises in Hencky strain: q = sqrt(3/2) ‖dev τ‖ ≤ τ_y, with the
// viscoplastic relaxation of spec 3.2 step 3 (viscosity η; 0: rate-independent).
struct VonMises {
  Real yield_stress;   // τ_y (uniaxial), Pa
  Real viscosity = 0;  // η, Pa·s
};
// Porous Cam-clay of spec 3.2: f = q² + A(n) p² − τ_y² ≤ 0 with p = −tr τ / 3,
// A(n) = a_p n / (1 − n) and the porosity n = (J^P − 1 + n₀) / J^P in
// [0, 0.95]; A = 0 is von Mises. Same viscoplastic relaxation.
struct CamClay {
  Real yield_stress;
  Real viscosity = 0;
  Real cohesion_slope = 2;    // a_p
  Real initial_porosity = 0;  // n₀
  Real porosity(Real plastic_j) const;
  Real a(Real plastic_j) const;  // A(n(J^P))
};
// A Herschel–Bulkley fluid with a true yield surface: von Mises in Hencky
// strain with the shear yield stress τ_y (uniaxial √3 τ_y), above which the
// overstress relaxes by the shared law's backward-Euler Perzyna flow
// (HerschelBulkley::relaxed_overstress): steady shear gives τ = τ_y + K γ̇ⁿ,
// the same law and numbers as SPH's material.herschel_bulkley. The field
// names follow the setting curves (yield_stress = τ_y, viscosity = K).
struct HerschelBulkleyFlow {
  Real yield_stress;    // τ_y, shear, Pa
  Real viscosity;       // K, Pa·sⁿ
  Real flow_index = 1;  // n
};
using PlasticLaw = std::variant<NoPlasticity, VonMises, CamClay, HerschelBulkleyFlow>;

// Return mapping of spec 3.2 for a Hencky material: projects the trial F^E
// (given by its SVD) and returns the SVD of the new F^E — the same rotations
// with new singular values; unchanged when elastic. Every plastic law takes
// the particle's plastic volume ratio J^P (Cam-clay's porosity; von Mises
// ignores it). Cam-clay: the closest point of the ellipse in the energy norm
// (a scalar Newton solve for the plastic multiplier), then the relaxation.
Svd3 return_map(const VonMises& law, const Lame& lame, Real dt, Real plastic_j, const Svd3& svd);
Svd3 return_map(const CamClay& law, const Lame& lame, Real dt, Real plastic_j, const Svd3& svd);
Svd3 return_map(const HerschelBulkleyFlow& law, const Lame& lame, Real dt, Real plastic_j, const Svd3& svd);
// The same returns on the principal Hencky strains of the trial F^E: true, with
// the strains projected, where the law yielded; false, untouched, where not.
bool return_strain(const VonMises& law, const Lame& lame, Real dt, Real plastic_j, Vec3& strain);
bool return_strain(const CamClay& law, const Lame& lame, Real dt, Real plastic_j, Vec3& strain);
bool return_strain(const HerschelBulkleyFlow& law, const Lame& lame, Real dt, Real plastic_j, Vec3& strain);
// Yield function f(τ) of a principal Kirchhoff stress (for tests).
Real yield_function(const CamClay& law, Real plastic_j, const Vec3& principal_tau);
inline Mat3 compose(const Svd3& s) { return s.u * s.sigma.asDiagonal() * s.v.transpose(); }

}  // namespace bakesim::mpm
