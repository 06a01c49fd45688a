// Thermomechanical MPM against outside numbers: the centre temperature of a
// slab heated through a convective boundary (the analytic series of a plane
// wall with Biot number Bi), a slab drying by diffusion and surface
// evaporation (the same series for the saturation), and the budgets: energy
// in = stored change, initial water = stored + evaporated, CO2 generated at a
// held temperature = a ρ exp(−z²) t V; and the same bake on 1 and 2 threads.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <tuple>

#include "core/parallel.hpp"
#include "helpers.hpp"
#include "support/threads.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

using test_support::make_mpm;

// Slab |x| < L, 0 < y, z < W between plates: the two plates normal to `hot_axis`
// faces get `face` exchange; the other four faces are insulated or closed.
struct Slab {
  double L = 0.02, W = 0.016, dx = 0.002;
};

json slab_scene(const Slab& s, json material, json environment, json colliders, const std::string& heat) {
  const double pad = 3 * s.dx + 0.006;
  return {{"solver", {{"type", "mpm"}, {"mpm", {{"cell_size", s.dx}, {"heat", heat}}}, {"cfl", 0.4}, {"max_dt", 1e-3}}},
          {"time", {{"end", 1.0}}},
          {"gravity", {0, 0, 0}},
          {"environment", environment},
          {"domain", {{"min", {-s.L - pad, -pad, -pad}}, {"max", {s.L + pad, s.W + pad, s.W + pad}}}},
          {"materials", {{"slab", material}}},
          {"bodies", json::array({{{"name", "slab"},
                                   {"material", "slab"},
                                   {"temperature", 20.0},
                                   {"shape", {{"type", "box"}, {"min", {-s.L, 0, 0}}, {"max", {s.L, s.W, s.W}}}}}})},
          {"colliders", colliders}};
}

json plate(const std::string& name, json lo, json hi, double temperature, double beta) {
  return {{"name", name},
          {"shape", {{"type", "box"}, {"min", lo}, {"max", hi}}},
          {"contact", "sticky"},
          {"temperature", temperature},
          {"heat_transfer_coefficient", beta}};
}

double centre_value(const mpm::MpmSolver& s, const std::string& quantity, double half_width) {
  const auto& x = s.particles().vector("position");
  const auto& q = s.particles().scalar(quantity);
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (std::abs(x[i].x()) < half_width) sum += q[i], ++n;
  return sum / n;
}

}  // namespace

// Outside the anonymous namespace: the test classes derive from it (unity builds warn otherwise).
class SlabHeat : public ::testing::TestWithParam<std::string> {};

TEST_P(SlabHeat, CentreTemperatureFollowsThePlaneWallSeries) {
  // ρ c = 1e6 J/(m³ K), κ = 1 W/(m K): α = 1e-6 m²/s, L²/α = 400 s; h = 50 W/(m² K): Bi = 1.
  const Slab s;
  const double rho = 1000, cp = 1000, kappa = 1, h = 50, t_inf = 120, t0 = 20;
  const double pad = 3 * s.dx + 0.006, far = 1.0;
  const json material = {{"density", rho}, {"specific_heat", cp}, {"conductivity", kappa}, {"youngs_modulus", 1e3}};
  // Hot plates on the x faces, insulated y and z faces (air with h = 0); bake clock 2000.
  const json colliders =
      json::array({plate("left", {-s.L - pad - far, -far, -far}, {-s.L, s.W + far, s.W + far}, t_inf, h),
                   plate("right", {s.L, -far, -far}, {s.L + pad + far, s.W + far, s.W + far}, t_inf, h)});
  const json env = {{"air_temperature", t0}, {"heat_transfer_coefficient", 0.0}, {"bake_time_scale", 2000.0}};
  auto solver = make_mpm(slab_scene(s, material, env, colliders, GetParam()));
  const double alpha = kappa / (rho * cp), biot = h * s.L / kappa;
  double worst = 0;
  for (double fo : {0.1, 0.25, 0.5, 1.0}) {
    const double bake = fo * s.L * s.L / alpha;
    test_support::advance_to(*solver, bake / 2000.0);
    const double measured = centre_value(*solver, "temperature", 0.1 * s.L);
    const double expected = t_inf + (t0 - t_inf) * test_support::plane_wall(biot, fo);
    const double error = std::abs(measured - expected) / (t_inf - t0);
    worst = std::max(worst, error);
    EXPECT_LT(error, 0.03) << "Fo " << fo << ": centre " << measured << " degC, series " << expected << " degC";
  }
  RecordProperty("worst_error_of_rise", std::to_string(worst));
  // Energy budget: what came through the boundary is what the slab stores.
  const double stored = solver->total_heat_energy() - rho * cp * (2 * s.L * s.W * s.W) * t0;
  EXPECT_NEAR(stored / solver->budget().heat_in, 1.0, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Mpm, SlabHeat, ::testing::Values("explicit", "implicit"));

class SlabDrying : public ::testing::TestWithParam<double> {};

TEST_P(SlabDrying, CentreFollowsThePlaneWallSeriesAndTheWaterBudgetCloses) {
  // Everything at 100 °C (no heat flow). Water diffuses with D = 1e-8 m²/s and
  // evaporates from the two x faces with flux E s, E = Bi D ρ_w / L: the mass
  // Biot number Bi = 1 or 10 (10 cells per half-thickness). The y and z faces
  // touch plates (no air, no evaporation).
  const Slab s;
  const double D = 1e-8, E = GetParam() * D * 1000 / s.L, s0 = 0.5, theta = 100;
  const double pad = 3 * s.dx + 0.006, far = 1.0;
  // Heat plays no part (all at 100 degC): a poor conductor keeps the conduction
  // bound (water's k, 0.6, on this bake clock) from setting the step.
  const json material = {{"density", 1000.0},
                         {"youngs_modulus", 1e3},
                         {"conductivity", 1e-3},
                         {"water", {{"saturation", s0}, {"diffusivity", D}, {"evaporation_rate", E}}}};
  const json colliders = json::array({plate("bottom", {-far, -pad - far, -far}, {far, 0, far}, theta, 10),
                                      plate("top", {-far, s.W, -far}, {far, s.W + pad + far, far}, theta, 10),
                                      plate("back", {-far, -far, -pad - far}, {far, far, 0}, theta, 10),
                                      plate("front", {-far, -far, s.W}, {far, far, s.W + pad + far}, theta, 10)});
  const json env = {{"air_temperature", theta}, {"heat_transfer_coefficient", 10.0}, {"bake_time_scale", 1e5}};
  json doc = slab_scene(s, material, env, colliders, "explicit");
  doc["bodies"][0]["temperature"] = theta;
  auto solver = make_mpm(doc);
  const double initial = solver->total_water();
  EXPECT_NEAR(initial, 1000 * s0 * 2 * s.L * s.W * s.W, 1e-9);
  const double biot = E * s.L / (D * 1000);
  for (double fo : {0.1, 0.3, 0.6}) {
    test_support::advance_to(*solver, fo * s.L * s.L / D / 1e5);
    const double measured = centre_value(*solver, "saturation", 0.1 * s.L) / s0;
    const double expected = test_support::plane_wall(biot, fo);
    {
      const auto& a = solver->particles().scalar("air_area");
      double area = 0;
      for (double v : a) area += v;
      printf("Fo %g centre %g expected %g; total water %g; air area %g (2W^2 %g)\n", fo, measured, expected,
             solver->total_water() / initial, area, 2 * s.W * s.W);
    }
    EXPECT_NEAR(measured, expected, 0.02) << "Fo " << fo;
    // Budget to round-off: water is only lost through the surface.
    const double stored = solver->total_water(), gone = solver->budget().evaporated;
    EXPECT_NEAR((stored + gone) / initial, 1.0, 1e-10) << "stored " << stored << " evaporated " << gone;
    EXPECT_EQ(solver->budget().clamped, 0.0);
  }
}

// Bi = 10 too: the evaporating particles sit up to a cell inside the face, and
// their flux is that of the face below them (Moisture::evaporation_flux_below).
// Measured: Bi 1 within 0.002, Bi 10 within 0.014 (0.02-0.06 ahead of the
// series when particles evaporated at their own saturation).
INSTANTIATE_TEST_SUITE_P(MassBiot, SlabDrying, ::testing::Values(1.0, 10.0));

TEST(MpmBaking, Co2GeneratedAtAHeldTemperatureMatchesTheRateLawAndRaisesTheBlock) {
  // A porous Cam-clay block held at θ = θ_r + Δθ/2 (body and air alike):
  // n = a ρ₀ exp(−1/4) t per unit initial volume; its pressure expands the block.
  const double a = 2e-5, rho = 500, peak = 40, width = 20, theta = peak + 0.5 * width;
  json doc = {
      {"solver", {{"type", "mpm"}, {"mpm", {{"cell_size", 0.004}, {"heat", "explicit"}}}, {"max_dt", 1e-3}}},
      {"time", {{"end", 1.0}}},
      {"gravity", {0, 0, 0}},
      {"environment", {{"air_temperature", theta}, {"heat_transfer_coefficient", 10.0}, {"bake_time_scale", 10.0}}},
      {"domain", {{"min", {-0.06, -0.06, -0.06}}, {"max", {0.06, 0.06, 0.06}}}},
      {"materials",
       {{"dough",
         {{"density", rho},
          {"youngs_modulus", 2e4},
          {"plasticity",
           {{"model", "cam_clay"}, {"yield_stress", 50.0}, {"viscosity", 0.0}, {"initial_porosity", 0.2}}},
          {"leavening", {{"rate", a}, {"peak_temperature", peak}, {"width", width}}}}}}},
      {"bodies",
       json::array({{{"name", "block"},
                     {"material", "dough"},
                     {"temperature", theta},
                     {"shape", {{"type", "box"}, {"min", {-0.02, -0.02, -0.02}}, {"max", {0.02, 0.02, 0.02}}}}}})}};
  auto solver = make_mpm(doc);
  const double v0 = 0.04 * 0.04 * 0.04;
  const double volume0 = deterministic_sum(
      solver->particles().size(), [&](std::size_t i) { return solver->particles().scalar("initial_volume")[i]; });
  EXPECT_NEAR(volume0, v0, 1e-9);
  test_support::advance_to(*solver, 0.2);
  const double bake = solver->bake_time();
  const double expected = a * rho * std::exp(-0.25) * bake * volume0;
  EXPECT_NEAR(solver->total_co2() / expected, 1.0, 1e-9);
  double volume = 0;
  const auto& j = solver->particles().scalar("J");
  for (std::size_t i = 0; i < j.size(); ++i) volume += j[i] * solver->particles().scalar("initial_volume")[i];
  EXPECT_GT(volume / volume0, 1.1) << "the gas pressure expands the porous block";
}

TEST(MpmBaking, SameBakeOnOneAndTwoThreads) {
  const test_support::ThreadLimitLifted all_threads;  // compares thread counts
  // The full model (heat, water, gas, temperature-dependent Cam-clay) on the
  // medium cookie: positions, temperatures and water identical bit for bit.
  std::ifstream in(std::string(BAKESIM_SOURCE_DIR) + "/scenes/cookie.json");
  std::stringstream ss;
  ss << in.rdbuf();
  auto doc = json::parse(ss.str());
  doc["solver"]["mpm"]["cell_size"] = 0.005;
  doc["environment"]["bake_time_scale"] = 3000.0;  // reach the leavening and setting range in 200 steps
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    auto s = make_mpm(doc);
    for (int k = 0; k < 200; ++k) s->step(s->max_stable_dt());
    EXPECT_GT(s->total_co2(), 0.0);
    return std::make_tuple(s->particles().vector("position"), s->particles().scalar("temperature"),
                           s->particles().scalar("water_mass"));
  };
  const auto a = run(1), b = run(2);
  ASSERT_EQ(std::get<0>(a).size(), std::get<0>(b).size());
  for (std::size_t i = 0; i < std::get<0>(a).size(); ++i) {
    ASSERT_EQ(std::get<0>(a)[i], std::get<0>(b)[i]) << i;
    ASSERT_EQ(std::get<1>(a)[i], std::get<1>(b)[i]) << i;
    ASSERT_EQ(std::get<2>(a)[i], std::get<2>(b)[i]) << i;
  }
}
