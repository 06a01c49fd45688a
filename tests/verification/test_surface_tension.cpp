// Colour-field surface tension (Eq 3.28–3.30): in zero gravity a cube of
// liquid rounds off, its corners pulled in towards a sphere, while the same
// cube without surface tension keeps its corners.
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

// Largest distance of a particle from the centroid, relative to the cube's half-diagonal.
double corner_reach(double sigma) {
  const json doc = {
      {"solver", {{"type", "sph"}, {"sph", {{"spacing", 0.005}, {"speed_of_sound", 5.0}}}}},
      {"time", {{"end", 1.0}}},
      {"gravity", {0, 0, 0}},
      {"domain", {{"min", {-0.1, -0.1, -0.1}}, {"max", {0.1, 0.1, 0.1}}}},
      {"materials",
       {{"liquid", {{"density", 1000.0}, {"viscosity", 0.05}, {"surface_tension", sigma}, {"xsph", 0.1}}}}},
      {"bodies",
       {{{"name", "cube"},
         {"material", "liquid"},
         {"shape", {{"type", "box"}, {"min", {-0.025, -0.025, -0.025}}, {"max", {0.025, 0.025, 0.025}}}}}}}};
  auto solver = test_support::make_sph(doc);
  test_support::advance_to(*solver, 0.15);
  const auto& x = solver->particles().vector("position");
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : x) c += p;
  c /= double(x.size());
  double reach = 0;
  for (const Vec3& p : x) reach = std::max(reach, (p - c).norm());
  return reach / (std::sqrt(3.0) * 0.0225);  // outermost lattice points sit at ±0.0225
}

}  // namespace

TEST(SurfaceTension, CubeRoundsOffInZeroGravity) {
  const double without = corner_reach(0.0);
  const double with = corner_reach(0.5);
  EXPECT_GT(without, 0.97) << "without surface tension the corners stay";
  EXPECT_LT(with, without - 0.05) << "with surface tension the corners pull in: " << with << " vs " << without;
}
