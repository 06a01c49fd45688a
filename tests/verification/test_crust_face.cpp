// The face temperature of surface particles (physics/heat.hpp, CrustFace),
// which the crust browns at, against the analytic surface temperature of a
// plane wall heated by the oven air (Incropera Eq 5.42 at x = L), in both
// solvers: a dry slab (no water, so the half-cell profile) with Bi = 1.
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

constexpr double kHalf = 0.01;  // L, m
constexpr double kWide = 0.04;  // extent in y and z, m
constexpr double kSpacing = 0.002;
constexpr double kAir = 120, kStart = 20, kH = 50, kK = 0.5, kRhoC = 1e6;  // Bi = h L / k = 1
constexpr double kClock = 2000;

json slab(const std::string& solver) {
  const double pad = 0.012;
  json s = {{"type", solver}, {"cfl", 0.4}, {"max_dt", 1e-3}};
  json material = {{"density", 1000.0}, {"specific_heat", kRhoC / 1000.0}, {"conductivity", kK}};
  if (solver == "sph") {
    s["sph"] = {{"spacing", kSpacing}};
  } else {
    s["mpm"] = {{"cell_size", kSpacing}, {"heat", "explicit"}};
    material["youngs_modulus"] = 1e3;
  }
  return {{"solver", s},
          {"time", {{"end", 1.0}}},
          {"gravity", {0, 0, 0}},
          {"environment", {{"air_temperature", kAir}, {"heat_transfer_coefficient", kH}, {"bake_time_scale", kClock}}},
          {"domain", {{"min", {-kHalf - pad, -pad, -pad}}, {"max", {kHalf + pad, kWide + pad, kWide + pad}}}},
          {"materials", {{"crust", material}}},
          {"bodies",
           json::array({{{"name", "slab"},
                         {"material", "crust"},
                         {"temperature", kStart},
                         {"shape", {{"type", "box"}, {"min", {-kHalf, 0, 0}}, {"max", {kHalf, kWide, kWide}}}}}})}};
}

struct FaceReading {
  double face = 0, particle = 0, outer = 0;
  int count = 0;
};

// Mean face and particle temperatures of the outermost particles on the two
// x faces, away from the edges (where the slab is one-dimensional).
FaceReading read_faces(const Solver& s) {
  const auto& x = s.particles().vector("position");
  const auto& face = s.particles().scalar("surface_temperature");
  const auto& theta = s.particles().scalar("temperature");
  double outer = 0;
  for (const Vec3& p : x) outer = std::max(outer, std::abs(p.x()));
  FaceReading r;
  r.outer = outer;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Vec3& p = x[i];
    if (std::abs(p.x()) < outer - 1e-6 || std::abs(p.y() - 0.5 * kWide) > 0.25 * kWide ||
        std::abs(p.z() - 0.5 * kWide) > 0.25 * kWide)
      continue;
    r.face += face[i], r.particle += theta[i], ++r.count;
  }
  r.face /= r.count, r.particle /= r.count;
  return r;
}

}  // namespace

class CrustFaceOfASlab : public ::testing::TestWithParam<std::string> {};

TEST_P(CrustFaceOfASlab, FollowsThePlaneWallSurfaceTemperature) {
  const std::unique_ptr<Solver> owned = GetParam() == "sph"
                                            ? std::unique_ptr<Solver>(test_support::make_sph(slab("sph")))
                                            : std::unique_ptr<Solver>(test_support::make_mpm(slab("mpm")));
  Solver& s = *owned;
  const double alpha = kK / kRhoC, biot = kH * kHalf / kK;
  for (double fo : {0.05, 0.1, 0.3}) {
    test_support::advance_to(s, fo * kHalf * kHalf / alpha / kClock);
    const FaceReading r = read_faces(s);
    ASSERT_GT(r.count, 10);
    const auto series = [&](double x) {
      return kAir + (kStart - kAir) * test_support::plane_wall(biot, fo, x / kHalf);
    };
    const double rise = kAir - kStart;
    const double face_error = (r.face - series(kHalf)) / rise;
    // The outermost particles sit inside the face: SPH's half a spacing, MPM's points a
    // quarter of a cell (two to a cell across).
    const double depth = kHalf - r.outer;
    const double particle_error = (r.particle - series(kHalf - depth)) / rise;
    std::printf(
        "%s Fo %.2f: series at the face %.2f degC, face %.2f (%+.3f of the rise), particle %.2f at %.2f mm against "
        "%.2f (%+.3f)\n",
        GetParam().c_str(), fo, series(kHalf), r.face, face_error, r.particle, 1e3 * depth, series(kHalf - depth),
        particle_error);
    // SPH: with the lumped exchange h (θ_out − θ) at the particle (before the face profile) the
    // particles ran 0.043 of the rise hot at Fo 0.3 and their faces 0.064 cold at Fo 0.05.
    // MPM (measured −0.042 / −0.027 / +0.005 at the face, −0.046 / −0.030 / +0.005 at the
    // points): its points read the temperature of the grid's nodes, a cell apart, and at Fo
    // 0.05 heat has reached about a cell (√(α t) = 2.2 mm), so the outer points lag; before
    // they took the face's heat through their depth they stood for their faces, −0.074 /
    // −0.048 / +0.003 of the rise below the face's series.
    const double limit = GetParam() == "sph" || fo > 0.2 ? 0.03 : 0.05;
    EXPECT_LT(std::abs(face_error), limit) << "Fo " << fo;
    EXPECT_LT(std::abs(particle_error), limit) << "Fo " << fo;
    RecordProperty("face_error_fo_" + std::to_string(int(fo * 100)), std::to_string(face_error));
  }
}

INSTANTIATE_TEST_SUITE_P(BothSolvers, CrustFaceOfASlab, ::testing::Values("sph", "mpm"));
