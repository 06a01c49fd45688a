// Kernels against their definitions: normalisation, and derivatives against
// finite differences (seed Eq 3.7–3.12 as corrected in docs/physics.md).
#include <gtest/gtest.h>

#include <cmath>

#include "sph/kernels.hpp"

using namespace bakesim;
using namespace bakesim::sph;

namespace {
// 4π ∫_0^h f(r) r² dr by the midpoint rule.
template <class F>
double radial_integral(F f, double h, int n = 200000) {
  double s = 0, dr = h / n;
  for (int i = 0; i < n; ++i) {
    const double r = (i + 0.5) * dr;
    s += f(r) * r * r * dr;
  }
  return 4.0 * kPi * s;
}
}  // namespace

TEST(CubicSpline, IntegratesToOne) {
  for (double h : {0.01, 0.5, 2.0}) {
    CubicSpline k(h);
    EXPECT_NEAR(radial_integral([&](double r) { return k.w(r); }, h), 1.0, 1e-6) << "h = " << h;
  }
}

TEST(CubicSpline, CompactSupportAndPositive) {
  CubicSpline k(0.1);
  EXPECT_EQ(k.w(0.1), 0.0);
  EXPECT_EQ(k.w(0.2), 0.0);
  for (double r = 0; r < 0.1; r += 0.001) EXPECT_GE(k.w(r), 0.0);
}

TEST(CubicSpline, DerivativeMatchesFiniteDifferences) {
  const double h = 0.04;
  CubicSpline k(h);
  for (double r = 0.001; r < h; r += 0.00137) {
    const double e = 1e-7;
    const double fd = (k.w(r + e) - k.w(r - e)) / (2 * e);
    EXPECT_NEAR(k.dw_dr(r), fd, 1e-5 * std::abs(k.w(0.0)) / h) << "r = " << r;
    EXPECT_NEAR(k.dw_dr_over_r(r), k.dw_dr(r) / r, 1e-9 * std::abs(k.dw_dr(r) / r) + 1e-12);
  }
}

TEST(CubicSpline, GradientVectorMatchesFiniteDifferences) {
  const double h = 0.05;
  CubicSpline k(h);
  const Vec3 x(0.011, -0.017, 0.006);
  const Vec3 g = k.gradient(x, x.norm());
  for (int a = 0; a < 3; ++a) {
    const double e = 1e-7;
    Vec3 xp = x, xm = x;
    xp[a] += e;
    xm[a] -= e;
    EXPECT_NEAR(g[a], (k.w(xp.norm()) - k.w(xm.norm())) / (2 * e), 1e-4 * g.norm());
  }
}

TEST(CubicSpline, LaplacianMatchesFiniteDifferences) {
  const double h = 0.05;
  CubicSpline k(h);
  for (const Vec3& x : {Vec3(0.004, 0.003, -0.002), Vec3(0.012, -0.009, 0.01), Vec3(0.0, 0.019, 0.004)}) {
    const double e = 1e-5;
    double lap = 0;
    for (int a = 0; a < 3; ++a) {
      Vec3 xp = x, xm = x;
      xp[a] += e;
      xm[a] -= e;
      lap += (k.w(xp.norm()) - 2 * k.w(x.norm()) + k.w(xm.norm())) / (e * e);
    }
    EXPECT_NEAR(k.laplacian(x.norm()), lap, 1e-3 * std::abs(lap) + 1e-2) << x.transpose();
  }
}

TEST(CubicSpline, LaplacianIntegratesToZero) {
  const double h = 0.1;
  CubicSpline k(h);
  const double scale = std::abs(k.laplacian(0.0)) * h * h * h;
  EXPECT_NEAR(radial_integral([&](double r) { return k.laplacian(r); }, h), 0.0, 1e-4 * scale);
}

TEST(ViscosityKernel, LaplacianOfMullerKernel) {
  // Eq 3.7 W(r) = 15/(2π h³)(−r³/(2h³) + r²/h² + h/(2r) − 1); Eq 3.8 is its Laplacian.
  const double h = 0.03;
  auto w = [&](double r) {
    return 15.0 / (2 * kPi * h * h * h) * (-r * r * r / (2 * h * h * h) + r * r / (h * h) + h / (2 * r) - 1);
  };
  ViscosityLaplacian lap(h);
  for (double r = 0.004; r < h * 0.95; r += 0.0031) {
    const double e = 1e-6;
    const double d1 = (w(r + e) - w(r - e)) / (2 * e);
    const double d2 = (w(r + e) - 2 * w(r) + w(r - e)) / (e * e);
    EXPECT_NEAR(lap(r), d2 + 2 * d1 / r, 1e-3 * lap(r)) << "r = " << r;
  }
  EXPECT_EQ(lap(h), 0.0);
}

TEST(WallKernelShare, LatticeLayerAtHalfSpacingGetsTheMissingShareExactly) {
  const double s = 0.01, h = 2 * s;
  CubicSpline k(h);
  const double total = lattice_kernel_sum(k, s);
  WallKernelShare share(k, s, total);
  // A particle s/2 from the wall: its own half of the lattice (own layer and
  // above) plus the share beyond the wall must make the full lattice sum.
  const int n = 4;
  double own = 0;
  for (int layer = 0; layer <= n; ++layer)
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j) own += k.w(s * std::sqrt(double(layer * layer + i * i + j * j)));
  EXPECT_NEAR(own / total + share.fraction(0.5 * s), 1.0, 1e-6);
  EXPECT_NEAR(share.fraction(h), 0.0, 1e-12);
  EXPECT_GT(share.fraction(0.0), share.fraction(0.5 * s));
  for (double d = 0.001; d < 0.019; d += 0.0023) {
    const double e = 1e-6;
    EXPECT_NEAR(share.slope(d), -(share.fraction(d + e) - share.fraction(d - e)) / (2 * e), 2e-3 * share.slope(0.0))
        << "d = " << d;
  }
}
