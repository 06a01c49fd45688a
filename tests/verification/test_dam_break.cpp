// Dam break: the surge front x/a against Martin & Moyce (1952) for
// T = t sqrt(2g/a) in [0.5, 2.5], within 10%. Coarser than scenes/dam-break.json
// so it fits the CI budget; docs/validation.md has the full-resolution run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

json dam_break(double spacing) {
  const double a = 0.146;
  return {{"solver", {{"type", "sph"}, {"sph", {{"spacing", spacing}}}}},
          {"time", {{"end", 0.3}}},
          {"domain", {{"min", {0, 0, 0}}, {"max", {4 * a, 3 * a, 0.5 * a}}}},
          {"materials", {{"water", {{"density", 1000.0}, {"viscosity", 1e-3}, {"xsph", 0.1}}}}},
          {"bodies",
           {{{"name", "column"},
             {"material", "water"},
             {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {a, 2 * a, 0.5 * a}}}}}}}};
}

}  // namespace

TEST(DamBreak, SurgeFrontFollowsMartinAndMoyce) {
  const double a = 0.146, g = 9.81;
  const double t_scale = std::sqrt(2 * g / a);
  auto solver = test_support::make_sph(dam_break(a / 20));
  const auto data = test_support::read_csv(std::string(BAKESIM_VALIDATION_DIR) + "/dambreak_martin_moyce1952.csv");
  ASSERT_FALSE(data.empty());
  // Both column sizes of the experiment, in time order.
  std::vector<std::pair<double, double>> points;
  for (const auto& row : data)
    if (row[1] >= 0.5 && row[1] <= 2.5) points.emplace_back(row[1], row[2]);
  std::sort(points.begin(), points.end());
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
