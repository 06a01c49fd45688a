// The divergence-free SPH pressure (solver.sph.pressure_solver
// "divergence_free", DFSPH): a still column holds hydrostatic pressure and
// its rest density with steps bounded by the flow instead of the speed of
// sound, and the dam break follows Martin & Moyce (1952) as the weakly
// compressible pressure does (tests/verification/test_dam_break.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

json divergence_free(json sph) {
  sph["pressure_solver"] = "divergence_free";
  return sph;
}

}  // namespace

// The column of Hydrostatic.MidDepthPressureIsRhoGH (test_hydrostatic.cpp)
// without artificial viscosity: no acoustic ringing to damp. Mid-depth
// pressure against ρ g (H − y) averaged over 0.2–0.5 s, the density of the
// particles held within the solve's tolerance, the column at rest, and
// steps no longer bounded by the speed of sound (the weakly compressible
// column takes its CFL step of about 1e-4 s; at rest this one takes max_dt).
// Measured (docs/validation.md): pressure +5.5% (weakly compressible: +3.8%;
// the symmetric SPH gradient next to the side walls needs more pressure
// than ρ g, and the interior feels it), mean |ρ/ρ0 − 1| inside 0.01%,
// 168 of 3,600 particles above 1 cm/s. With a density tolerance of 0.1%
// instead of 0.01% the column filled with unpressed voids (mean 0.9%).
TEST(DivergenceFree, StillColumnHoldsHydrostaticPressureAndRestDensity) {
  const double width = 0.06, height = 0.12, depth = 0.032, s = 0.004;
  const json doc = {{"solver", {{"type", "sph"}, {"sph", divergence_free({{"spacing", s}})}}},
                    {"time", {{"end", 0.5}}},
                    {"domain", {{"min", {0, 0, 0}}, {"max", {width, 0.15, depth}}}},
                    {"materials", {{"water", {{"density", 1000.0}, {"viscosity", 1e-3}, {"xsph", 0.1}}}}},
                    {"bodies",
                     {{{"name", "column"},
                       {"material", "water"},
                       {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {width, height, depth}}}}}}}};
  auto solver = test_support::make_sph(doc);
  ASSERT_TRUE(solver->divergence_free());
  test_support::advance_to(*solver, 0.2);
  const double g = 9.81, rho0 = 1000.0, h = 2 * s;
  double measured_sum = 0, expected_sum = 0, worst_density_error = 0;
  long samples = 0, steps = 0;
  const auto& ps = solver->particles();
  test_support::advance_to(*solver, 0.5, [&] {
    ++steps;
    worst_density_error = std::max(worst_density_error, solver->last_density_error());
    const auto& x = ps.vector("position");
    const auto& p = ps.scalar("pressure");
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const Vec3& xi = x[i];
      if (std::abs(xi.y() - height / 2) > s || xi.x() < h || xi.x() > width - h || xi.z() < h || xi.z() > depth - h)
        continue;
      measured_sum += p[i];
      expected_sum += rho0 * g * (height - xi.y());
      ++samples;
    }
  });
  ASSERT_GT(samples, 100);
  const double measured = measured_sum / samples, expected = expected_sum / samples;
  std::printf("divergence-free column: %ld steps in 0.3 s, mid-depth pressure %.1f Pa against %.1f Pa (%+.2f%%)\n",
              steps, measured, expected, 100 * (measured - expected) / expected);
  EXPECT_NEAR(measured, expected, 0.07 * expected) << "measured " << measured << " Pa, expected " << expected << " Pa";
  RecordProperty("relative_error", std::to_string((measured - expected) / expected));
  // Each density solve stopped at its tolerance (0.01% mean predicted error)
  // or, after its 100 iterations, not far above it (measured: 0.025% at worst).
  EXPECT_LE(worst_density_error, 5e-4);
  // Inside the column (more than h from every face) the density is at rest
  // within 0.05% on the mean and 1% at any particle.
  const auto& x = ps.vector("position");
  const auto& rho = ps.scalar("density");
  double worst_inside = 0, sum_inside = 0;
  long inside = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const Vec3& xi = x[i];
    if (xi.y() < h || xi.y() > height - 2 * h || xi.x() < h || xi.x() > width - h || xi.z() < h || xi.z() > depth - h)
      continue;
    worst_inside = std::max(worst_inside, std::abs(rho[i] / rho0 - 1));
    sum_inside += std::abs(rho[i] / rho0 - 1);
    ++inside;
  }
  ASSERT_GT(inside, 100);
  std::printf("inside: mean |rho/rho0 - 1| %.4f, worst %.4f\n", sum_inside / inside, worst_inside);
  EXPECT_LT(sum_inside / inside, 5e-4);
  EXPECT_LT(worst_inside, 0.01);
  double vmax = 0;
  std::size_t moving = 0;  // above 1 cm/s
  for (const Vec3& v : ps.vector("velocity")) {
    vmax = std::max(vmax, v.norm());
    moving += v.norm() > 0.01;
  }
  std::printf("fastest %.3f m/s, %zu of %zu above 0.01 m/s\n", vmax, moving, ps.size());
  EXPECT_LT(vmax, 0.05 * std::sqrt(2 * g * height));
  EXPECT_LT(moving, ps.size() / 10);
  // 0.3 s at rest in at most 1,000 steps (weakly compressible: about 3,000).
  EXPECT_LE(steps, 1000);
}

// The dam break of DamBreak.SurgeFrontFollowsMartinAndMoyce (a/20 across the
// column), its front against the measured one at T = t √(2g/a) in [0.5, 2.5].
// Measured: +10.8% at T = 1.212, the rest within +4.3% to +8.9% (weakly
// compressible at a/20: 8.5% at most). Both run ahead of the experiment
// more as they are refined (docs/validation.md: at ~100K particles the
// weakly compressible front is 11.6% ahead at T = 1.212); the bound, 12%,
// catches a front that breaks away; it does not claim the 10%.
TEST(DivergenceFree, DamBreakFollowsMartinAndMoyce) {
  const double a = 0.146, g = 9.81;
  const double t_scale = std::sqrt(2 * g / a);
  const json doc = {{"solver", {{"type", "sph"}, {"sph", divergence_free({{"spacing", a / 20}})}}},
                    {"time", {{"end", 0.3}}},
                    {"domain", {{"min", {0, 0, 0}}, {"max", {4 * a, 3 * a, 0.5 * a}}}},
                    {"materials", {{"water", {{"density", 1000.0}, {"viscosity", 1e-3}, {"xsph", 0.1}}}}},
                    {"bodies",
                     {{{"name", "column"},
                       {"material", "water"},
                       {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {a, 2 * a, 0.5 * a}}}}}}}};
  auto solver = test_support::make_sph(doc);
  std::vector<std::pair<double, double>> points;
  for (const auto& row : test_support::read_csv(std::string(BAKESIM_VALIDATION_DIR) + "/dambreak_martin_moyce1952.csv"))
    if (row[1] >= 0.5 && row[1] <= 2.5) points.emplace_back(row[1], row[2]);
  std::sort(points.begin(), points.end());
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
