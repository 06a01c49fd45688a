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

Svd3 jacobi_svd(const Mat3& f) {
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

// A symmetric 3×3 matrix by its six entries and the rotation Q built up on it.
template <class T>
struct SymmetricJacobi {
  T a00, a11, a22, a01, a02, a12;
  T q[3][3];  // q[row][col]
};

// One Jacobi rotation in the (p, r) plane of a symmetric 3×3 matrix held as
// its six entries (k the third index): zeroes a_pr and turns the columns p, r
// of Q with it. The update is the textbook one on the entries the rotation
// changes (a_pp, a_rr, a_kp, a_kr), with τ = s/(1 + c) for round-off
// (Press et al., Numerical Recipes, §11.1): about a third of the operations
// of turning the full matrix from both sides.
template <int p, int r, class T>
inline void jacobi_rotate(T& app, T& arr, T& apr, T& akp, T& akr, T (&q)[3][3]) {
  using std::abs, std::sqrt;
  T t;
  if constexpr (std::is_same_v<T, Real>) {
    if (apr == 0) return;
    const Real theta = (arr - app) / (2 * apr);
    t = (theta >= 0 ? 1 : -1) / (abs(theta) + sqrt(theta * theta + 1));
  } else {
    // Lanes whose a_pr is already zero turn by t = 0 (θ would be ±∞ or 0/0).
    const auto zero = apr == 0;
    T denominator = 2 * apr;
    where(zero, denominator) = 1;
    const T theta = (arr - app) / denominator;
    T sign = 1;
    where(theta < 0, sign) = -1;
    t = sign / (abs(theta) + sqrt(theta * theta + 1));
    where(zero, t) = 0;
  }
  const T c = 1 / sqrt(t * t + 1), s = t * c, tau = s / (1 + c);
  app -= t * apr;
  arr += t * apr;
  apr = 0;  // zero by construction; round-off would only slow the stop
  const T kp = akp, kr = akr;
  akp = kp - s * (kr + tau * kp);
  akr = kr + s * (kp - tau * kr);
  for (int i = 0; i < 3; ++i) {
    const T qip = q[i][p], qir = q[i][r];
    q[i][p] = qip - s * (qir + tau * qip);
    q[i][r] = qir + s * (qip - tau * qir);
  }
}

// Cyclic Jacobi sweeps until the off-diagonal entries fall below 1e-12 of the
// diagonal (eigenvalues to 1e-24), in every lane. MPM deformation gradients
// are close to rotations, so FᵀF is close to diagonal in a few rotations;
// Jacobi is also accurate for nearly equal eigenvalues, where closed-form
// solutions lose the eigenvectors.
template <class T>
void jacobi_sweeps(SymmetricJacobi<T>& m) {
  for (int sweep = 0; sweep < 12; ++sweep) {
    const T off = m.a01 * m.a01 + m.a02 * m.a02 + m.a12 * m.a12;
    const T diag = m.a00 * m.a00 + m.a11 * m.a11 + m.a22 * m.a22;
    if constexpr (std::is_same_v<T, Real>) {
      if (off <= 1e-24 * diag) break;
    } else {
      if (all_of(off <= 1e-24 * diag)) break;
    }
    jacobi_rotate<0, 1>(m.a00, m.a11, m.a01, m.a02, m.a12, m.q);  // k = 2: a_k0 = a02, a_k1 = a12
    jacobi_rotate<0, 2>(m.a00, m.a22, m.a02, m.a01, m.a12, m.q);  // k = 1: a_k0 = a01, a_k2 = a12
    jacobi_rotate<1, 2>(m.a11, m.a22, m.a12, m.a01, m.a02, m.q);  // k = 0: a_k1 = a01, a_k2 = a02
  }
}

// F = U Σ Vᵀ from the eigen-decomposition FᵀF = Q diag(s²) Qᵀ: V = Q sorted
// largest first, U = F V Σ⁻¹.
Svd3 svd_from_eigen(const Mat3& f, const Mat3& q, const Vec3& s2) {
  int order[3] = {0, 1, 2};
  if (s2[order[0]] < s2[order[1]]) std::swap(order[0], order[1]);
  if (s2[order[1]] < s2[order[2]]) std::swap(order[1], order[2]);
  if (s2[order[0]] < s2[order[1]]) std::swap(order[0], order[1]);
  const Real scale = s2[order[0]];
  // Tiny singular values lose their relative accuracy when squared.
  if (!(s2[order[2]] > 1e-8 * scale)) return jacobi_svd(f);
  Svd3 out;
  for (int k = 0; k < 3; ++k) {
    out.v.col(k) = q.col(order[k]);
    out.sigma[k] = std::sqrt(s2[order[k]]);
  }
  if (out.v.determinant() < 0) out.v.col(2) *= -1;
  const Mat3 fv = f * out.v;
  out.u.col(0) = fv.col(0) / out.sigma[0];
  Vec3 u1 = fv.col(1) - out.u.col(0).dot(fv.col(1)) * out.u.col(0);  // Gram–Schmidt against round-off
  out.u.col(1) = u1 / u1.norm();
  // Third column by the cross product keeps U a rotation; its sign gives det F.
  out.u.col(2) = out.u.col(0).cross(out.u.col(1));
  out.sigma[2] = out.u.col(2).dot(fv.col(2));
  return out;
}

}  // namespace

Svd3 svd3(const Mat3& f) {
  const Mat3 a = f.transpose() * f;
  SymmetricJacobi<Real> m{a(0, 0), a(1, 1), a(2, 2), a(0, 1), a(0, 2), a(1, 2), {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  jacobi_sweeps(m);
  Mat3 q;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) q(i, j) = m.q[i][j];
  return svd_from_eigen(f, q, Vec3(m.a00, m.a11, m.a22));
}

void svd3x4(const Mat3 (&f)[4], Svd3 (&out)[4]) {
  Mat3 a[4];
  for (int l = 0; l < 4; ++l) a[l] = f[l].transpose() * f[l];
  const auto entry = [&](int i, int j) { return Lanes([&](auto l) { return a[l](i, j); }); };
  SymmetricJacobi<Lanes> m{entry(0, 0), entry(1, 1), entry(2, 2), entry(0, 1), entry(0, 2), entry(1, 2), {}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.q[i][j] = i == j ? 1 : 0;
  jacobi_sweeps(m);
  for (int l = 0; l < 4; ++l) {
    Mat3 q;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) q(i, j) = m.q[i][j][l];
    out[l] = svd_from_eigen(f[l], q, Vec3(m.a00[l], m.a11[l], m.a22[l]));
  }
}

Mat3 kirchhoff_stress(const Hencky& law, const Mat3&, const Svd3& svd) {
  const Vec3 eps = svd.sigma.cwiseAbs().array().log().matrix();
  const Real tr = eps.sum();
  const Vec3 t = (2 * law.lame.mu * eps).array() + law.lame.lambda * tr;
  return svd.u * t.asDiagonal() * svd.u.transpose();
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
    const Vec3 eps = s.sigma.cwiseAbs().array().log().matrix();
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
// q = q_tr / (1 + 6μΔγ); f(Δγ) is convex and decreasing, so Newton from
// Δγ = 0 approaches its root monotonically from below.
Svd3 ellipse_return(Real yield, Real viscosity, Real a, const Lame& lame, Real dt, const Svd3& svd) {
  const Vec3 eps = svd.sigma.cwiseAbs().array().max(1e-12).log().matrix();
  const Real bulk = lame.lambda + 2 * lame.mu / 3;
  const Real tr = eps.sum();
  const Vec3 dev = eps.array() - tr / 3;
  const Real p_tr = -bulk * tr;
  const Real q_tr = std::sqrt(1.5) * 2 * lame.mu * dev.norm();
  const Real y2 = yield * yield;
  if (q_tr * q_tr + a * p_tr * p_tr <= y2) return svd;
  Real p, q;
  if (yield <= 0) {
    q = 0;
    p = a > 0 ? 0 : p_tr;
  } else if (a == 0) {  // von Mises: radial return, pressure unchanged
    q = yield;
    p = p_tr;
  } else {
    Real g = 0;
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
  return Svd3{svd.u, svd.v, (dev_new.array() + tr_new / 3).exp().matrix()};
}

}  // namespace

Svd3 return_map(const VonMises& law, const Lame& lame, Real dt, Real, const Svd3& svd) {
  return ellipse_return(law.yield_stress, law.viscosity, 0, lame, dt, svd);
}

Svd3 return_map(const HerschelBulkleyFlow& law, const Lame& lame, Real dt, Real, const Svd3& svd) {
  const Vec3 eps = svd.sigma.cwiseAbs().array().max(1e-12).log().matrix();
  const Real tr = eps.sum();
  const Vec3 dev = eps.array() - tr / 3;
  // Shear stress equivalent √(J₂) = q/√3 = √2 μ |dev ε| of the trial state.
  const Real tau_trial = std::sqrt(2.0) * lame.mu * dev.norm();
  const Real overstress = tau_trial - law.yield_stress;
  if (overstress <= 0) return svd;
  const HerschelBulkley flow{law.yield_stress, law.viscosity, law.flow_index};
  const Real tau = law.yield_stress + flow.relaxed_overstress(overstress, lame.mu, dt);
  const Vec3 dev_new = dev * (tau / tau_trial);  // radial return: pressure unchanged
  return Svd3{svd.u, svd.v, (dev_new.array() + tr / 3).exp().matrix()};
}

Real CamClay::porosity(Real plastic_j) const {
  return std::clamp((plastic_j - 1 + initial_porosity) / plastic_j, Real(0), Real(0.95));
}

Real CamClay::a(Real plastic_j) const {
  const Real n = porosity(plastic_j);
  return cohesion_slope * n / (1 - n);
}

Svd3 return_map(const CamClay& law, const Lame& lame, Real dt, Real plastic_j, const Svd3& svd) {
  return ellipse_return(law.yield_stress, law.viscosity, law.a(plastic_j), lame, dt, svd);
}

Real yield_function(const CamClay& law, Real plastic_j, const Vec3& tau) {
  const Real p = -tau.sum() / 3;
  const Vec3 dev = tau.array() + p;
  const Real q = std::sqrt(1.5) * dev.norm();
  return q * q + law.a(plastic_j) * p * p - law.yield_stress * law.yield_stress;
}

}  // namespace bakesim::mpm
