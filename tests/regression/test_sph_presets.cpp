// Issue 22 item 1: every food preset has an SPH section and bakes in SPH. A
// 44 mm round of it in a muffin cup, 20 minutes at 180 °C, coarse (4 mm) for
// CI: it stays finite and in its cup, comes to rest, its moist dough stays at
// the boiling point, its core heats through, a setting food's outside sets and
// it loses water (the chocolate, whose water is all bound, keeps it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>

#include "io/materials.hpp"
#include "io/scene.hpp"
#include "sph/solver.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

// The presets with an SPH section and a composition (foods, not the thesis's dough).
const char* kFoodPresetsWithSph[] = {"lean-bread-dough", "enriched-dough", "cookie-dough", "sponge-batter",
                                     "muffin-batter",    "pancake-batter", "marshmallow",  "dark-chocolate",
                                     "apple-flesh",      "apple-skin"};

constexpr double kCupRadius = 0.026, kCupFloor = 0.003, kSpacing = 0.004;

json cup_scene(const std::string& preset) {
  json scene = json::parse(R"({
    "name": "preset-in-a-cup",
    "solver": {"type": "sph", "sph": {"spacing": 0.004, "speed_of_sound": 5.0}},
    "time": {"end": 1.0, "fps": 5},
    "domain": {"min": [-0.04, -0.01, -0.04], "max": [0.04, 0.08, 0.04]},
    "environment": {"air_temperature": 180, "oven": "conventional", "bake_time_scale": 1200,
                    "mass_transfer_coefficient": 0},
    "bodies": [{"name": "round", "material": "food",
                "shape": {"type": "cylinder", "center": [0, 0.017, 0], "axis": [0, 1, 0],
                          "radius": 0.022, "height": 0.026}}],
    "colliders": [{"name": "cup", "shape": {"type": "cup", "base": [0, 0.003, 0], "radius": 0.026,
                                            "height": 0.035, "wall_thickness": 0.01},
                   "friction": 0.5, "temperature": "oven", "heat_transfer_coefficient": 150}]
  })");
  scene["materials"] = {{"food", {{"preset", preset}}}};
  return scene;
}

}  // namespace

class SphPreset : public ::testing::TestWithParam<const char*> {};

// The list above is every such preset: a new one is tested or this fails.
TEST(SphPresets, TheListHoldsEveryFoodPresetWithAnSphSection) {
  std::set<std::string> expected;
  for (const std::string& name : material_preset_names()) {
    const json p = material_preset(name, "test");
    if (p.contains("sph") && p.contains("composition")) expected.insert(name);
  }
  EXPECT_EQ(std::set<std::string>(std::begin(kFoodPresetsWithSph), std::end(kFoodPresetsWithSph)), expected);
}

TEST_P(SphPreset, BakesInACupAtRestMoistBelowBoilingSetOnTheOutside) {
  const std::string preset = GetParam();
  const Scene scene = parse_scene(cup_scene(preset).dump(), "scene.json", ".");
  const json material = scene.resolved["materials"]["food"];
  const double set_temperature =
      material["set_temperature"].is_null() ? 1e9 : material["set_temperature"].get<double>();
  const double moisture0 = material["moisture"]["content"].get<double>();
  ASSERT_GT(moisture0, 0.0) << "the preset's composition gives the moisture";
  // An elastic solid that never relaxes (the apple presets) must keep its shape.
  const bool solid = material["relaxation_time"].is_number() && material["relaxation_time"].get<double>() >= 1e5;
  sph::SphSolver solver(scene.sph);
  const auto& ps = solver.particles();
  auto height = [&ps] {
    double lo = 1e9, hi = -1e9;
    for (const Vec3& x : ps.vector("position")) lo = std::min(lo, double(x.y())), hi = std::max(hi, double(x.y()));
    return hi - lo;
  };
  const double height0 = height();
  const auto& temperature = ps.scalar("temperature");
  const auto& moisture = ps.scalar("moisture");
  const auto& water = ps.scalar("water_mass");
  double water0 = 0;
  for (double w : water) water0 += w;
  double hottest_moist = 0;  // the hottest particle still holding 0.3 kg/kg (issue 20's crumb criterion)
  int step = 0;
  while (solver.time() < scene.end_time - 1e-12) {
    solver.step(std::min(solver.max_stable_dt(), scene.end_time - solver.time()));  // throws on NaN
    if (++step % 20 == 0)
      for (std::size_t i = 0; i < ps.size(); ++i)
        if (moisture[i] > 0.3) hottest_moist = std::max(hottest_moist, double(temperature[i]));
  }
  solver.synchronize();  // as the frame loop does before a frame
  double fastest = 0, out_of_cup = 0, coldest = 1e9, water1 = 0, mass = 0;
  std::size_t set = 0;
  const auto &position = ps.vector("position"), &velocity = ps.vector("velocity");
  const auto &particle_mass = ps.scalar("mass"), &peak = ps.scalar("peak_temperature");
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const Vec3& x = position[i];
    fastest = std::max(fastest, double(velocity[i].norm()));
    out_of_cup = std::max({out_of_cup, std::hypot(x.x(), x.z()) - kCupRadius, kCupFloor - x.y()});
    coldest = std::min(coldest, double(temperature[i]));
    water1 += water[i];
    mass += particle_mass[i];  // constant: drying does not lighten a particle's mechanics mass
    if (peak[i] >= set_temperature) ++set;
  }
  const double weight_loss = (water0 - water1) / mass, set_share = double(set) / double(ps.size()),
               height_ratio = height() / height0;
  std::printf(
      "%s: %zu particles, fastest %.2g m/s, out of the cup by %.2g mm, coldest %.1f degC, hottest moist "
      "%.1f degC, weight loss %.1f%% (%.0f%% of its water), set %.0f%%, height x%.2f\n",
      preset.c_str(), ps.size(), fastest, 1e3 * out_of_cup, coldest, hottest_moist, 100 * weight_loss,
      100 * (1 - water1 / water0), 100 * set_share, height_ratio);
  // Nothing sprays (the issue's SPH cookie that blew apart: 0.5 m/s); a melted chocolate still sloshes at
  // about 1 cm/s of mechanics, an apple rings elastically at up to 3 cm/s, batters and doughs are below 1 cm/s.
  EXPECT_LT(fastest, 0.05);
  EXPECT_LT(out_of_cup, 0.5 * kSpacing);  // in the cup (a particle's centre within half a spacing of its wall)
  // Moist dough stays at the boiling point: on its boiling line, 100.9 degC at
  // 0.3 kg/kg (its water bound a little, the default isotherm; physics/water.hpp).
  EXPECT_LE(hottest_moist, 101.0);
  EXPECT_GT(coldest, 90.0);  // 20 minutes at 180 °C bake the core through (from 20 °C)
  // It dries (baked goods lose about 8-25% of their weight), unless all its water is bound at the
  // oven's temperature (bound water, physics/water.hpp): the chocolate's 1.4% (X 0.014 against the
  // 0.055 the default isotherm binds at 180 degC) stays, as it does in a chocolate heated in an oven.
  if (moisture0 > scene.sph.materials[0].moisture.boiling_moisture(180)) {
    EXPECT_GT(1 - water1 / water0, 0.05);
  } else {
    EXPECT_LT(1 - water1 / water0, 0.01);
  }
  EXPECT_LT(weight_loss, 0.3);
  if (solid) {
    EXPECT_GT(height_ratio, 0.9);  // an elastic solid stands
  }
  if (set_temperature < 1e9) {
    EXPECT_GT(set_share, 0.2);  // the outside has set
  }
}

INSTANTIATE_TEST_SUITE_P(FoodPresets, SphPreset, ::testing::ValuesIn(kFoodPresetsWithSph),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });
