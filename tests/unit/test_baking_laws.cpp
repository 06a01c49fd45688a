// Baking laws against closed-form solutions: the Maxwell stress (thesis
// Eq 3.20–3.27), convective exchange (Eq 3.42), oven wall radiation and the
// bubble gas law (Eq 3.48–3.51).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "physics/browning.hpp"
#include "physics/bubbles.hpp"
#include "physics/heat.hpp"
#include "physics/maxwell.hpp"
#include "physics/leavening.hpp"
#include "physics/moisture.hpp"
#include "physics/oven.hpp"
#include "physics/porosity.hpp"
#include "physics/setting.hpp"

using namespace bakesim;

TEST(MaxwellStress, RelaxesAsExpUnderZeroStrainRate) {
  Mat3 s;
  s << 100, 30, -20, 30, -50, 10, -20, 10, 40;
  const Mat3 s0 = s;
  const Real lambda = 0.7, dt = 1e-3;
  for (int k = 1; k <= 2000; ++k) {
    s = maxwell_stress_step(s, Mat3::Zero(), 1e4, lambda, dt);
    if (k % 500 == 0) {
      const Mat3 expected = s0 * std::exp(-k * dt / lambda);
      EXPECT_LT((s - expected).norm(), 1e-10 * s0.norm()) << "t = " << k * dt;
    }
  }
}

TEST(MaxwellStress, PureExtensionApproachesViscousLimit) {
  // L = diag(ė, −ė, 0): W = 0, D' = diag(ė, −ė, 0), so from rest
  // S_xx(t) = μ_e λ ė (1 − e^{−t/λ}) and S_yy = −S_xx, S_zz = 0.
  const Real mu_e = 50.0, lambda = 0.2, rate = 0.3, dt = 2e-4;
  Mat3 l = Mat3::Zero();
  l(0, 0) = rate;
  l(1, 1) = -rate;
  Mat3 s = Mat3::Zero();
  for (int k = 1; k <= 5000; ++k) {
    s = maxwell_stress_step(s, l, mu_e, lambda, dt);
    const Real t = k * dt;
    const Real expected = mu_e * lambda * rate * (1 - std::exp(-t / lambda));
    ASSERT_NEAR(s(0, 0), expected, 1e-9 * mu_e * lambda * rate);
    ASSERT_NEAR(s(1, 1), -expected, 1e-9 * mu_e * lambda * rate);
    ASSERT_NEAR(s(2, 2), 0.0, 1e-12);
  }
}

TEST(MaxwellStress, SemiImplicitSplitMatchesTheExplicitStep) {
  // The relaxation before the solve and the forcing after it, at the same
  // velocity gradient: the explicit step, but for the rotation of the relaxed
  // stress instead of the old one (w R(S)(1 − e^{−dt/λ}), order dt²/λ).
  Mat3 s, l;
  s << 100, 30, -20, 30, -50, 10, -20, 10, 40;
  l << 0.3, -1.2, 0.5, 0.7, -0.1, 0.2, -0.4, 0.9, 0.6;
  const Real mu_e = 5e4;
  for (const Real lambda : {1e9, 0.7, 1e-3})
    for (const Real dt : {1e-5, 1e-3}) {
      const Real decay = std::exp(-dt / lambda);
      const Mat3 split = maxwell_forcing_step(decay * s, l, mu_e, maxwell_forcing_weight(lambda, dt));
      const Mat3 rotation = maxwell_rates(s, l).rotation;
      const Mat3 expected =
          maxwell_stress_step(s, l, mu_e, lambda, dt) - maxwell_forcing_weight(lambda, dt) * (1 - decay) * rotation;
      EXPECT_LT((split - expected).norm(), 1e-12 * (s.norm() + mu_e * dt)) << "lambda " << lambda << " dt " << dt;
    }
  // Far below λ the step's viscosity is μ_e dt / 2 (the increment μ_e dt D' is 2 η D').
  EXPECT_NEAR(maxwell_step_viscosity(mu_e, maxwell_forcing_weight(1e9, 1e-4)), 0.5 * mu_e * 1e-4, 1e-12);
}

TEST(MaxwellStress, DeviatorIsTracelessAndExpansionMakesNoStress) {
  // Uniform expansion (a rising dough) has no deviatoric strain rate.
  const MaxwellRates r = maxwell_rates(Mat3::Zero(), 0.4 * Mat3::Identity());
  EXPECT_NEAR(r.strain_rate_deviator.norm(), 0.0, 1e-15);
  Mat3 l;
  l << 1, 2, 3, 4, 5, 6, 7, 8, 10;
  EXPECT_NEAR(maxwell_rates(Mat3::Zero(), l).strain_rate_deviator.trace(), 0.0, 1e-14);
}

TEST(MaxwellStress, RigidRotationRotatesTheStress) {
  // L = skew(ω): the co-rotational term alone rotates S with the body, so
  // after turning by θ about z, S = R(θ) S0 R(θ)ᵀ (objectivity of Eq 3.21).
  Mat3 s0;
  s0 << 10, 2, 0, 2, -4, 1, 0, 1, 3;
  const Real omega = 2.0, dt = 1e-5, t_end = 0.5;
  Mat3 l = Mat3::Zero();
  l(0, 1) = -omega;
  l(1, 0) = omega;  // v = ω × x about z
  Mat3 s = s0;
  const int steps = static_cast<int>(std::lround(t_end / dt));
  for (int k = 0; k < steps; ++k) {
    // Midpoint (RK2) of dS/dt = W S − S W to see the rotation, not Euler's drift.
    const Mat3 mid = s + 0.5 * dt * maxwell_stress_rate(s, l, 0.0, 1e30);
    s += dt * maxwell_stress_rate(mid, l, 0.0, 1e30);
  }
  const Mat3 rot = Eigen::AngleAxis<Real>(omega * t_end, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_LT((s - rot * s0 * rot.transpose()).norm(), 1e-6 * s0.norm());
}

TEST(MaxwellStress, StressRateMatchesFiniteDifferenceOfTheStep) {
  Mat3 s, l;
  s << 5, 1, 2, 1, -3, 0.5, 2, 0.5, 1;
  l << 0.3, -0.2, 0.1, 0.4, -0.1, 0.2, -0.3, 0.05, -0.2;
  const Real mu_e = 20, lambda = 1.5, dt = 1e-6;
  const Mat3 fd = (maxwell_stress_step(s, l, mu_e, lambda, dt) - s) / dt;
  EXPECT_LT((fd - maxwell_stress_rate(s, l, mu_e, lambda)).norm(), 1e-4);
}

TEST(HeatExchange, MatchesTheLumpedExponential) {
  // m c dT/dt = h A (T_ext − T): T(t) = T_ext + (T0 − T_ext) e^{−hA t/(m c)},
  // for any number of steps.
  const Real hA = 0.02, mc = 3.0, t0 = 20, outside = 200;
  Real t = t0;
  for (int k = 0; k < 37; ++k) t = exchange_temperature(t, outside, hA, mc, 1.3);
  EXPECT_NEAR(t, outside + (t0 - outside) * std::exp(-hA * 37 * 1.3 / mc), 1e-9);
  // A huge step lands on T_ext, never beyond.
  EXPECT_NEAR(exchange_temperature(t0, outside, hA, mc, 1e9), outside, 1e-12);
  EXPECT_DOUBLE_EQ(exchange_temperature(t0, outside, 0.0, mc, 10), t0);
}

TEST(HeatExchange, RadiationIsStefanBoltzmannInNewtonsForm) {
  // h_r (T_w − T) = ε σ (T_w⁴ − T⁴) in kelvin, both ways round; none without emissivity.
  for (const auto& [surface, wall] : {std::pair<Real, Real>{20, 200}, {150, 180}, {230, 180}}) {
    const Real t = surface + 273.15, w = wall + 273.15;
    EXPECT_NEAR(radiative_coefficient(0.9, surface, wall) * (wall - surface),
                0.9 * 5.670374419e-8 * (w * w * w * w - t * t * t * t), 1e-9);
  }
  // About 15.7 W/(m² K) between a 100 °C crust (ε 0.9) and 200 °C walls: as much as the convection.
  EXPECT_NEAR(radiative_coefficient(0.9, 100, 200), 15.7, 0.1);
  EXPECT_DOUBLE_EQ(radiative_coefficient(0.0, 20, 200), 0.0);
  Oven oven;
  oven.heat_transfer_coefficient = 12;
  oven.emissivity = 0.9;
  EXPECT_DOUBLE_EQ(oven.surface_coefficient(100, 200), 12 + radiative_coefficient(0.9, 100, 200));
}

TEST(Bubbles, GasLawUsesKelvin) {
  // 26 °C → 100 °C: V = 373.15 / 299.15.
  EXPECT_NEAR(bubble_volume_ratio(100, 26), 373.15 / 299.15, 1e-12);
  EXPECT_DOUBLE_EQ(bubble_volume_ratio(26, 26), 1.0);
  // Eq 3.48: no extra pressure before heating, and the throttle ρ/ρ0.
  EXPECT_DOUBLE_EQ(bubble_pressure(1000, 900, 1000, 26, 26), 0.0);
  EXPECT_NEAR(bubble_pressure(1000, 500, 1000, 100, 26), 1000 * 0.5 * (373.15 / 299.15 - 1), 1e-9);
  // Eq 3.52: zero pressure at the risen density ρ_f.
  EXPECT_DOUBLE_EQ(tait_pressure(1000, 400, 400, 7), 0.0);
  EXPECT_NEAR(tait_pressure(1000, 440, 400, 7), 1000 * (std::pow(1.1, 7) - 1), 1e-9);
}

TEST(BubbleLaws, CoolingRisenGasContractsByTheGasLawAndNeverReexpands) {
  // Gas trapped at 100 °C and cooled to 25 °C occupies 298.15/373.15 of its
  // volume at constant pressure: the reference density grows by the inverse.
  EXPECT_NEAR(contracted_reference_density(500.0, 25.0, 100.0), 500.0 * 373.15 / 298.15, 1e-9);
  EXPECT_DOUBLE_EQ(contracted_reference_density(500.0, 100.0, 100.0), 500.0);
  EXPECT_DOUBLE_EQ(contracted_reference_density(500.0, 180.0, 100.0), 500.0);  // hotter: keeps the risen volume
}

TEST(SetCrustSoftening, ActsOnlyOnDilationAfterSettingOfADriedParticle) {
  SettingCurves sc{PiecewiseLinear::constant(1000), PiecewiseLinear::constant(10)};
  EXPECT_EQ(sc.softening_factor(1.5, 1.2, 0.5), 1.0);  // k = 0: the paper's law
  sc.set_softening = 60;
  sc.brittle_water_loss = 0.02;
  EXPECT_EQ(sc.softening_factor(1.1, 1.2, 0.5), 1.0);    // compacted since setting
  EXPECT_EQ(sc.softening_factor(1.32, 1.2, 0.02), 1.0);  // still moist: crumb
  // Fully brittle from twice the threshold: exp(−k (J/J_set − 1)).
  EXPECT_NEAR(sc.softening_factor(1.32, 1.2, 0.05), std::exp(-60 * 0.1), 1e-12);
  EXPECT_NEAR(sc.softening_factor(1.32, 1.2, 0.9), std::exp(-60 * 0.1), 1e-12);
  // Halfway up the ramp (water lost 0.03): half the rate.
  EXPECT_NEAR(sc.softening_factor(1.32, 1.2, 0.03), std::exp(-30 * 0.1), 1e-12);
  // Monotone: more dilation, weaker.
  EXPECT_LT(sc.softening_factor(1.4, 1.2, 0.1), sc.softening_factor(1.3, 1.2, 0.1));
}

// Short steps take e^{-x} from its series (physics/browning.hpp): each step
// must agree with the exponential to round-off on both sides of the switch,
// and a thousand short steps must add up to the closed form 1 - e^{-k t}.
TEST(BrowningKinetics, ShortStepsAgreeWithTheExponentialToRoundOff) {
  const BrowningKinetics zanoni;
  const double index = 0.3;
  for (const double celsius : {20.0, 100.0, 150.0, 200.0, 250.0, 300.0})
    for (const double x : {1e-12, 1e-8, 1e-5, 3e-4, 0.999e-3, 1.001e-3, 1e-2}) {
      const double dt = x / zanoni.rate(celsius);
      const double exact = 1.0 - (1.0 - index) * std::exp(-x);
      EXPECT_NEAR(zanoni.advance(index, celsius, dt), exact, 2e-16) << celsius << " degC, k dt " << x;
    }
  const double celsius = 180.0, t = 500.0;
  double b = 0;
  for (int k = 0; k < 1000; ++k) b = zanoni.advance(b, celsius, t / 1000);
  EXPECT_GT(zanoni.rate(celsius) * t / 1000, 1e-4);  // the series' range, not its trivial end
  EXPECT_LT(zanoni.rate(celsius) * t / 1000, 1e-3);
  // A thousand steps' round-off (a few 1e-16 each) either way.
  EXPECT_NEAR(b, 1.0 - std::exp(-zanoni.rate(celsius) * t), 2e-13);
}

TEST(Leavening, GenerationStopsWhenTheLeavenerIsSpent) {
  Leavening gas;
  gas.rate = 1e-5;
  gas.peak_temperature = 60;
  gas.width = 15;
  const Real density = 1000, dt = 1;
  // At the peak: a ρ₀ per second of bake, unlimited by default (the spec).
  EXPECT_NEAR(gas.generated(0.5, dt, 60, density), 0.5 + dt * 1e-5 * density, 1e-12);
  gas.amount = 1e-4;  // mol/kg: at most 0.1 mol per m³ of initial volume here
  EXPECT_NEAR(gas.generated(0.05, dt, 60, density), 0.06, 1e-12);
  EXPECT_DOUBLE_EQ(gas.generated(0.095, dt, 60, density), 0.1);
  EXPECT_DOUBLE_EQ(gas.generated(0.1, dt, 60, density), 0.1);    // spent: no more
  EXPECT_DOUBLE_EQ(gas.generated(0.12, dt, 60, density), 0.12);  // never taken back
  // The temperature factor of four particles at once (MPM) is the scalar law's.
  const Lane4 temperatures(20.0, 40.0, 61.3, 150.0);
  const Lane4 four = gas.profile(temperatures);
  for (int l = 0; l < 4; ++l) {
    const Real z = (temperatures[l] - gas.peak_temperature) / gas.width;
    EXPECT_NEAR(four[l], std::exp(-z * z), 4e-16 * std::exp(-z * z)) << temperatures[l];
    EXPECT_NEAR(gas.generated_at(0.01, dt, four[l], density), gas.generated(0.01, dt, temperatures[l], density), 1e-15);
  }
}

TEST(IrreversibleSetting, FollowsTheCurrentTemperatureUntilSetThenThePeak) {
  IrreversibleSetting never;  // null: reversible
  EXPECT_FALSE(never.ever());
  EXPECT_EQ(never.property_temperature(30.0, 180.0), 30.0);
  IrreversibleSetting at85{85.0};
  EXPECT_TRUE(at85.ever());
  EXPECT_EQ(at85.property_temperature(60.0, 70.0), 60.0);  // warmed to 70, cooled to 60: not set yet
  EXPECT_TRUE(at85.is_set(85.0));
  EXPECT_EQ(at85.property_temperature(40.0, 120.0), 120.0);  // set: the peak, however far it cools
  IrreversibleSetting always{-273.15};                       // the thesis's irreversible curves
  EXPECT_EQ(always.property_temperature(20.0, 20.0), 20.0);
  EXPECT_EQ(always.property_temperature(50.0, 90.0), 90.0);
  // With a curve flat beyond θ_set (the paper's Fig 8) a set particle reads the values at θ_set.
  const PiecewiseLinear yield({{20.0, 300.0}, {85.0, 3000.0}});
  EXPECT_EQ(yield(at85.property_temperature(40.0, 150.0)), yield(85.0));
}
