// Temperature curves against the seed's formulas (thesis Eq 4.1–4.4, Table 4.1).
#include <gtest/gtest.h>

#include <cmath>

#include "physics/curves.hpp"

using namespace bakesim;

TEST(Curves, TwoSegmentViscosityOfTable41) {
  // Eq 4.1 with T0 = 26, Tc = 45, Tf = 120 °C and μ: 0.1 → 1 → 5e3.
  const TemperatureCurve mu = PiecewiseLinear({{26, 0.1}, {45, 1.0}, {120, 5000.0}});
  EXPECT_DOUBLE_EQ(evaluate(mu, 26), 0.1);
  EXPECT_DOUBLE_EQ(evaluate(mu, 45), 1.0);
  EXPECT_NEAR(evaluate(mu, 35.5), 0.1 + 9.5 * 0.9 / 19.0, 1e-12);
  EXPECT_NEAR(evaluate(mu, 100), 1.0 + 55.0 * 4999.0 / 75.0, 1e-9);
  // Beyond the table the value stays at the end values (no negative viscosity below T0).
  EXPECT_DOUBLE_EQ(evaluate(mu, 0), 0.1);
  EXPECT_DOUBLE_EQ(evaluate(mu, 200), 5000.0);
  EXPECT_FALSE(is_constant(mu));
}

TEST(Curves, ZhangArctanRelaxationTime) {
  // Eq 4.3: λ = C_λ [(2/π) atan((T − 65)/2) + 1] + 2, C_λ = 450.
  const ZhangArctan lambda{450.0};
  EXPECT_NEAR(lambda(65.0), 452.0, 1e-12);
  EXPECT_NEAR(lambda(-1e9), 2.0, 1e-5);
  EXPECT_NEAR(lambda(1e9), 902.0, 1e-5);
  EXPECT_NEAR(lambda(67.0), 450.0 * (2.0 / kPi * std::atan(1.0) + 1.0) + 2.0, 1e-12);
  // Monotone in T.
  for (double t = 0; t < 130; t += 1) EXPECT_LT(lambda(t), lambda(t + 1));
}

TEST(Curves, ConstantAndPiecewiseEvaluateThroughTheVariant) {
  EXPECT_DOUBLE_EQ(evaluate(ConstantCurve{0.3}, 1000.0), 0.3);
  EXPECT_TRUE(is_constant(ConstantCurve{0.3}));
  const TemperatureCurve eps = PiecewiseLinear({{26, 0.05}, {120, 5.0}});  // Eq 4.4
  EXPECT_NEAR(evaluate(eps, 73), 0.05 + 47.0 * 4.95 / 94.0, 1e-12);
}
