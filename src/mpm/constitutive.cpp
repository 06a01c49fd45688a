#include "mpm/constitutive.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

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

Svd3 svd3(const Mat3& f) {
  // FᵀF = V Σ² Vᵀ in closed form (eigenvalues ascending), U = F V Σ⁻¹.
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(f.transpose() * f);
  const Vec3 s2 = eig.eigenvalues();
  // Well separated, not tiny: the fast path is accurate to round-off.
  const Real scale = s2[2];
  if (!(s2[0] > 1e-6 * scale) || s2[1] - s2[0] < 1e-6 * scale || s2[2] - s2[1] < 1e-6 * scale)
    return jacobi_svd(f);
  Svd3 out;
  // Largest first, as JacobiSVD orders them.
  out.v.col(0) = eig.eigenvectors().col(2);
  out.v.col(1) = eig.eigenvectors().col(1);
  out.v.col(2) = eig.eigenvectors().col(0);
  out.sigma = Vec3(std::sqrt(s2[2]), std::sqrt(s2[1]), std::sqrt(s2[0]));
  if (out.v.determinant() < 0) out.v.col(2) *= -1;
  const Mat3 fv = f * out.v;
  out.u.col(0) = fv.col(0) / out.sigma[0];
  out.u.col(1) = fv.col(1) / out.sigma[1];
  // Third column by the cross product keeps U a rotation; its sign gives det F.
  out.u.col(2) = out.u.col(0).cross(out.u.col(1));
  out.sigma[2] = out.u.col(2).dot(fv.col(2));
  return out;
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

Svd3 return_map(const VonMises& law, const Lame& lame, Real dt, const Svd3& svd) {
  // Spec 3.2 with A = 0: the trial deviatoric Hencky strain is scaled onto
  // q = τ_y, then relaxed back towards the trial by 1/(1 + 2μΔt/η).
  const Vec3 eps = svd.sigma.cwiseAbs().array().max(1e-12).log().matrix();
  const Real mean = eps.sum() / 3;
  const Vec3 dev = eps.array() - mean;
  const Real q = std::sqrt(1.5) * 2 * lame.mu * dev.norm();
  if (q <= law.yield_stress) return svd;
  const Vec3 dev_proj = dev * (law.yield_stress / q);
  const Real keep = law.viscosity > 0 ? 1.0 / (1.0 + 2 * lame.mu * dt / law.viscosity) : 0.0;
  const Vec3 dev_new = dev_proj + keep * (dev - dev_proj);
  return Svd3{svd.u, svd.v, (dev_new.array() + mean).exp().matrix()};
}

}  // namespace bakesim::mpm
