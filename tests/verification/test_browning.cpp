// Browning (Zanoni et al. 1995; physics/browning.hpp): a body held at a
// constant temperature browns monotonically, and its browning index after a
// bake time t is the closed form 1 − exp(−k t) with k = k0 exp(−Ea / (R T)),
// computed here from the paper's numbers, for both solvers.
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

using namespace bakesim;
using json = nlohmann::json;

namespace {

constexpr double kHeld = 200.0;  // °C, body and oven air alike
double zanoni_rate(double celsius) { return 42000.0 * std::exp(-64151.0 / (8.314462618 * (celsius + 273.15))); }

json held_scene(const std::string& solver) {
  json s = {{"type", solver}, {"max_dt", 1e-3}};
  if (solver == "mpm")
    s["mpm"] = {{"cell_size", 0.01}, {"heat", "explicit"}};
  else
    s["sph"] = {{"spacing", 0.01}};
  return {
      {"solver", s},
      {"time", {{"end", 1.0}}},
      {"gravity", {0, 0, 0}},
      {"environment", {{"air_temperature", kHeld}, {"bake_time_scale", 600.0}}},
      {"domain", {{"min", {-0.1, -0.1, -0.1}}, {"max", {0.1, 0.1, 0.1}}}},
      {"materials",
       {{"dough", solver == "mpm" ? json{{"density", 1000.0}, {"youngs_modulus", 1e4}} : json{{"density", 1000.0}}}}},
      {"bodies",
       json::array({{{"name", "crust"},
                     {"material", "dough"},
                     {"temperature", kHeld},
                     {"shape", {{"type", "box"}, {"min", {-0.02, -0.02, -0.02}}, {"max", {0.02, 0.02, 0.02}}}}}})}};
}

void expect_closed_form(Solver& solver, double bake_time_scale) {
  const auto& b = solver.particles().scalar("browning");
  double previous = b[0];
  int steps = 0;
  test_support::advance_to(solver, 0.5, [&] {
    EXPECT_GE(b[0], previous) << "browning went back at step " << steps;
    previous = b[0];
    ++steps;
  });
  ASSERT_GT(steps, 10);
  const double bake = solver.time() * bake_time_scale;  // 300 s
  const double expected = 1.0 - std::exp(-zanoni_rate(kHeld) * bake);
  EXPECT_GT(expected, 0.5);  // the test is not trivial: most of the way to burnt
  for (double v : b) EXPECT_NEAR(v, expected, 1e-6 * expected);
}

}  // namespace

TEST(Browning, MpmBodyHeldAt200CMatchesTheClosedFormKinetics) {
  auto solver = test_support::make_mpm(held_scene("mpm"));
  expect_closed_form(*solver, 600.0);
}

TEST(Browning, SphBodyHeldAt200CMatchesTheClosedFormKinetics) {
  auto solver = test_support::make_sph(held_scene("sph"));
  expect_closed_form(*solver, 600.0);
}

// Moist dough browns only once dried past the boiling point (the spec's
// "browning then runs only where the crust is above 100 °C"): a moist body
// in 100 °C air stays pale, the same body without water browns by the
// closed form (1.2% of the way in 300 s at 100 °C).
class BrowningOfMoistDough : public ::testing::TestWithParam<std::string> {};

TEST_P(BrowningOfMoistDough, WaitsForTheCrustToDryPastTheBoilingPoint) {
  for (const bool moist : {true, false}) {
    json scene = held_scene(GetParam());
    scene["environment"]["air_temperature"] = 100.0;
    scene["bodies"][0]["temperature"] = 100.0;
    if (moist) scene["materials"]["dough"]["moisture"] = {{"content", 0.5}};
    std::unique_ptr<Solver> solver = GetParam() == "sph" ? std::unique_ptr<Solver>(test_support::make_sph(scene))
                                                         : std::unique_ptr<Solver>(test_support::make_mpm(scene));
    test_support::advance_to(*solver, 0.5);
    const double closed = 1.0 - std::exp(-zanoni_rate(100.0) * solver->time() * 600.0);
    double lo = 1, hi = 0;
    for (double v : solver->particles().scalar("browning")) lo = std::min(lo, v), hi = std::max(hi, v);
    if (moist) {
      EXPECT_EQ(hi, 0.0) << GetParam();
    } else {
      EXPECT_NEAR(lo, closed, 1e-6) << GetParam();
      EXPECT_NEAR(hi, closed, 1e-6) << GetParam();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(BothSolvers, BrowningOfMoistDough, ::testing::Values("sph", "mpm"));

TEST(Browning, ColderCrustBrownsSlowerAsArrheniusSays) {
  const BrowningKinetics k;
  // k(200 °C) / k(150 °C) = exp(Ea/R (1/423.15 − 1/473.15)) ≈ 4.6
  EXPECT_NEAR(k.rate(200) / k.rate(150), std::exp(64151.0 / 8.314462618 * (1 / 423.15 - 1 / 473.15)), 1e-9);
  EXPECT_NEAR(k.colour_difference(1.0), 52.0, 1e-12);
}
