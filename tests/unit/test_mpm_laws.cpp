// MPM constitutive laws: the SVD, Kirchhoff stress against finite differences
// of the energy density (τ = ∂ψ/∂F Fᵀ), and the von Mises return mapping.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "mpm/constitutive.hpp"
#include "physics/rheology.hpp"

using namespace bakesim;
using namespace bakesim::mpm;

namespace {

Mat3 sample_f(int k) {
  Mat3 f;
  f << 1.1, 0.2, -0.05, 0.1, 0.9, 0.15, -0.1, 0.05, 1.2;
  if (k == 1) f << 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0;
  if (k == 2) f << 1.3, 0.0, 0.0, 0.0, 1.3, 0.0, 0.0, 0.0, 0.7;  // repeated singular values
  if (k == 3) f << 0.6, 0.4, 0.0, -0.3, 0.8, 0.1, 0.2, 0.0, 1.5;
  return f;
}

Mat3 stress_by_finite_differences(const ElasticLaw& law, const Mat3& f) {
  Mat3 p;
  const Real h = 1e-6;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      Mat3 fp = f, fm = f;
      fp(a, b) += h;
      fm(a, b) -= h;
      p(a, b) = (energy_density(law, fp) - energy_density(law, fm)) / (2 * h);
    }
  return p * f.transpose();
}

}  // namespace

TEST(MpmLaws, SvdReconstructsWithRotations) {
  for (int k = 0; k < 4; ++k) {
    const Mat3 f = sample_f(k);
    const Svd3 s = svd3(f);
    EXPECT_NEAR((s.u * s.sigma.asDiagonal() * s.v.transpose() - f).norm(), 0.0, 1e-12) << k;
    EXPECT_NEAR(s.u.determinant(), 1.0, 1e-12);
    EXPECT_NEAR(s.v.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((s.u.transpose() * s.u - Mat3::Identity()).norm(), 0.0, 1e-12);
  }
  // An inverted F keeps rotations and puts the sign in the smallest σ.
  Mat3 inv = sample_f(0);
  inv.col(2) *= -1;
  const Svd3 s = svd3(inv);
  EXPECT_LT(s.sigma.prod(), 0);
  EXPECT_NEAR((s.u * s.sigma.asDiagonal() * s.v.transpose() - inv).norm(), 0.0, 1e-12);
}

// svd3x4 runs the Jacobi sweeps of four matrices in the lanes of one vector,
// until every lane has converged: each result must be a valid SVD of its own
// matrix whatever the other lanes hold (a lane already diagonal beside one
// that needs several sweeps, repeated singular values, an inverted F, one
// nearly singular F that takes the Jacobi SVD fallback), and agree with svd3.
TEST(MpmLaws, FourAtOnceSvdGivesEachMatrixItsOwnSvd) {
  Mat3 nearly_singular = sample_f(0);
  nearly_singular.col(1) = nearly_singular.col(0) + 1e-7 * Vec3(0.3, -0.2, 0.1);
  Mat3 inverted = sample_f(3);
  inverted.col(2) *= -1;
  const Mat3 batches[2][4] = {{sample_f(0), sample_f(1), sample_f(2), sample_f(3)},
                              {inverted, nearly_singular, 2.5 * Mat3::Identity(), sample_f(0).transpose()}};
  for (const auto& batch : batches) {
    Svd3 four[4];
    svd3x4(batch, four);
    for (int l = 0; l < 4; ++l) {
      const Mat3& f = batch[l];
      const Svd3& s = four[l];
      const Real scale = f.norm();
      EXPECT_NEAR((compose(s) - f).norm(), 0.0, 1e-12 * scale) << l;
      EXPECT_NEAR(s.u.determinant(), 1.0, 1e-12) << l;
      EXPECT_NEAR(s.v.determinant(), 1.0, 1e-12) << l;
      EXPECT_NEAR((s.v.transpose() * s.v - Mat3::Identity()).norm(), 0.0, 1e-12) << l;
      const Svd3 one = svd3(f);
      EXPECT_NEAR((s.sigma - one.sigma).norm(), 0.0, 1e-12 * scale) << l;
      EXPECT_GE(s.sigma[0], s.sigma[1]) << l;
      EXPECT_GE(s.sigma[1], std::abs(s.sigma[2])) << l;
    }
  }
}

// The constitutive phase takes its chunk's Hencky strains, and the returned
// stretches e^ε, on 4-lane vectors (Eigen's SIMD logarithm and exponential):
// each must be the C library's to round-off, at stretches near 1 (elastic
// MPM) and far from it, and |σ| floored at 1e-12 as hencky_strain does.
TEST(MpmLaws, FourAtOnceHenckyStrainIsTheLogarithmOfEachStretch) {
  const Real stretches[][4] = {
      {1.0, 0.70710678, 1.41421356, 1 + 1e-9}, {0.999, 1.2, 0.8, 1.0001}, {1e-13, 0.6, 3.0, 1.05}};
  for (const auto& axis0 : stretches) {
    Svd3 four[4];
    for (int l = 0; l < 4; ++l)
      four[l] = {Mat3::Identity(), Mat3::Identity(), Vec3(axis0[l], 1 - 0.05 * l, -(1 + 0.1 * l))};
    Vec3 strain[4];
    hencky_strain_x4(four, strain);
    for (int l = 0; l < 4; ++l) {
      const Vec3 one = hencky_strain(four[l].sigma);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(strain[l][i], one[i], 4e-16 * std::max(Real(1), std::abs(one[i]))) << l << " axis " << i;
    }
  }
  Real worst = 0;
  for (int k = 0; k <= 4000; ++k) {  // stretches from 0.1 to 10
    Svd3 four[4];
    for (int l = 0; l < 4; ++l) {
      const Real x = 0.1 * std::pow(100.0, (k + l / 4.0) / 4001.0);
      four[l] = {Mat3::Identity(), Mat3::Identity(), Vec3(x, x, x)};
    }
    Vec3 strain[4];
    hencky_strain_x4(four, strain);
    for (int l = 0; l < 4; ++l) {
      const Real exact = std::log(four[l].sigma[0]);
      if (exact != 0) worst = std::max(worst, std::abs(strain[l][0] - exact) / std::abs(exact));
    }
  }
  EXPECT_LT(worst, 4e-16);
}

TEST(MpmLaws, FourAtOnceStretchIsTheExponentialOfEachStrain) {
  Real worst = 0;
  for (int k = -4000; k <= 4000; ++k) {  // strains from -3 to 3
    Vec3 strain[4], sigma[4];
    for (int l = 0; l < 4; ++l) strain[l] = Vec3(3.0 * (k + l / 4.0) / 4001.0, 1e-9 * l, -0.25 * l);
    hencky_stretch_x4(strain, sigma);
    for (int l = 0; l < 4; ++l)
      for (int i = 0; i < 3; ++i) {
        const Real exact = std::exp(strain[l][i]);
        worst = std::max(worst, std::abs(sigma[l][i] - exact) / exact);
      }
  }
  EXPECT_LT(worst, 4e-16);
}

TEST(MpmLaws, KirchhoffStressIsTheEnergyDerivative) {
  const Lame lame = Lame::from_young(1e4, 0.3);
  for (const ElasticLaw& law : {ElasticLaw(Hencky{lame}), ElasticLaw(FixedCorotated{lame})})
    for (int k : {0, 2, 3}) {
      const Mat3 f = sample_f(k);
      const Mat3 tau = kirchhoff_stress(law, f, svd3(f));
      const Mat3 fd = stress_by_finite_differences(law, f);
      EXPECT_NEAR((tau - fd).norm() / fd.norm(), 0.0, 1e-6) << "law " << law.index() << " F " << k;
    }
  // Stress free at rest.
  EXPECT_NEAR(kirchhoff_stress(Hencky{lame}, Mat3::Identity(), svd3(Mat3::Identity())).norm(), 0.0, 1e-12);
}

TEST(MpmLaws, VonMisesProjectsOntoTheYieldSurfaceAndKeepsVolume) {
  const Lame lame = Lame::from_young(1e4, 0.3);
  const VonMises vm{100.0, 0.0};
  const Mat3 f = sample_f(3);
  const Mat3 fe = compose(return_map(vm, lame, 1e-3, 1.0, svd3(f)));
  const Mat3 tau = kirchhoff_stress(Hencky{lame}, fe, svd3(fe));
  const Mat3 dev = tau - tau.trace() / 3 * Mat3::Identity();
  EXPECT_NEAR(std::sqrt(1.5) * dev.norm(), 100.0, 1e-9);  // on f = 0
  EXPECT_NEAR(fe.determinant(), f.determinant(), 1e-12);  // plastic flow is isochoric
  // Viscoplastic: part of the way back, by 1/(1 + 2μΔt/η).
  const VonMises slow{100.0, 2 * lame.mu * 1e-3};  // keep = 1/2
  const Mat3 fs = compose(return_map(slow, lame, 1e-3, 1.0, svd3(f)));
  const Mat3 ts = kirchhoff_stress(Hencky{lame}, fs, svd3(fs));
  const Mat3 tt = kirchhoff_stress(Hencky{lame}, f, svd3(f));
  const auto q = [](const Mat3& t) { return std::sqrt(1.5) * (t - t.trace() / 3 * Mat3::Identity()).norm(); };
  EXPECT_NEAR(q(ts), 100.0 + 0.5 * (q(tt) - 100.0), 1e-6 * q(tt));
  // Inside the yield surface nothing changes.
  const Mat3 small = Mat3::Identity() + 1e-4 * sample_f(0);
  EXPECT_NEAR((compose(return_map(vm, lame, 1e-3, 1.0, svd3(small))) - small).norm(), 0.0, 1e-12);
}

namespace {
Vec3 principal_tau(const Lame& lame, const Mat3& fe) {
  const Svd3 s = svd3(fe);
  const Vec3 eps = s.sigma.array().log().matrix();
  return (2 * lame.mu * eps).array() + lame.lambda * eps.sum();
}
}  // namespace

TEST(MpmLaws, CamClayIsVonMisesWithoutPorosity) {
  const Lame lame = Lame::from_young(1e4, 0.3);
  const CamClay cc{100.0, 0.0, 2.0, 0.0};
  EXPECT_EQ(cc.porosity(1.0), 0.0);
  EXPECT_EQ(cc.porosity(0.8), 0.0);  // compacted below zero porosity: clamped
  EXPECT_NEAR(cc.porosity(1.25), 0.2, 1e-12);
  EXPECT_NEAR(cc.a(1.25), 2 * 0.2 / 0.8, 1e-12);
  const Mat3 f = sample_f(3);
  const Mat3 a = compose(return_map(cc, lame, 1e-3, 1.0, svd3(f)));
  const Mat3 b = compose(return_map(VonMises{100.0, 0.0}, lame, 1e-3, 1.0, svd3(f)));
  EXPECT_NEAR((a - b).norm(), 0.0, 1e-12);
}

TEST(MpmLaws, CamClayReturnsToTheClosestPointOfTheEllipseInTheEnergyNorm) {
  const Lame lame = Lame::from_young(1e4, 0.3);
  const Real bulk = lame.lambda + 2 * lame.mu / 3;
  const CamClay cc{100.0, 0.0, 2.0, 0.1};
  const Real jp = 1.3;  // porosity (0.3 + 0.1) / 1.3, A ≈ 0.89
  const Real a = cc.a(jp);
  ASSERT_GT(a, 0.5);
  // Trial states: dilated (p < 0), compressed (p > 0) and sheared.
  const Mat3 trials[3] = {1.03 * sample_f(3), 0.97 * sample_f(3), sample_f(2)};
  for (int k = 0; k < 3; ++k) {
    const Mat3& f = trials[k];
    const Vec3 t_tr = principal_tau(lame, f);
    ASSERT_GT(yield_function(cc, jp, t_tr), 0) << k;
    const Mat3 fe = compose(return_map(cc, lame, 1e-3, jp, svd3(f)));
    const Vec3 t = principal_tau(lame, fe);
    EXPECT_NEAR(yield_function(cc, jp, t) / (100.0 * 100.0), 0.0, 1e-9) << k;  // on f = 0
    // Brute force: the point of the ellipse q² + A p² = τ_y² nearest the
    // trial in the energy norm Δp²/K + Δq²/(3μ).
    const Real p_tr = -t_tr.sum() / 3, q_tr = std::sqrt(1.5) * (t_tr.array() + p_tr).matrix().norm();
    Real best = 1e300, bp = 0, bq = 0;
    for (int i = 0; i <= 200000; ++i) {
      const Real th = M_PI * i / 200000;
      const Real p = 100.0 / std::sqrt(a) * std::cos(th), q = 100.0 * std::sin(th);
      const Real e = (p - p_tr) * (p - p_tr) / bulk + (q - q_tr) * (q - q_tr) / (3 * lame.mu);
      if (e < best) best = e, bp = p, bq = q;
    }
    const Real p = -t.sum() / 3, q = std::sqrt(1.5) * (t.array() + p).matrix().norm();
    EXPECT_NEAR(p, bp, 0.05) << k;
    EXPECT_NEAR(q, bq, 0.05) << k;
  }
  // The more porous, the less it holds under tension: a dilated state that
  // von Mises keeps yields with porosity.
  const Mat3 dilated = 1.006 * Mat3::Identity();  // p ≈ −150 Pa: A p² > τ_y²
  EXPECT_NEAR((compose(return_map(VonMises{100.0, 0.0}, lame, 1e-3, 1.0, svd3(dilated))) - dilated).norm(), 0, 1e-15);
  EXPECT_LT(compose(return_map(cc, lame, 1e-3, jp, svd3(dilated))).determinant(), dilated.determinant());
}

namespace {

// Steady shear stress τ_xy of a Hencky von Mises material sheared at rate
// γ̇ (v_x = γ̇ y) for `steps` steps of dt: F ← (I + Δt ∇v) F, then the return map.
Real steady_shear_stress(const VonMises& law, const Lame& lame, Real rate, Real dt, int steps) {
  Mat3 grad = Mat3::Zero();
  grad(0, 1) = rate;
  Mat3 f = Mat3::Identity();
  for (int k = 0; k < steps; ++k) f = compose(return_map(law, lame, dt, 1.0, svd3((Mat3::Identity() + dt * grad) * f)));
  return kirchhoff_stress(ElasticLaw{Hencky{lame}}, f, svd3(f))(0, 1);
}

}  // namespace

TEST(MpmLaws, ViscoplasticVonMisesShearsAsABinghamFluidOfViscosityHalfEta) {
  // The relaxation of spec 3.2 step 3 (keep 1 / (1 + 2μΔt/η) of the overstress)
  // in simple shear settles at τ_xy = τ_y/√3 + (η/2) γ̇: a Bingham fluid whose
  // shear yield stress is τ_y/√3 (q = √3 τ_xy) and whose plastic (shear)
  // viscosity is η/2, as docs/physics.md states. Small elastic strains (τ/2μ ≈ 0.5%).
  const Lame lame = Lame::from_young(2.6e4, 0.3);  // μ = 1e4 Pa
  const Real eta = 50, rate = 2, dt = 1e-4;        // relaxation time η/2μ = 25 steps
  const Real viscous = steady_shear_stress(VonMises{0.0, eta}, lame, rate, dt, 3000);
  EXPECT_NEAR(viscous, 0.5 * eta * rate, 0.01 * 0.5 * eta * rate);
  const Real yield = 100;
  const Real bingham = steady_shear_stress(VonMises{yield, eta}, lame, rate, dt, 3000);
  const Real expected = yield / std::sqrt(3.0) + 0.5 * eta * rate;
  EXPECT_NEAR(bingham, expected, 0.01 * expected);
  // Twice the rate: the stress above yield doubles (linear in γ̇, no other rate dependence).
  const Real faster = steady_shear_stress(VonMises{yield, eta}, lame, 2 * rate, dt, 3000);
  EXPECT_NEAR(faster - yield / std::sqrt(3.0), 2 * (bingham - yield / std::sqrt(3.0)), 0.02 * eta * rate);
}

// Issue 26, one law for both solvers: a Bingham fluid given as the shared
// Herschel–Bulkley law (physics/rheology.hpp) and turned into MPM's von Mises
// parameters by von_mises_equivalent shears in the MPM return exactly as the
// law says, τ = τ_y + K γ̇, at two rates.
TEST(MpmLaws, VonMisesEquivalentOfTheSharedBinghamLawShearsAsTheLaw) {
  const Lame lame = Lame::from_young(2.6e4, 0.3);
  const HerschelBulkley bingham{60.0, 20.0, 1.0};
  const VonMisesEquivalent vm = von_mises_equivalent(bingham);
  for (const Real rate : {1.0, 3.0}) {
    const Real tau = steady_shear_stress(VonMises{vm.uniaxial_yield_stress, vm.viscosity}, lame, rate, 1e-4, 4000);
    EXPECT_NEAR(tau, bingham.shear_stress(rate), 0.01 * bingham.shear_stress(rate)) << "at rate " << rate;
  }
}
