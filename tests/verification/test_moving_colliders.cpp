// SPH keyframed colliders (the contact law and motion shared with MPM): a
// floor that rises at constant speed lifts the fluid resting on it with that
// speed, and a sticky paddle carries the particles it holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

json lift_scene(bool moving) {
  json d = json::parse(R"({
    "solver": {"type": "sph", "sph": {"spacing": 0.01, "speed_of_sound": 20}},
    "time": {"end": 0.5},
    "domain": {"min": [-0.1, -0.05, -0.1], "max": [0.1, 0.3, 0.1]},
    "materials": {"water": {"density": 1000, "viscosity": 0.5}},
    "bodies": [{"name": "block", "material": "water",
                "shape": {"type": "box", "min": [-0.04, 0.005, -0.04], "max": [0.04, 0.065, 0.04]}}],
    "colliders": [{"name": "floor", "shape": {"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}}]
  })");
  // The floor rises 4 cm in 0.4 s (0.1 m/s) after a short rest.
  if (moving)
    d["colliders"][0]["motion"] = {{"keyframes", {{{"time", 0.1}}, {{"time", 0.5}, {"translation", {0, 0.04, 0}}}}}};
  return d;
}

Real mean_height(const Solver& s) {
  const auto& x = s.particles().vector("position");
  Real sum = 0;
  for (const Vec3& p : x) sum += p.y();
  return sum / Real(x.size());
}

}  // namespace

TEST(SphMovingColliders, ARisingFloorLiftsTheFluidAtItsSpeed) {
  auto still = test_support::make_sph(lift_scene(false));
  auto lift = test_support::make_sph(lift_scene(true));
  test_support::advance_to(*still, 0.1);
  test_support::advance_to(*lift, 0.1);
  const Real rest_still = mean_height(*still), rest_lift = mean_height(*lift);
  EXPECT_NEAR(rest_still, rest_lift, 1e-9);  // nothing moves before the first keyframe
  test_support::advance_to(*still, 0.5);
  test_support::advance_to(*lift, 0.5);
  // The floor rose 4 cm by t = 0.5 s; the fluid on it rose with it (the
  // static floor's fluid settles by a fraction of a millimetre), and no
  // particle is below the floor's surface.
  const Real rise = (mean_height(*lift) - rest_lift) - (mean_height(*still) - rest_still);
  std::printf("rising floor: the fluid rose %.4f m with a floor that rose 0.04 m\n", rise);
  EXPECT_NEAR(rise, 0.04, 0.004);
  for (const Vec3& p : lift->particles().vector("position")) EXPECT_GT(p.y(), 0.04);
}

TEST(SphMovingColliders, AStickyPaddleCarriesWhatTouchesIt) {
  json d = lift_scene(false);
  d["gravity"] = {0, 0, 0};
  d["bodies"][0]["shape"] = {{"type", "box"}, {"min", {-0.04, -0.001, -0.04}}, {"max", {0.04, 0.059, 0.04}}};
  d["colliders"] = json::parse(R"([{"name": "paddle", "contact": "sticky",
    "shape": {"type": "box", "min": [-0.06, -0.04, -0.06], "max": [0.06, 0.0, 0.06]},
    "motion": {"keyframes": [{"time": 0}, {"time": 1, "translation": [0.2, 0, 0]}]}}])");
  d["domain"] = {{"min", {-0.1, -0.05, -0.1}}, {"max", {0.4, 0.3, 0.1}}};
  auto s = test_support::make_sph(d);
  const auto& x0 = s->particles().vector("position");
  std::vector<std::int32_t> bottom;
  Real start = 0;
  for (std::size_t i = 0; i < x0.size(); ++i)
    if (x0[i].y() < 0.005) bottom.push_back(s->particles().integer("id")[i]), start += x0[i].x();
  ASSERT_GT(bottom.size(), 20u);
  start /= Real(bottom.size());
  test_support::advance_to(*s, 0.2);
  // The bottom layer, held by the paddle, moved with it: 4 cm along x.
  const auto& x = s->particles().vector("position");
  const auto& id = s->particles().integer("id");
  Real end = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (std::find(bottom.begin(), bottom.end(), id[i]) != bottom.end()) end += x[i].x();
  end /= Real(bottom.size());
  EXPECT_NEAR(end - start, 0.04, 0.004);
}
