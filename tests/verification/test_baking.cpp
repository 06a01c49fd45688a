// Baking physics of the SPH solver (thesis 3.1.6, 3.3): the velocity
// gradient of Eq 3.27 on a linear field, a small hot sphere against the
// lumped-capacitance solution (Eq 3.42–3.43) and with oven wall radiation
// against the Stefan–Boltzmann one, the bake clock, heat from a hot
// collider, a set dough that holds its shape under gravity, and vented
// bubbles at the air-facing surface.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

json block_scene(double spacing) {
  return {{"solver", {{"type", "sph"}, {"sph", {{"spacing", spacing}}}}},
          {"time", {{"end", 1.0}}},
          {"gravity", {0, 0, 0}},
          {"domain", {{"min", {-0.05, -0.05, -0.05}}, {"max", {0.05, 0.05, 0.05}}}},
          {"materials", {{"dough", json::object()}}},
          {"bodies",
           json::array({{{"name", "block"},
                         {"material", "dough"},
                         {"shape", {{"type", "box"}, {"min", {-0.02, -0.02, -0.02}}, {"max", {0.02, 0.02, 0.02}}}}}})}};
}

}  // namespace

TEST(BakingPhysics, VelocityGradientOfALinearFieldIsRecoveredInside) {
  auto solver = test_support::make_sph(block_scene(0.002));
  Mat3 g;
  g << 0.3, -0.2, 0.1, 0.4, -0.1, 0.2, -0.3, 0.05, -0.2;
  auto& ps = solver->mutable_particles();
  auto& x = ps.vector("position");
  auto& v = ps.vector("velocity");
  for (std::size_t i = 0; i < x.size(); ++i) v[i] = g * x[i];
  double worst = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i].cwiseAbs().maxCoeff() < 0.02 - 0.0045)  // a full support inside
      worst = std::max(worst, (solver->velocity_gradient(i) - g).norm() / g.norm());
  // Eq 3.27 is not renormalised: on the initial lattice its kernel moment
  // is off by about 2%.
  EXPECT_LT(worst, 0.03) << worst;
}

namespace {

constexpr double kR = 0.01, kT0 = 20.0, kAir = 200.0, kH = 20.0;
constexpr double kRho = 1000.0, kCp = 1000.0;

// A small, very conductive sphere (Biot number h R / k = 4e-3): it heats
// uniformly, T(t) = T_air + (T0 − T_air) exp(−h A t / (m c_p)).
json hot_air_scene(double scale) {
  return {{"solver", {{"type", "sph"}, {"sph", {{"spacing", 0.002}}}}},
          {"time", {{"end", 1.0}}},
          {"gravity", {0, 0, 0}},
          {"environment", {{"air_temperature", kAir}, {"heat_transfer_coefficient", kH}, {"bake_time_scale", scale}}},
          {"domain", {{"min", {-0.02, -0.02, -0.02}}, {"max", {0.02, 0.02, 0.02}}}},
          {"materials", {{"metal", {{"density", kRho}, {"specific_heat", kCp}, {"conductivity", 50.0}}}}},
          {"bodies", json::array({{{"name", "ball"},
                                   {"material", "metal"},
                                   {"temperature", kT0},
                                   {"shape", {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", kR}}}}})}};
}

double mean_temperature(const Solver& s) {
  const auto& t = s.particles().scalar("temperature");
  double sum = 0;
  for (double v : t) sum += v;
  return sum / t.size();
}

}  // namespace

TEST(BakingPhysics, SmallSphereHeatsLikeTheLumpedSolution) {
  auto solver = test_support::make_sph(hot_air_scene(1.0));
  // The particles' mass; the exchange area is the sum of the surface
  // particles' areas (Eq 3.43), which tests/verification/test_surface.cpp
  // compares with the true sphere area.
  double mass = 0, area = 0;
  for (double mi : solver->particles().scalar("mass")) mass += mi;
  for (double ai : solver->particles().scalar("surface_area")) area += ai;
  const double tau = mass * kCp / (kH * area);
  const double t_end = 0.05 * tau;
  const double e0 = mean_temperature(*solver);
  test_support::advance_to(*solver, t_end);
  const double expected_rise = (kAir - kT0) * (1 - std::exp(-t_end / tau));
  const double rise = mean_temperature(*solver) - e0;
  RecordProperty("rise_ratio", std::to_string(rise / expected_rise));
  EXPECT_NEAR(rise / expected_rise, 1.0, 0.03);
  // Against the true sphere (exact mass and area) the coarse particle
  // sphere (radius 5 spacings) is within 15%.
  const double true_tau = kRho * kR * kCp / (3 * kH);
  EXPECT_NEAR(rise / ((kAir - kT0) * (1 - std::exp(-t_end / true_tau))), 1.0, 0.15);
  // The heat that came in through the surface is what the particles hold.
  EXPECT_NEAR(solver->exchanged_heat(), mass * kCp * rise, 1e-6 * mass * kCp * rise);
}

namespace {

// Lumped radiation, m c dT/dt = ε σ A (T_w⁴ − T⁴), in closed form: with
// F(T) = [ln((T_w + T)/(T_w − T)) + 2 atan(T/T_w)] / (4 T_w³) (kelvin),
// F'(T) = 1/(T_w⁴ − T⁴), so t = m c (F(T) − F(T0)) / (ε σ A). Returns T(t) in °C.
double radiated_temperature(double t, double t0_c, double wall_c, double mc_over_eps_sigma_a) {
  const double w = wall_c + 273.15;
  const auto F = [&](double T) { return (std::log((w + T) / (w - T)) + 2 * std::atan(T / w)) / (4 * w * w * w); };
  const double target = F(t0_c + 273.15) + t / mc_over_eps_sigma_a;
  double lo = t0_c + 273.15, hi = w;
  for (int k = 0; k < 200; ++k) (F(0.5 * (lo + hi)) < target ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi) - 273.15;
}

}  // namespace

// Oven wall radiation alone (no convection, ε 0.9, walls at the 200 °C air): the
// small conductive sphere follows the Stefan–Boltzmann lumped solution, in SPH
// with its particles' mass and exchange area (measured: 0.998 of the rise), in
// MPM against the true sphere (0.981).
TEST(BakingPhysics, OvenWallRadiationHeatsASmallSphereByStefanBoltzmann) {
  constexpr double kEps = 0.9, kSigma = 5.670374419e-8;
  constexpr double kClock = 50;  // bake seconds per simulated second
  json scene = hot_air_scene(kClock);
  scene["environment"]["heat_transfer_coefficient"] = 0.0;
  scene["environment"]["emissivity"] = kEps;
  // Conductivity 5 W/(m K): Biot number h_r R / k below 0.03, still lumped, and a 10x looser conduction step bound.
  scene["materials"]["metal"]["conductivity"] = 5.0;
  auto sph = test_support::make_sph(scene);
  double mass = 0, area = 0;
  for (double mi : sph->particles().scalar("mass")) mass += mi;
  for (double ai : sph->particles().scalar("surface_area")) area += ai;
  // Long enough for a rise of about 60 K at the initial rate (the rate falls as the ball warms).
  const double scale = mass * kCp / (kEps * kSigma * area);
  const double t_end = 60 * scale / (std::pow(kAir + 273.15, 4) - std::pow(kT0 + 273.15, 4));  // bake time
  const double expected = radiated_temperature(t_end, kT0, kAir, scale);
  ASSERT_GT(expected, 60.0);
  ASSERT_LT(expected, 80.0);
  const double e0 = mean_temperature(*sph);
  test_support::advance_to(*sph, t_end / kClock);
  const double rise = mean_temperature(*sph) - e0;
  RecordProperty("sph_rise_ratio", std::to_string(rise / (expected - kT0)));
  EXPECT_NEAR(rise / (expected - kT0), 1.0, 0.03) << "rise " << rise << " K, expected " << expected - kT0;
  EXPECT_NEAR(sph->exchanged_heat(), mass * kCp * rise, 1e-6 * mass * kCp * rise);
  // Without the emissivity nothing comes in.
  scene["environment"]["emissivity"] = 0.0;
  auto cold = test_support::make_sph(scene);
  test_support::advance_to(*cold, 0.1 * t_end / kClock);
  EXPECT_NEAR(mean_temperature(*cold), kT0, 1e-9);

  // MPM, 2 mm cells: against the true sphere's mass and area.
  constexpr double kMpmClock = 1000;  // the elastic wave bounds the MPM step: fewer steps on a faster clock
  json mpm_scene = hot_air_scene(kMpmClock);
  mpm_scene["solver"] = {{"type", "mpm"}, {"mpm", {{"cell_size", 0.002}, {"heat", "explicit"}}}};
  mpm_scene["environment"]["heat_transfer_coefficient"] = 0.0;
  mpm_scene["environment"]["emissivity"] = kEps;
  mpm_scene["materials"]["metal"]["conductivity"] = 5.0;
  auto mpm = test_support::make_mpm(mpm_scene);
  const double true_scale = kRho * kR * kCp / (3 * kEps * kSigma);
  const double true_expected = radiated_temperature(t_end, kT0, kAir, true_scale);
  const double m0 = mean_temperature(*mpm);
  test_support::advance_to(*mpm, t_end / kMpmClock);
  const double mpm_rise = mean_temperature(*mpm) - m0;
  RecordProperty("mpm_rise_ratio", std::to_string(mpm_rise / (true_expected - kT0)));
  EXPECT_NEAR(mpm_rise / (true_expected - kT0), 1.0, 0.04)
      << "rise " << mpm_rise << " K, expected " << true_expected - kT0;
}

TEST(BakingPhysics, BakeClockRunsHeatFasterByItsScale) {
  // 10 s of bake at scale 10 in 1 s of mechanics equals 10 s at scale 1.
  auto slow = test_support::make_sph(hot_air_scene(1.0));
  auto fast = test_support::make_sph(hot_air_scene(10.0));
  test_support::advance_to(*slow, 10.0);
  test_support::advance_to(*fast, 1.0);
  EXPECT_NEAR(fast->bake_time(), 10.0, 1e-9);
  const double rise_slow = mean_temperature(*slow) - kT0, rise_fast = mean_temperature(*fast) - kT0;
  EXPECT_GT(rise_slow, 1.0);
  EXPECT_NEAR(rise_fast / rise_slow, 1.0, 0.02);
}

TEST(BakingPhysics, HotTrayHeatsTheBottomFirst) {
  json scene = block_scene(0.002);
  scene["gravity"] = {0, -9.81, 0};
  scene["environment"] = {{"air_temperature", 20.0}, {"heat_transfer_coefficient", 0.0}, {"bake_time_scale", 100.0}};
  scene["materials"]["dough"] = {{"preset", "dough"}, {"viscosity", 10.0}};
  scene["bodies"][0]["temperature"] = 20.0;
  scene["bodies"][0]["shape"] = {{"type", "box"}, {"min", {-0.02, -0.049, -0.02}}, {"max", {0.02, -0.039, 0.02}}};
  scene["colliders"] = json::array({{{"name", "tray"},
                                     {"shape", {{"type", "plane"}, {"point", {0, -0.05, 0}}, {"normal", {0, 1, 0}}}},
                                     {"temperature", 200.0},
                                     {"heat_transfer_coefficient", 500.0}}});
  auto solver = test_support::make_sph(scene);
  test_support::advance_to(*solver, 0.1);
  const auto& x = solver->particles().vector("position");
  const auto& t = solver->particles().scalar("temperature");
  // Bottom: the layer on the tray; top: the upper 3 mm of the block as it now stands (it sags).
  double bottom = 0, top = 0, highest = -1;
  int nb = 0, nt = 0;
  for (const Vec3& p : x) highest = std::max(highest, p.y());
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i].y() < -0.047) bottom += t[i], ++nb;
    if (x[i].y() > highest - 0.003) top += t[i], ++nt;
  }
  bottom /= nb;
  top /= nt;
  EXPECT_GT(bottom, 40.0);
  EXPECT_LT(top, bottom - 10.0);
  EXPECT_GT(solver->exchanged_heat(), 0.0);
}

TEST(BakingPhysics, SetDoughHoldsItsShapeUnderGravity) {
  // Above T_f the dough of Table 4.1 has μ_e = 5e4 Pa, λ ≈ 900 s and
  // μ = 5e3 Pa·s: a 3 cm block must not sag by 5% in a second.
  json scene = block_scene(0.003);
  scene["gravity"] = {0, -9.81, 0};
  scene["environment"] = {{"air_temperature", 130.0}, {"heat_transfer_coefficient", 0.0}};
  scene["solver"]["sph"]["speed_of_sound"] = 10.0;
  scene["materials"]["dough"] = {{"preset", "dough"}};
  scene["bodies"][0]["temperature"] = 130.0;
  scene["bodies"][0]["shape"] = {{"type", "box"}, {"min", {-0.015, -0.05, -0.015}}, {"max", {0.015, -0.02, 0.015}}};
  auto solver = test_support::make_sph(scene);
  EXPECT_TRUE(solver->implicit_viscosity());
  auto height = [&] {
    double lo = 1e9, hi = -1e9;
    for (const Vec3& p : solver->particles().vector("position")) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
    return hi - lo;
  };
  const double h0 = height();
  test_support::advance_to(*solver, 1.0);
  RecordProperty("height_ratio", std::to_string(height() / h0));
  EXPECT_GT(height() / h0, 0.95);
  EXPECT_LT(height() / h0, 1.02);
}

// bubbles.vent_at_surface: a rising bubble particle that faced the oven air in
// the last heat phase presses by Tait on its rest density (clamped at 0), not
// by the gas law; one inside keeps the gas law. Without venting the air-facing
// bubbles press by the gas law like the rest (the thesis). A block of all
// bubble particles in hot air, gravity off, stepped until its outer layer has
// started to rise; the flags read are those before the last step.
TEST(BakingPhysics, VentedBubblesFacingTheAirHoldNoGasPressure) {
  auto run = [](bool vent) {
    json scene = block_scene(0.003);
    scene["solver"]["sph"]["speed_of_sound"] = 10.0;
    scene["environment"] = {
        {"air_temperature", 200.0}, {"heat_transfer_coefficient", 50.0}, {"bake_time_scale", 100.0}};
    scene["materials"]["dough"]["conductivity"] = 20.0;  // the layers under the surface heat and rise too
    scene["bodies"][0]["temperature"] = 20.0;
    scene["bodies"][0]["bubbles"] = {{"fraction", 1.0}, {"vent_at_surface", vent}, {"pressure_scale", 1000.0}};
    auto solver = test_support::make_sph(scene);
    test_support::advance_to(*solver, 0.02);
    // The pressure phase reads the flags of the last heat phase and the temperatures before this step's.
    const std::vector<std::int32_t> facing = solver->particles().integer("air_facing");
    const std::vector<Real> t = solver->particles().scalar("temperature");
    solver->step(solver->max_stable_dt());
    const auto& ps = solver->particles();
    const auto& rise = ps.integer("rise_state");
    const auto& p = ps.scalar("pressure");
    const auto& rho = ps.scalar("density");
    const double rho0 = 1000.0, b = rho0 * 10.0 * 10.0 / 7.0;  // the default material; Tait B = ρ0 c² / 7, c = 10 m/s
    const double b_gas = 1000.0;                               // pressure_scale
    int vented = 0, inside = 0, gas_law_at_face = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (rise[i] != 1) continue;
      const double gas = b_gas * (rho[i] / rho0) * ((t[i] + 273.15) / (20.0 + 273.15) - 1.0);
      const double tait = std::max(0.0, b * (std::pow(rho[i] / rho0, 7.0) - 1.0));
      if (facing[i]) {
        if (vent) {
          EXPECT_NEAR(p[i], tait, 1e-9 * b) << i;
          ++vented;
        } else if (std::abs(p[i] - gas) < 1e-9 * b && gas > tait + 0.1) {
          ++gas_law_at_face;
        }
      } else {
        EXPECT_NEAR(p[i], gas, 1e-9 * b) << i;
        ++inside;
      }
    }
    std::printf("vent %d: %d air-facing rising bubbles vented, %d pressing by the gas law; %d inside\n", vent, vented,
                gas_law_at_face, inside);
    return std::array<int, 3>{vented, gas_law_at_face, inside};
  };
  const auto vented = run(true), thesis = run(false);
  EXPECT_GT(vented[0], 50);
  EXPECT_GT(vented[2], 50);
  EXPECT_GT(thesis[1], 50);
  EXPECT_EQ(thesis[0], 0);
}

TEST(BakingPhysics, PeakPropertyTemperatureKeepsBakedDoughSetWhenItCools) {
  // The oven heats the ball to about 180 °C and is then switched off
  // (air 20 °C): set from the start (set_temperature −273.15) the viscosity
  // stays at the curve's value for the hottest temperature each particle
  // reached; never set (null) it falls back with the temperature.
  const TemperatureCurve curve = PiecewiseLinear({{20, 0.001}, {100, 0.05}});
  auto run = [&](const json& set_temperature) {
    json scene = hot_air_scene(1000.0);
    scene["environment"]["air_temperature"] = json::array({{0, 200}, {150, 200}, {151, 20}});
    scene["environment"]["heat_transfer_coefficient"] = 200.0;
    scene["materials"]["metal"]["conductivity"] = 5.0;  // Biot 0.4; a bake-clock step not bound by conduction
    scene["materials"]["metal"]["viscosity"] = {{"curve", "piecewise_linear"}, {"points", {{20, 0.001}, {100, 0.05}}}};
    scene["materials"]["metal"]["set_temperature"] = set_temperature;
    auto solver = test_support::make_sph(scene);
    test_support::advance_to(*solver, 0.3);  // 300 s of bake
    return solver;
  };
  auto peak = run(-273.15), current = run(nullptr);
  for (auto* s : {peak.get(), current.get()}) {
    const auto& t = s->particles().scalar("temperature");
    EXPECT_LT(*std::max_element(t.begin(), t.end()), 60.0);  // it has cooled well below the set range
  }
  const auto& mu_peak = peak->particles().scalar("viscosity");
  const auto& mu_now = current->particles().scalar("viscosity");
  const auto& t_now = current->particles().scalar("temperature");
  for (std::size_t i = 0; i < mu_peak.size(); ++i) {
    EXPECT_DOUBLE_EQ(mu_peak[i], 0.05);  // every particle passed 100 °C
    EXPECT_DOUBLE_EQ(mu_now[i], evaluate(curve, t_now[i]));
  }
}
