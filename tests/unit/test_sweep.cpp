// Sweep grids (io/sweep.hpp) and the numbers a run's results are read into (render/run_results.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/errors.hpp"
#include "io/sweep.hpp"
#include "render/run_results.hpp"

using namespace bakesim;

TEST(Sweep, ValuesSplitAtTopLevelCommasOnly) {
  EXPECT_EQ(parse_sweep_axis("environment.air_temperature=150,180,210").values,
            (std::vector<std::string>{"150", "180", "210"}));
  const SweepAxis centres = parse_sweep_axis("bodies[0].shape.center=[0,0.1,0],[0,0.2,0]");
  EXPECT_EQ(centres.path, "bodies[0].shape.center");
  EXPECT_EQ(centres.values, (std::vector<std::string>{"[0,0.1,0]", "[0,0.2,0]"}));
  EXPECT_EQ(parse_sweep_axis("environment.air_temperature=[[0,150],[600,200]],180").values,
            (std::vector<std::string>{"[[0,150],[600,200]]", "180"}));
  EXPECT_EQ(parse_sweep_axis(R"(name="a,b","c\",d")").values, (std::vector<std::string>{R"("a,b")", R"("c\",d")"}));
  EXPECT_THROW(parse_sweep_axis("air_temperature"), InputError);
  EXPECT_THROW(parse_sweep_axis("=1,2"), InputError);
  EXPECT_THROW(parse_sweep_axis("time.end=1,,2"), InputError);
  EXPECT_THROW(parse_sweep_axis("time.end="), InputError);
}

TEST(Sweep, TheGridIsEveryCombinationFirstAxisSlowest) {
  const std::vector<SweepAxis> axes{parse_sweep_axis("environment.air_temperature=150,180"),
                                    parse_sweep_axis("time.fps=10"),
                                    parse_sweep_axis("materials.dough.leavening.rate=1e-6,2e-6,4e-6")};
  const auto points = sweep_points(axes);
  ASSERT_EQ(points.size(), 6u);
  EXPECT_EQ(points[0].label, "air_temperature=150,rate=1e-6");
  EXPECT_EQ(points[2].label, "air_temperature=150,rate=4e-6");
  EXPECT_EQ(points[3].label, "air_temperature=180,rate=1e-6");
  EXPECT_EQ(points[5].sets, (std::vector<std::string>{"environment.air_temperature=180", "time.fps=10",
                                                      "materials.dough.leavening.rate=4e-6"}));
  EXPECT_EQ(points[5].values, (std::vector<std::string>{"180", "10", "4e-6"}));
  EXPECT_EQ(points[0].directory, "1-air_temperature=150_rate=1e-6");
  // Two axes with one last key are told apart by their paths; unsafe characters leave the directory name.
  const auto same = sweep_points(
      {parse_sweep_axis("bodies[0].temperature=5,10"), parse_sweep_axis("colliders[0].temperature=\"oven\",200")});
  EXPECT_EQ(same[1].label, "bodies[0].temperature=5,colliders[0].temperature=200");
  EXPECT_EQ(same[0].directory, "1-bodies_0_.temperature=5_colliders_0_.temperature=_oven_");
  EXPECT_THROW(
      sweep_points({parse_sweep_axis("a=1,2,3,4,5,6,7,8,9,10"), parse_sweep_axis("b=1,2,3,4,5,6,7,8,9,10")}, 50),
      InputError);
}

TEST(RunResults, FirstCrossingInterpolatesBetweenRows) {
  const std::vector<double> t{0, 60, 120, 180};
  EXPECT_DOUBLE_EQ(render::first_crossing(t, {20, 80, 100, 120}, 95), 60 + 60 * 15.0 / 20.0);
  EXPECT_DOUBLE_EQ(render::first_crossing(t, {96, 97, 98, 99}, 95), 0);
  EXPECT_TRUE(std::isnan(render::first_crossing(t, {20, 40, 60, 94.9}, 95)));
  // A core that passes the line, cools and passes it again: the first time counts.
  EXPECT_DOUBLE_EQ(render::first_crossing(t, {90, 100, 90, 100}, 95), 30);
}

TEST(RunResults, DoneIsTheSeaLevelCoreOrFiveKelvinBelowWhereWaterBoils) {
  EXPECT_DOUBLE_EQ(render::done_core_degc(100.0), 95.0);
  EXPECT_DOUBLE_EQ(render::done_core_degc(93.4), 88.4);   // 2,000 m up: the moist crumb stops at 93.4 °C
  EXPECT_DOUBLE_EQ(render::done_core_degc(105.0), 95.0);  // a pressure above 1 atm does not raise it
  // A run directory's level comes from its scene.json; without one, sea level.
  const auto dir = std::filesystem::temp_directory_path() / "bakesim-done-level";
  std::filesystem::create_directories(dir);
  EXPECT_DOUBLE_EQ(render::done_core_degc(dir), 95.0);
  { std::ofstream(dir / "scene.json") << R"({"environment": {"altitude": 2000}})"; }
  EXPECT_NEAR(render::done_core_degc(dir), 88.4, 0.1);
  { std::ofstream(dir / "scene.json") << R"({"environment": {"air_pressure": 84609, "altitude": null}})"; }
  EXPECT_NEAR(render::done_core_degc(dir), 90.0, 0.1);
  std::filesystem::remove_all(dir);
}
