// Temperature curves against the seed's formulas (thesis Eq 4.1–4.4, Table 4.1).
#include <gtest/gtest.h>

#include <cmath>

#include "physics/curves.hpp"
#include "physics/food_properties.hpp"
#include "physics/oven.hpp"

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

// Choi & Okos (1986) composition model (physics/food_properties.hpp).
TEST(FoodProperties, PureWaterIsWithinAPercentOfIapws) {
  FoodComposition water;
  water[FoodComponent::water] = 1;
  const ThermalProperties p = food_properties(water, 20);
  // IAPWS-95 / IAPWS 2008 at 20 °C, 1 atm: 998.2 kg/m³, 4182 J/(kg K), 0.598 W/(m K).
  EXPECT_NEAR(p.density / 998.2, 1, 0.005);
  EXPECT_NEAR(p.specific_heat / 4182, 1, 0.005);
  EXPECT_NEAR(p.conductivity / 0.598, 1, 0.015);
}

TEST(FoodProperties, MixturesFollowTheSeriesAndParallelRules) {
  // Half water, half fat by mass at 20 °C, worked by hand from the published coefficients.
  FoodComposition f;
  f[FoodComponent::water] = 0.5;
  f[FoodComponent::fat] = 0.5;
  const ThermalProperties p = food_properties(f, 20);
  EXPECT_NEAR(p.density, 954.88, 0.05);
  EXPECT_NEAR(p.specific_heat, 3094.16, 0.05);
  EXPECT_NEAR(p.conductivity, 0.38059, 5e-5);
  f.porosity = 0.2;  // a fifth of the volume air, in parallel
  const ThermalProperties airy = food_properties(f, 20);
  EXPECT_NEAR(airy.density, 0.8 * 954.88, 0.05);
  EXPECT_DOUBLE_EQ(airy.specific_heat, p.specific_heat);
  EXPECT_NEAR(airy.conductivity, 0.8 * 0.38059 + 0.2 * 0.026, 5e-5);
}

// ICAO standard atmosphere (ISO 2533) tabulated pressures, Pa.
TEST(Oven, AltitudeGivesTheStandardAtmospheresPressureAndItsBoilingPoint) {
  EXPECT_DOUBLE_EQ(standard_atmosphere_pressure(0), 101325.0);
  const std::pair<double, double> table[] = {{-500, 107477}, {1000, 89875}, {2000, 79495}, {3000, 70108}};
  for (const auto& [metres, pascal] : table) EXPECT_NEAR(standard_atmosphere_pressure(metres), pascal, 3.0) << metres;
  Oven oven;
  EXPECT_DOUBLE_EQ(oven.boiling_point(), 100.0);
  oven.air_pressure = standard_atmosphere_pressure(2000);
  EXPECT_NEAR(oven.boiling_point(), 93.4, 0.1);  // steam tables: 93.3 degC at 79.5 kPa
}
