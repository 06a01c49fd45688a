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

json body_scene(const json& shape, double spacing) {
  return {{"solver", {{"type", "sph"}, {"sph", {{"spacing", spacing}}}}},
          {"time", {{"end", 1.0}}},
          {"gravity", {0, 0, 0}},
          {"domain", {{"min", {-0.1, -0.1, -0.1}}, {"max", {0.1, 0.1, 0.1}}}},
          {"materials", {{"dough", {{"density", 1000.0}}}}},
          {"bodies", json::array({{{"name", "b"}, {"material", "dough"}, {"shape", shape}}})}};
}

double surface_area_sum(const sph::SphSolver& solver) {
  double sum = 0;
  for (double a : solver.particles().scalar("surface_area")) sum += a;
  return sum;
}

double area_sum(const json& shape, double spacing) {
  return surface_area_sum(*test_support::make_sph(body_scene(shape, spacing)));
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

// A risen surface: the particles of a sphere spread apart as a dough's do when
// it rises (every distance times f, masses kept, so each holds f³ times its
// volume). The co-area share S is calibrated for the support-to-spacing ratio
// of the sampled lattice (2); with the support kept, the spread particles are
// sampled more coarsely and their areas fall short: the sum is printed, not
// asserted (0.95 / 0.70 / 0.44 of 4π (f r)² at f = 1.1 / 1.25 / 1.44;
// a share tabulated by the local ratio was tried and is ill-conditioned below
// it: docs/physics.md). With adaptive smoothing (Eq 3.53–3.56, reference the
// rest density) each support grows with its particle's spacing, the ratio
// stays 2 and the areas follow the new surface (1.030 / 1.030 / 1.021, the
// sampled sphere 1.019): asserted within 0.03 of the sampled sphere.
TEST(ExchangeArea, FollowsASurfaceWhoseParticlesSpreadApartWithAdaptiveSmoothing) {
  const double s = 0.001, r = 0.02;
  for (const bool adaptive : {false, true}) {
    json doc = body_scene({{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", r}}, s);
    if (adaptive)
      doc["solver"]["sph"]["adaptive_smoothing"] = {
          {"enabled", true}, {"reference", "rest_density"}, {"sensitivity", 1.0 / 3.0}, {"range", {1.0, 1.5}}};
    auto solver = test_support::make_sph(doc);
    const double rest = surface_area_sum(*solver) / (4 * kPi * r * r);
    auto& x = solver->mutable_particles().vector("position");
    const std::vector<Vec3> sampled = x;
    for (const double f : {1.1, 1.25, 1.44}) {
      for (std::size_t i = 0; i < x.size(); ++i) x[i] = f * sampled[i];
      solver->refresh();
      // The supports follow the densities a step later: a few vanishing steps settle them.
      for (int k = 0; k < 4; ++k) {
        solver->step(1e-12);
        solver->refresh();
      }
      const double ratio = surface_area_sum(*solver) / (4 * kPi * r * r * f * f);
      std::printf("%s f %.2f: area sum / 4 pi (f r)^2 = %.4f (sampled %.4f)\n", adaptive ? "adaptive" : "fixed h ", f,
                  ratio, rest);
      RecordProperty(std::string(adaptive ? "adaptive" : "fixed") + "_f" + std::to_string(int(f * 100)),
                     std::to_string(ratio));
      if (adaptive) {
        EXPECT_NEAR(ratio, rest, 0.03) << "spread by " << f;
      }
    }
  }
}
