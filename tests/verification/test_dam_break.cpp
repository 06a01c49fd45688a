// Dam break: the surge front x/a against Martin & Moyce (1952) for
// T = t sqrt(2g/a) in [0.5, 2.5], within 10%. Coarser than scenes/dam-break.json
// so it fits the CI budget; docs/validation.md has the full-resolution run.
// With either pressure: weakly compressible and divergence-free.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

json dam_break(double spacing, const char* pressure_solver = "weakly_compressible") {
  const double a = 0.146;
  return {{"solver", {{"type", "sph"}, {"sph", {{"spacing", spacing}, {"pressure_solver", pressure_solver}}}}},
          {"time", {{"end", 0.3}}},
          {"domain", {{"min", {0, 0, 0}}, {"max", {4 * a, 3 * a, 0.5 * a}}}},
          {"materials", {{"water", {{"density", 1000.0}, {"viscosity", 1e-3}, {"xsph", 0.1}}}}},
          {"bodies",
           {{{"name", "column"},
             {"material", "water"},
             {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {a, 2 * a, 0.5 * a}}}}}}}};
}

// (T, Z) of Martin & Moyce (1952), both column sizes, T in [0.5, 2.5], in time order.
std::vector<std::pair<double, double>> martin_moyce_points() {
  std::vector<std::pair<double, double>> points;
  for (const auto& row : test_support::read_csv(std::string(BAKESIM_VALIDATION_DIR) + "/dambreak_martin_moyce1952.csv"))
    if (row[1] >= 0.5 && row[1] <= 2.5) points.emplace_back(row[1], row[2]);
  std::sort(points.begin(), points.end());
  return points;
}

}  // namespace

TEST(DamBreak, SurgeFrontFollowsMartinAndMoyce) {
  const double a = 0.146, g = 9.81;
  const double t_scale = std::sqrt(2 * g / a);
  auto solver = test_support::make_sph(dam_break(a / 20));
  const auto points = martin_moyce_points();
  int compared = 0;
  double worst = 0;
  for (const auto& [T, Z] : points) {
    test_support::advance_to(*solver, T / t_scale);
    double front = 0;
    for (const Vec3& x : solver->particles().vector("position")) front = std::max(front, x.x());
    const double z_sim = front / a;
    const double err = std::abs(z_sim - Z) / Z;
    worst = std::max(worst, err);
    EXPECT_LT(err, 0.10) << "T = " << T << ": simulated Z = " << z_sim << ", Martin & Moyce Z = " << Z;
    ++compared;
  }
  EXPECT_GE(compared, 5);
  RecordProperty("worst_relative_error", std::to_string(worst));
}

// The same tank with the divergence-free pressure (solver.sph.pressure_solver,
// DFSPH). Measured: +10.8% at T = 1.212, the rest within +4.3% to +8.9%
// (weakly compressible at a/20: 8.5% at most). Both run ahead of the
// experiment more as they are refined (docs/validation.md: at ~100K
// particles the weakly compressible front is 11.6% ahead at T = 1.212); the
// bound, 12%, catches a front that breaks away; it does not claim the
// issue's 10%.
TEST(DivergenceFree, DamBreakFollowsMartinAndMoyce) {
  const double a = 0.146, g = 9.81;
  const double t_scale = std::sqrt(2 * g / a);
  auto solver = test_support::make_sph(dam_break(a / 20, "divergence_free"));
  const auto points = martin_moyce_points();
  ASSERT_GE(points.size(), 5u);
  long steps = 0, iterations = 0;
  double worst = 0;
  for (const auto& [T, Z] : points) {
    test_support::advance_to(*solver, T / t_scale, [&] {
      ++steps;
      iterations += solver->last_density_iterations() + solver->last_divergence_iterations();
    });
    double front = 0;
    for (const Vec3& x : solver->particles().vector("position")) front = std::max(front, x.x());
    const double z_sim = front / a, err = (z_sim - Z) / Z;
    std::printf("divergence-free a/20: T %.3f Z measured %.3f simulated %.3f (%+.1f%%)\n", T, Z, z_sim, 100 * err);
    if (std::abs(err) > std::abs(worst)) worst = err;
    EXPECT_LT(std::abs(err), 0.12) << "T = " << T << ": simulated Z = " << z_sim << ", Martin & Moyce Z = " << Z;
  }
  std::printf("divergence-free a/20: %ld steps to t = %.3f s, %.1f solve iterations a step\n", steps, solver->time(),
              double(iterations) / double(steps));
  RecordProperty("worst_relative_error", std::to_string(worst));
}

namespace {

// The same tank in MPM: water as a von Mises material with no yield stress
// (its deviator relaxes to the viscous stress of μ = η/2 = 1 mPa s each step)
// and an elastic bulk stiff enough that the column barely compresses: with
// E = 0.2 MPa and ν = 0.45 the bulk modulus is 0.67 MPa, a sound speed of
// 26 m/s, ten times the surge's ~2.4 m/s. Quasi-2D: periodic along z, four
// cells deep. The domain faces are free-slip walls.
json mpm_dam_break(int cells_per_a) {
  const double a = 0.146, dx = a / cells_per_a;
  return {{"solver", {{"type", "mpm"}, {"mpm", {{"cell_size", dx}, {"heat", "off"}, {"model", "baseline"}}}}},
          {"time", {{"end", 0.3}}},
          {"domain", {{"min", {0, 0, 0}}, {"max", {4 * a, 3 * a, 4 * dx}}, {"periodic", {"z"}}}},
          {"materials",
           {{"water",
             {{"density", 1000.0},
              {"youngs_modulus", 2e5},
              {"poisson_ratio", 0.45},
              {"plasticity", {{"model", "von_mises"}, {"yield_stress", 0.0}, {"viscosity", 2e-3}}}}}}},
          {"bodies",
           {{{"name", "column"},
             {"material", "water"},
             {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {a, 2 * a, 4 * dx}}}}}}}};
}

}  // namespace

// Issue 26: the dam break in MPM, against the same Martin & Moyce points. The
// front is the largest material-point x plus the quarter cell each point
// stands for (points start half a cell apart), so Z = 1 at rest. Measured
// (docs/validation.md): the MPM front runs ahead of the experiment, worst
// +14.5% at a/10 and +20.0% at a/20 (SPH: +8.5% at a/20), and refining does
// not bring it closer: an open defect of issue 26. The bound, 25%, catches
// a front that breaks away (a wall that leaks, material that stops feeling
// the floor) without claiming the agreement the issue asks for.
class MpmDamBreak : public ::testing::TestWithParam<std::tuple<int, double>> {};

TEST_P(MpmDamBreak, SurgeFrontFollowsMartinAndMoyce) {
  const auto [cells_per_a, tolerance] = GetParam();
  const double a = 0.146, g = 9.81, dx = a / cells_per_a;
  const double t_scale = std::sqrt(2 * g / a);
  auto solver = test_support::make_mpm(mpm_dam_break(cells_per_a));
  const std::size_t count = solver->particles().size();
  const auto points = martin_moyce_points();
  ASSERT_GE(points.size(), 5u);
  double worst = 0;
  for (const auto& [T, Z] : points) {
    test_support::advance_to(*solver, T / t_scale);
    double front = 0;
    for (const Vec3& x : solver->particles().vector("position")) front = std::max(front, x.x());
    const double z_sim = (front + 0.25 * dx) / a;
    const double err = (z_sim - Z) / Z;
    std::printf("MPM a/%d: T %.3f Z measured %.3f simulated %.3f (%+.1f%%)\n", cells_per_a, T, Z, z_sim, 100 * err);
    if (std::abs(err) > std::abs(worst)) worst = err;
    EXPECT_LT(std::abs(err), tolerance) << "T = " << T << ": simulated Z = " << z_sim << ", Martin & Moyce Z = " << Z;
  }
  EXPECT_EQ(solver->particles().size(), count);
  RecordProperty("worst_relative_error", std::to_string(worst));
}

INSTANTIATE_TEST_SUITE_P(Cells, MpmDamBreak, ::testing::Values(std::make_tuple(10, 0.25)),
                         [](const auto& info) { return "a_over_" + std::to_string(std::get<0>(info.param)); });
// The finer cases of the convergence study (15 s and 2 minutes on 2 threads):
// --gtest_also_run_disabled_tests.
INSTANTIATE_TEST_SUITE_P(DISABLED_Fine, MpmDamBreak,
                         ::testing::Values(std::make_tuple(20, 0.25), std::make_tuple(40, 0.25)),
                         [](const auto& info) { return "a_over_" + std::to_string(std::get<0>(info.param)); });
