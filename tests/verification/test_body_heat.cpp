// Heat taken in by whole bodies in oven air, against the exact solutions of
// finite bodies with constant properties: a cube is the product of three
// plane walls, a finite cylinder of a plane wall (its height) and an infinite
// cylinder (its radius) (Incropera §5.8, Eq 5.64–5.65; the series Eq 5.42 and
// 5.49–5.50). The body is the Zhang loaf's dough without water (k 0.196 W/(m K),
// ρ 301 kg/m³, c_p 2250 J/(kg K)) in 190 °C air with h = 10 W/(m² K) for 15
// minutes of bake: the loaf of docs/validation.md (R 36 mm, H 35 mm: Bi 1.84
// radially and 0.89 axially) and a 40 mm cube (Bi 1.02). The slab tests
// (test_crust_face.cpp, test_tray_heat.cpp) check faces; these check the
// curved faces, edges and rims a bake has, which every exchange area must get
// right for the heat in (and so the core temperature) to be right.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "helpers.hpp"
#include "mpm/solver.hpp"

using namespace bakesim;
using nlohmann::json;

// A named namespace: the verification tests build as one unity file.
namespace body_heat {

constexpr double kK = 0.196, kRho = 301, kC = 2250, kH = 10, kAir = 190, kStart = 25;
constexpr double kClock = 3000;
constexpr double kRadius = 0.036, kHeight = 0.035, kCube = 0.04;

json body_scene(const std::string& solver, const std::string& shape, double resolution, double domain_shift = 0) {
  json s = {{"type", solver}, {"cfl", 0.4}, {"max_dt", 1e-3}};
  json material = {{"density", kRho}, {"specific_heat", kC}, {"conductivity", kK}};
  if (solver == "sph") {
    s["sph"] = {{"spacing", resolution}, {"smoothing_ratio", 2.0}, {"speed_of_sound", 5.0}};
    material["viscosity"] = 50.0;
  } else {
    s["mpm"] = {{"cell_size", resolution}, {"particles_per_cell", 8}, {"heat", "explicit"}};
    material["youngs_modulus"] = 12000.0;
    material["poisson_ratio"] = 0.15;
  }
  const json geometry = shape == "cylinder" ? json{{"type", "cylinder"},
                                                   {"center", {0, 0, 0}},
                                                   {"axis", {0, 1, 0}},
                                                   {"radius", kRadius},
                                                   {"height", kHeight}}
                                            : json{{"type", "box"},
                                                   {"min", {-kCube / 2, -kCube / 2, -kCube / 2}},
                                                   {"max", {kCube / 2, kCube / 2, kCube / 2}}};
  return {{"solver", s},
          {"time", {{"end", 1.0}}},
          {"gravity", {0, 0, 0}},
          {"environment", {{"air_temperature", kAir}, {"heat_transfer_coefficient", kH}, {"bake_time_scale", kClock}}},
          {"domain",
           {{"min", {-0.05 - domain_shift, -0.05 - domain_shift, -0.05 - domain_shift}}, {"max", {0.05, 0.05, 0.05}}}},
          {"materials", {{"dough", material}}},
          {"bodies",
           json::array({{{"name", "body"}, {"material", "dough"}, {"temperature", kStart}, {"shape", geometry}}})}};
}

// (T − T∞)/(T0 − T∞) of the exact solution at x (the body centred at the origin, the cylinder's axis along y),
// or its mean over the body.
double exact(const std::string& shape, double bake_seconds, const Vec3& x, bool mean = false) {
  const double alpha = kK / (kRho * kC);
  if (shape == "cylinder") {
    const double half = kHeight / 2, r = std::hypot(x.x(), x.z());
    const double fo_axial = alpha * bake_seconds / (half * half),
                 fo_radial = alpha * bake_seconds / (kRadius * kRadius);
    const double axial = mean ? test_support::plane_wall_mean(kH * half / kK, fo_axial)
                              : test_support::plane_wall(kH * half / kK, fo_axial, x.y() / half);
    return axial * test_support::infinite_cylinder(kH * kRadius / kK, fo_radial, r / kRadius, mean);
  }
  const double half = kCube / 2, biot = kH * half / kK, fo = alpha * bake_seconds / (half * half);
  double product = 1;
  for (int k = 0; k < 3; ++k)
    product *= mean ? test_support::plane_wall_mean(biot, fo) : test_support::plane_wall(biot, fo, x[k] / half);
  return product;
}

struct Reading {
  double minutes, heat_ratio, centre_error;
};

// Bakes the body to each time and compares the heat in per mass (the mean rise, one c_p) and the
// particles within one spacing of the centre with the exact body's.
std::vector<Reading> bake(const std::string& solver, const std::string& shape, double resolution,
                          const std::vector<double>& minutes, double domain_shift = 0) {
  const json scene = body_scene(solver, shape, resolution, domain_shift);
  const std::unique_ptr<Solver> owned = solver == "sph" ? std::unique_ptr<Solver>(test_support::make_sph(scene))
                                                        : std::unique_ptr<Solver>(test_support::make_mpm(scene));
  Solver& s = *owned;
  const double rise = kAir - kStart;
  std::vector<Reading> out;
  for (double at : minutes) {
    const double bake_seconds = 60 * at;
    test_support::advance_to(s, bake_seconds / kClock);
    const auto& x = s.particles().vector("position");
    const auto& m = s.particles().scalar("mass");
    const auto& theta = s.particles().scalar("temperature");
    double mass = 0, heat = 0, centre = 0, centre_exact = 0, centre_mass = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      mass += m[i], heat += m[i] * (theta[i] - kStart);
      if (x[i].norm() < resolution) {
        centre += m[i] * theta[i], centre_mass += m[i];
        centre_exact += m[i] * (kAir - rise * exact(shape, bake_seconds, x[i]));
      }
    }
    const double heat_ratio = (heat / mass) / (rise * (1 - exact(shape, bake_seconds, Vec3::Zero(), true)));
    const double centre_error = centre_mass > 0 ? (centre - centre_exact) / centre_mass / rise : 1e9;
    std::printf(
        "%s %s at %.1f mm (domain shifted %.1f mm), %.0f min of bake: heat in %.4f of the exact body's, "
        "centre %+.4f of the rise\n",
        solver.c_str(), shape.c_str(), 1e3 * resolution, 1e3 * domain_shift, at, heat_ratio, centre_error);
    out.push_back({at, heat_ratio, centre_error});
  }
  return out;
}

}  // namespace body_heat

namespace bh = body_heat;

// solver, shape, spacing or cell size (m)
class BodyInOvenAir : public ::testing::TestWithParam<std::tuple<std::string, std::string, double>> {};

TEST_P(BodyInOvenAir, TakesInTheExactSolutionsHeat) {
  const auto [solver, shape, resolution] = GetParam();
  for (const bh::Reading& r : bh::bake(solver, shape, resolution, {3.0, 9.0, 15.0})) {
    const std::string at = std::to_string(int(r.minutes)) + "min";
    RecordProperty("heat_ratio_" + at, std::to_string(r.heat_ratio));
    RecordProperty("centre_error_" + at, std::to_string(r.centre_error));
    // Measured (docs/validation.md, "Heat into whole bodies"), heat in at 3 / 9 / 15 min and the
    // centre at 15: SPH cube (2 mm) −0.9 / −0.1 / +0.05%, +0.003 of the rise; SPH cylinder
    // (3 mm) +2.8 / +3.2 / +2.8%, +0.034 (2 mm: +1.7–1.9%, +0.018); MPM cube (4 mm) −8.4 /
    // −5.5 / −3.9%, −0.034; MPM cylinder (4 mm) −3.4 / −2.0 / −1.4%, −0.003. MPM's node
    // areas round the edges and rims off (the cube's sum to 0.895 of its faces at 4 mm) and
    // its points take their share in series with their depth below the face.
    const bool sph = solver == "sph";
    const double heat_limit = sph ? 0.04 : (r.minutes < 5 ? 0.09 : 0.06);
    EXPECT_LT(std::abs(r.heat_ratio - 1), heat_limit) << r.minutes << " min";
    EXPECT_LT(std::abs(r.centre_error), sph ? 0.045 : 0.04) << r.minutes << " min";
  }
}

INSTANTIATE_TEST_SUITE_P(BothSolvers, BodyInOvenAir,
                         ::testing::Values(std::make_tuple("sph", "cube", 0.002), std::make_tuple("mpm", "cube", 0.004),
                                           std::make_tuple("sph", "cylinder", 0.003),
                                           std::make_tuple("mpm", "cylinder", 0.004)),
                         [](const auto& info) {
                           const double mm = 1e3 * std::get<2>(info.param);
                           return std::get<0>(info.param) + "_" + std::get<1>(info.param) + "_" +
                                  std::to_string(int(mm * 10)) + "tenth_mm";
                         });

// The same cube with its faces half a cell off the grid's node planes and on them: the heat it
// takes in is the same within 2.5% after 3 minutes (measured 0.916 and 0.934 of the exact
// body's). Before the node areas gave a neighbour without material's half of each difference to
// the node that has it, the face off the node planes lost that neighbour's share: 0.852 against
// 0.927 (a 40 mm cube in 4 mm cells, docs/validation.md).
TEST(MpmBodyInOvenAir, TakesTheSameHeatWhereverTheGridCutsItsFaces) {
  const double off = bh::bake("mpm", "cube", 0.004, {3.0})[0].heat_ratio;
  const double on = bh::bake("mpm", "cube", 0.004, {3.0}, 0.002)[0].heat_ratio;
  RecordProperty("faces_off_node_planes", std::to_string(off));
  RecordProperty("faces_on_node_planes", std::to_string(on));
  EXPECT_NEAR(off, on, 0.025);
}
