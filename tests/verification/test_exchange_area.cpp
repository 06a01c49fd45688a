// SPH exchange areas (phase surface): the areas of the surface particles sum to
// the body's true surface area on a lattice-aligned box, a cylinder and a
// sphere (issue: π r² per particle took in 21% too much on the box and 7–9%
// too little on curved faces, and refining did not help).
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

double area_sum(const json& shape, double spacing) {
  json doc = {{"solver", {{"type", "sph"}, {"sph", {{"spacing", spacing}}}}},
              {"time", {{"end", 1.0}}},
              {"gravity", {0, 0, 0}},
              {"domain", {{"min", {-0.1, -0.1, -0.1}}, {"max", {0.1, 0.1, 0.1}}}},
              {"materials", {{"dough", {{"density", 1000.0}}}}},
              {"bodies", json::array({{{"name", "b"}, {"material", "dough"}, {"shape", shape}}})}};
  auto solver = test_support::make_sph(doc);
  double sum = 0;
  for (double a : solver->particles().scalar("surface_area")) sum += a;
  return sum;
}

}  // namespace

// Bodies at least 20 spacings across their smallest dimension (the shipped
// bread roll is 25 across). The kernel rounds a box's edges over about one
// support, so a coarser box falls short by that: 0.961 at 10 spacings across.
TEST(ExchangeArea, SumsToTheTrueAreaOnABoxACylinderAndASphere) {
  for (const double s : {0.002, 0.001}) {
    const double a = 40 * s, b = 20 * s, c = 30 * s;  // box edges
    const double box =
        area_sum({{"type", "box"}, {"min", {-a / 2, -b / 2, -c / 2}}, {"max", {a / 2, b / 2, c / 2}}}, s);
    const double box_true = 2 * (a * b + a * c + b * c);
    EXPECT_NEAR(box / box_true, 1.0, 0.03) << "box, s = " << s;
    const double r = 0.02, h = 0.03;
    const double cyl =
        area_sum({{"type", "cylinder"}, {"center", {0, 0, 0}}, {"axis", {0, 1, 0}}, {"radius", r}, {"height", h}}, s);
    EXPECT_NEAR(cyl / (2 * kPi * r * r + 2 * kPi * r * h), 1.0, 0.03) << "cylinder, s = " << s;
    const double sph = area_sum({{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", r}}, s);
    EXPECT_NEAR(sph / (4 * kPi * r * r), 1.0, 0.03) << "sphere, s = " << s;
    RecordProperty("ratios_s" + std::to_string(int(s * 1e4)), std::to_string(box / box_true) + " " +
                                                                  std::to_string(cyl / (2 * kPi * r * (r + h))) + " " +
                                                                  std::to_string(sph / (4 * kPi * r * r)));
    std::printf("s %.4f: box %.4f cylinder %.4f sphere %.4f\n", s, box / box_true, cyl / (2 * kPi * r * (r + h)),
                sph / (4 * kPi * r * r));
  }
}
