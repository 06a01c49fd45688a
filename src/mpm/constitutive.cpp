#include "mpm/constitutive.hpp"
#include "physics/rheology.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <experimental/simd>

namespace bakesim::mpm {

namespace {

// The rare fallback for a nearly singular F, kept out of line: inlined into
// svd3x4's lane loop it made the hot function larger, and GCC 12 warned of
// JacobiSVD's singular values as maybe uninitialised (a false positive).
[[gnu::noinline]] Svd3 jacobi_svd(const Mat3& f) {
  Eigen::JacobiSVD<Mat3> s(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Svd3 out{s.matrixU(), s.matrixV(), s.singularValues()};
  // Rotations only: move a reflection into the smallest singular value.
  if (out.u.determinant() < 0) {
    out.u.col(2) *= -1;
    out.sigma[2] *= -1;
  }
  if (out.v.determinant() < 0) {
    out.v.col(2) *= -1;
    out.sigma[2] *= -1;
  }
  return out;
}

}  // namespace

namespace {

// Four matrices at once, one per SIMD lane (issue 25: the divisions and square
// roots of four particles in flight together instead of one after another).
// std::experimental::simd (libstdc++) rather than Eigen arrays: Eigen's
// select() is evaluated lane by lane, with a branch and a scalar division each.
namespace stdx = std::experimental;
using Lanes = stdx::fixed_size_simd<Real, 4>;

// Four symmetric 3×3 matrices by their six entries and the rotations Q built up on them.
struct SymmetricJacobi {
  Lanes a00, a11, a22, a01, a02, a12;
  Lanes q[3][3];  // q[row][col]
};

// One Jacobi rotation in the (p, r) plane of a symmetric 3×3 matrix held as
// its six entries (k the third index): zeroes a_pr and turns the columns p, r
// of Q with it. The update is the textbook one on the entries the rotation
// changes (a_pp, a_rr, a_kp, a_kr), with τ = s/(1 + c) for round-off
// (Press et al., Numerical Recipes, §11.1): about a third of the operations
// of turning the full matrix from both sides. Forced inline: GCC 12 left the
// three calls of a sweep out of line in the native build (55 instructions a
// particle and step each, their lanes passed through memory).
template <int p, int r>
[[gnu::always_inline]] inline void jacobi_rotate(Lanes& app, Lanes& arr, Lanes& apr, Lanes& akp, Lanes& akr,
                                                 Lanes (&q)[3][3]) {
  // Lanes whose a_pr is already zero turn by t = 0 (θ would be ±∞ or 0/0).
  const auto zero = apr == 0;
  Lanes denominator = 2 * apr;
  where(zero, denominator) = 1;
  const Lanes theta = (arr - app) / denominator;
  Lanes sign = 1;
  where(theta < 0, sign) = -1;
  Lanes t = sign / (abs(theta) + sqrt(theta * theta + 1));
  where(zero, t) = 0;
  const Lanes c = 1 / sqrt(t * t + 1), s = t * c, tau = s / (1 + c);
  app -= t * apr;
  arr += t * apr;
  apr = 0;  // zero by construction; round-off would only slow the stop
  const Lanes kp = akp, kr = akr;
  akp = kp - s * (kr + tau * kp);
  akr = kr + s * (kp - tau * kr);
  for (int i = 0; i < 3; ++i) {
    const Lanes qip = q[i][p], qir = q[i][r];
    q[i][p] = qip - s * (qir + tau * qip);
    q[i][r] = qir + s * (qip - tau * qir);
  }
}

// Cyclic Jacobi sweeps until the off-diagonal entries fall below 1e-12 of the
// diagonal (eigenvalues to 1e-24), in every lane. MPM deformation gradients
// are close to rotations, so FᵀF is close to diagonal in a few rotations;
// Jacobi is also accurate for nearly equal eigenvalues, where closed-form
// solutions lose the eigenvectors.
void jacobi_sweeps(SymmetricJacobi& m) {
  for (int sweep = 0; sweep < 12; ++sweep) {
    const Lanes off = m.a01 * m.a01 + m.a02 * m.a02 + m.a12 * m.a12;
    const Lanes diag = m.a00 * m.a00 + m.a11 * m.a11 + m.a22 * m.a22;
    if (all_of(off <= 1e-24 * diag)) break;
    jacobi_rotate<0, 1>(m.a00, m.a11, m.a01, m.a02, m.a12, m.q);  // k = 2: a_k0 = a02, a_k1 = a12
    jacobi_rotate<0, 2>(m.a00, m.a22, m.a02, m.a01, m.a12, m.q);  // k = 1: a_k0 = a01, a_k2 = a12
    jacobi_rotate<1, 2>(m.a11, m.a22, m.a12, m.a01, m.a02, m.q);  // k = 0: a_k1 = a01, a_k2 = a02
  }
}

}  // namespace

Svd3 svd3(const Mat3& f) {
  const Mat3 four[4] = {f, f, f, f};
  Svd3 out[4];
  svd3x4(four, out);
  return out[0];
}

void svd3x4(const Mat3 (&f)[4], Svd3 (&out)[4]) {
  // F's entries lane by lane, and FᵀF.
  Lanes fl[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) fl[i][j] = Lanes([&](auto l) { return f[l](i, j); });
  const auto gram = [&](int i, int j) { return fl[0][i] * fl[0][j] + fl[1][i] * fl[1][j] + fl[2][i] * fl[2][j]; };
  SymmetricJacobi m{gram(0, 0), gram(1, 1), gram(2, 2), gram(0, 1), gram(0, 2), gram(1, 2), {}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.q[i][j] = i == j ? 1 : 0;
  jacobi_sweeps(m);
  // Lane by lane: eigenvalues sorted largest first with
  // their columns of Q (three compare-and-swaps), V = Q made a rotation,
  // U = F V Σ⁻¹ with Gram–Schmidt and a cross product.
  Lanes s2[3] = {m.a00, m.a11, m.a22};
  Lanes(&v)[3][3] = m.q;
  const auto order = [&](int a, int b) {
    const auto swap = s2[a] < s2[b];
    const Lanes sa = s2[a];
    where(swap, s2[a]) = s2[b];
    where(swap, s2[b]) = sa;
    for (int i = 0; i < 3; ++i) {
      const Lanes va = v[i][a];
      where(swap, v[i][a]) = v[i][b];
      where(swap, v[i][b]) = va;
    }
  };
  order(0, 1), order(1, 2), order(0, 1);
  const Lanes det_v = v[0][0] * (v[1][1] * v[2][2] - v[2][1] * v[1][2]) -
                      v[0][1] * (v[1][0] * v[2][2] - v[2][0] * v[1][2]) +
                      v[0][2] * (v[1][0] * v[2][1] - v[2][0] * v[1][1]);
  for (int i = 0; i < 3; ++i) where(det_v < 0, v[i][2]) = -v[i][2];
  // Tiny singular values lose their relative accuracy when squared: those lanes take the Jacobi SVD.
  const auto tiny = !(s2[2] > 1e-8 * s2[0]);
  Lanes fv[3][3];  // F V
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) fv[i][k] = fl[i][0] * v[0][k] + fl[i][1] * v[1][k] + fl[i][2] * v[2][k];
  const Lanes sigma0 = sqrt(s2[0]), sigma1 = sqrt(s2[1]);
  Lanes u[3][3];
  for (int i = 0; i < 3; ++i) u[i][0] = fv[i][0] / sigma0;
  const Lanes along = u[0][0] * fv[0][1] + u[1][0] * fv[1][1] + u[2][0] * fv[2][1];
  for (int i = 0; i < 3; ++i) u[i][1] = fv[i][1] - along * u[i][0];  // Gram–Schmidt against round-off
  const Lanes norm1 = sqrt(u[0][1] * u[0][1] + u[1][1] * u[1][1] + u[2][1] * u[2][1]);
  for (int i = 0; i < 3; ++i) u[i][1] /= norm1;
  // Third column by the cross product keeps U a rotation; its sign gives det F.
  u[0][2] = u[1][0] * u[2][1] - u[2][0] * u[1][1];
  u[1][2] = u[2][0] * u[0][1] - u[0][0] * u[2][1];
  u[2][2] = u[0][0] * u[1][1] - u[1][0] * u[0][1];
  const Lanes sigma2 = u[0][2] * fv[0][2] + u[1][2] * fv[1][2] + u[2][2] * fv[2][2];
  for (int l = 0; l < 4; ++l) {
    if (tiny[l]) {
      out[l] = jacobi_svd(f[l]);
      continue;
    }
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) out[l].u(i, k) = u[i][k][l], out[l].v(i, k) = v[i][k][l];
    out[l].sigma = Vec3(sigma0[l], sigma1[l], sigma2[l]);
  }
}

// ε = ln max(|σ|, 1e-12) and σ = e^ε lane by lane: Eigen evaluates log and exp
// of a 4-lane array on SIMD vectors (its own polynomial kernels, within an ulp
// or two of the C library's; std::log and std::exp are one call per value).
// One particle's three values take three lanes of the same kernels, so the
// chunk and the single-particle paths give the same numbers.
namespace {
Lane4 strain_of(const Lane4& sigma) { return sigma.abs().max(Real(1e-12)).log(); }
}  // namespace

Vec3 hencky_strain(const Vec3& sigma) {
  const Lane4 e = strain_of(Lane4(sigma[0], sigma[1], sigma[2], 1));
  return Vec3(e[0], e[1], e[2]);
}

Vec3 hencky_stretch(const Vec3& strain) {
  const Lane4 e = Lane4(strain[0], strain[1], strain[2], 0).exp();
  return Vec3(e[0], e[1], e[2]);
}

void hencky_stretch_x4(const Vec3 (&strain)[4], Vec3 (&sigma)[4]) {
  for (int i = 0; i < 3; ++i) {
    const Lane4 e = Lane4(strain[0][i], strain[1][i], strain[2][i], strain[3][i]).exp();
    for (int l = 0; l < 4; ++l) sigma[l][i] = e[l];
  }
}

void hencky_strain_x4(const Svd3 (&svd)[4], Vec3 (&strain)[4]) {
  for (int i = 0; i < 3; ++i) {
    const Lane4 e = strain_of(Lane4(svd[0].sigma[i], svd[1].sigma[i], svd[2].sigma[i], svd[3].sigma[i]));
    for (int l = 0; l < 4; ++l) strain[l][i] = e[l];
  }
}

Mat3 hencky_stress(const Lame& lame, const Vec3& strain, const Mat3& u) {
  const Vec3 t = (2 * lame.mu * strain).array() + lame.lambda * strain.sum();
  return u * t.asDiagonal() * u.transpose();
}

Mat3 kirchhoff_stress(const Hencky& law, const Mat3&, const Svd3& svd) {
  return hencky_stress(law.lame, hencky_strain(svd.sigma), svd.u);
}

Mat3 kirchhoff_stress(const FixedCorotated& law, const Mat3& f, const Svd3& svd) {
  const Mat3 r = svd.u * svd.v.transpose();
  const Real j = svd.sigma.prod();
  return 2 * law.lame.mu * (f - r) * f.transpose() + (law.lame.lambda * (j - 1) * j) * Mat3::Identity();
}

Mat3 kirchhoff_stress(const ElasticLaw& law, const Mat3& f, const Svd3& svd) {
  return std::visit([&](const auto& l) { return kirchhoff_stress(l, f, svd); }, law);
}

Real energy_density(const ElasticLaw& law, const Mat3& f) {
  const Svd3 s = svd3(f);
  if (const auto* h = std::get_if<Hencky>(&law)) {
    const Vec3 eps = hencky_strain(s.sigma);
    return h->lame.mu * eps.squaredNorm() + 0.5 * h->lame.lambda * eps.sum() * eps.sum();
  }
  const auto& c = std::get<FixedCorotated>(law);
  const Real j = s.sigma.prod();
  return c.lame.mu * (s.sigma - Vec3::Ones()).squaredNorm() + 0.5 * c.lame.lambda * (j - 1) * (j - 1);
}

namespace {

// Spec 3.2 steps 1–4 in principal Hencky strains for the ellipse
// q² + A p² ≤ τ_y² (A = 0: von Mises). Minimising the energy distance
// (p − p_tr)²/(2K) + (q − q_tr)²/(6μ) on f = 0 gives p = p_tr / (1 + 2KAΔγ),
// q = q_tr / (1 + 6μΔγ); f(Δγ) is convex and decreasing, so Newton from any
// Δγ below its root approaches it monotonically from below.
bool ellipse_return(Real yield, Real viscosity, Real a, const Lame& lame, Real dt, Vec3& eps) {
  const Real bulk = lame.lambda + 2 * lame.mu / 3;
  const Real tr = eps.sum();
  const Vec3 dev = eps.array() - tr / 3;
  const Real p_tr = -bulk * tr;
  const Real q_tr = std::sqrt(1.5) * 2 * lame.mu * dev.norm();
  const Real y2 = yield * yield;
  if (q_tr * q_tr + a * p_tr * p_tr <= y2) return false;
  Real p, q;
  if (yield <= 0) {
    q = 0;
    p = a > 0 ? 0 : p_tr;
  } else if (a == 0) {  // von Mises: radial return, pressure unchanged
    q = yield;
    p = p_tr;
  } else {
    // Start from the larger of two roots that each leave out one term of f: at
    // either f is still ≥ 0 (the other term's share), so both lie at or below
    // the root and Newton still approaches it from below, from closer than 0.
    const Real y = std::sqrt(y2);
    const Real g_shear = q_tr > y ? (q_tr / y - 1) / (6 * lame.mu) : 0;
    const Real p_abs = std::sqrt(a) * std::abs(p_tr);
    const Real g_pressure = p_abs > y ? (p_abs / y - 1) / (2 * bulk * a) : 0;
    Real g = std::max(g_shear, g_pressure);
    for (int it = 0; it < 100; ++it) {
      const Real sq = 1 / (1 + 6 * lame.mu * g), sp = 1 / (1 + 2 * bulk * a * g);
      const Real qq = q_tr * sq, pp = p_tr * sp;
      const Real f = qq * qq + a * pp * pp - y2;
      if (f <= 1e-12 * y2) break;
      const Real df = -12 * lame.mu * qq * qq * sq - 4 * bulk * a * a * pp * pp * sp;
      g -= f / df;
    }
    q = q_tr / (1 + 6 * lame.mu * g);
    p = p_tr / (1 + 2 * bulk * a * g);
  }
  const Real keep = viscosity > 0 ? 1.0 / (1.0 + 2 * lame.mu * dt / viscosity) : 0.0;
  const Real p_new = p + keep * (p_tr - p), q_new = q + keep * (q_tr - q);
  const Vec3 dev_new = q_tr > 0 ? Vec3(dev * (q_new / q_tr)) : dev;
  const Real tr_new = -p_new / bulk;
  eps = dev_new.array() + tr_new / 3;
  return true;
}

}  // namespace

bool return_strain(const VonMises& law, const Lame& lame, Real dt, Real, Vec3& strain) {
  return ellipse_return(law.yield_stress, law.viscosity, 0, lame, dt, strain);
}

bool return_strain(const HerschelBulkleyFlow& law, const Lame& lame, Real dt, Real, Vec3& strain) {
  const Real tr = strain.sum();
  const Vec3 dev = strain.array() - tr / 3;
  // Shear stress equivalent √(J₂) = q/√3 = √2 μ |dev ε| of the trial state.
  const Real tau_trial = std::sqrt(2.0) * lame.mu * dev.norm();
  const Real overstress = tau_trial - law.yield_stress;
  if (overstress <= 0) return false;
  const HerschelBulkley flow{law.yield_stress, law.viscosity, law.flow_index};
  const Real tau = law.yield_stress + flow.relaxed_overstress(overstress, lame.mu, dt);
  strain = (dev * (tau / tau_trial)).array() + tr / 3;  // radial return: pressure unchanged
  return true;
}

Real CamClay::porosity(Real plastic_j) const {
  return std::clamp((plastic_j - 1 + initial_porosity) / plastic_j, Real(0), Real(0.95));
}

Real CamClay::a(Real plastic_j) const {
  const Real n = porosity(plastic_j);
  return cohesion_slope * n / (1 - n);
}

bool return_strain(const CamClay& law, const Lame& lame, Real dt, Real plastic_j, Vec3& strain) {
  return ellipse_return(law.yield_stress, law.viscosity, law.a(plastic_j), lame, dt, strain);
}

namespace {
template <class Law>
Svd3 return_on_svd(const Law& law, const Lame& lame, Real dt, Real plastic_j, const Svd3& svd) {
  Vec3 strain = hencky_strain(svd.sigma);
  if (!return_strain(law, lame, dt, plastic_j, strain)) return svd;
  return Svd3{svd.u, svd.v, hencky_stretch(strain)};
}
}  // namespace

Svd3 return_map(const VonMises& law, const Lame& lame, Real dt, Real plastic_j, const Svd3& svd) {
  return return_on_svd(law, lame, dt, plastic_j, svd);
}
Svd3 return_map(const CamClay& law, const Lame& lame, Real dt, Real plastic_j, const Svd3& svd) {
  return return_on_svd(law, lame, dt, plastic_j, svd);
}
Svd3 return_map(const HerschelBulkleyFlow& law, const Lame& lame, Real dt, Real plastic_j, const Svd3& svd) {
  return return_on_svd(law, lame, dt, plastic_j, svd);
}

Real yield_function(const CamClay& law, Real plastic_j, const Vec3& tau) {
  const Real p = -tau.sum() / 3;
  const Vec3 dev = tau.array() + p;
  const Real q = std::sqrt(1.5) * dev.norm();
  return q * q + law.a(plastic_j) * p * p - law.yield_stress * law.yield_stress;
}

}  // namespace bakesim::mpm
