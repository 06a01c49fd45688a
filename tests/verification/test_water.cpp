// Water, vapour and latent heat (physics/water.hpp) in the solvers:
//  - the two-phase Stefan problem: a moist slab whose face is held above the
//    boiling point, with vapour and liquid transport off, against the Neumann
//    similarity solution (front X = 2λ√(αt), erf profiles on both sides);
//  - a moist block baked in each solver: the water budget (liquid + gone)
//    and the energy budget (sensible + latent gone − heat in) close to
//    round-off, moist dough never passes the boiling point, the crust dries
//    and heats past it.
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"
#include "sim/bake_stats.hpp"
#include "mpm/solver.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

// Neumann's λ for melting/evaporation with equal properties on both sides:
//   St₁ / (e^{λ²} erf λ) − St₂ / (e^{λ²} erfc λ) = λ √π,
// St₁ = c (T_s − T_b) / L, St₂ = c (T_b − T_i) / L.
double neumann_lambda(double st1, double st2) {
  auto f = [&](double l) {
    return st1 / (std::exp(l * l) * std::erf(l)) - st2 / (std::exp(l * l) * std::erfc(l)) - l * std::sqrt(kPi);
  };
  double lo = 1e-6, hi = 3;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

constexpr double kS = 0.001, kLength = 0.04, kSide = 0.012;
constexpr double kRho = 500, kC = 2500, kK = 0.5, kX0 = 0.5;
constexpr double kTi = 20, kTb = 100, kTs = 200, kScale = 1000;

json stefan_scene() {
  return {
      {"solver", {{"type", "sph"}, {"sph", {{"spacing", kS}, {"speed_of_sound", 2.0}}}}},
      {"time", {{"end", 1.0}}},
      {"gravity", {0, 0, 0}},
      // Nothing leaves through the free faces: the only way out is boiling at the hot face.
      {"environment",
       {{"heat_transfer_coefficient", 0.0}, {"mass_transfer_coefficient", 0.0}, {"bake_time_scale", kScale}}},
      {"domain", {{"min", {-0.01, 0, 0}}, {"max", {kLength, kSide, kSide}}}},
      {"materials",
       {{"dough",
         {{"density", kRho},
          {"specific_heat", kC},
          {"conductivity", kK},
          {"viscosity", 1.0},
          // Neumann's sharp front boils all the water at θ_b: an isotherm that binds none
          // (a = e⁻²⁰: a_w above 0.99 down to X = 1e-7 kg/kg).
          {"moisture",
           {{"content", kX0},
            {"vapour_diffusivity", 0.0},
            {"liquid_diffusivity", 0.0},
            {"sorption", {{"oswin_a_offset", -20.0}}}}}}},
        {"hot", {{"density", kRho}, {"specific_heat", kC}, {"conductivity", kK}}}}},
      {"bodies", json::array({{{"name", "slab"},
                               {"material", "dough"},
                               {"temperature", kTi},
                               {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {kLength, kSide, kSide}}}}},
                              {{"name", "face"},
                               {"material", "hot"},
                               {"temperature", kTs},
                               {"hold_temperature", true},
                               {"shape", {{"type", "box"}, {"min", {-0.01, 0, 0}}, {"max", {0, kSide, kSide}}}}}})}};
}

}  // namespace

TEST(WaterStefan, EvaporationFrontAndTemperaturesFollowTheNeumannSolution) {
  auto solver = test_support::make_sph(stefan_scene());
  const double alpha = kK / (kRho * kC);
  const double water_per_volume = kRho * kX0 / (1 + kX0);
  const double latent_kelvin = 2.257e6 * water_per_volume / (kRho * kC);  // L_v / (ρ c)
  const double lambda = neumann_lambda((kTs - kTb) / latent_kelvin, (kTb - kTi) / latent_kelvin);
  // The held layer's first centres are the face (as in HeatConduction.SlabCentre...).
  const double face = -0.5 * kS;
  const auto& ps = solver->particles();
  double water0 = 0;
  for (double w : ps.scalar("water_mass")) water0 += w;
  for (const double bake_seconds : {200.0, 400.0, 800.0}) {
    test_support::advance_to(*solver, bake_seconds / kScale);
    const double t = bake_seconds;
    const double front = 2 * lambda * std::sqrt(alpha * t);
    // The front from the water gone: the dry layer held W/V of it per volume.
    double water = 0;
    for (double w : ps.scalar("water_mass")) water += w;
    const double simulated_front = (water0 - water) / (water_per_volume * kSide * kSide) + (0 - face);
    EXPECT_NEAR(simulated_front, front, 0.05 * front) << "t = " << t << " s";
    // Temperatures on the centre line, half-way through the dry layer and 4 mm into the wet side.
    auto mean_temperature_at = [&](double x_from_face) {
      const auto& x = ps.vector("position");
      const auto& temp = ps.scalar("temperature");
      double sum = 0;
      int n = 0;
      for (std::size_t i = 0; i < x.size(); ++i)
        if (std::abs(x[i].x() - face - x_from_face) < 0.6 * kS && std::abs(x[i].y() - 0.5 * kSide) < 2 * kS &&
            std::abs(x[i].z() - 0.5 * kSide) < 2 * kS)
          sum += temp[i], ++n;
      return sum / n;
    };
    const double eta_scale = 2 * std::sqrt(alpha * t);
    const double x_dry = 0.5 * front, x_wet = front + 0.004;
    // The profiles at the sampled particles' own distances (the lattice sits at half spacings).
    const double dry_at = std::round((x_dry + face - 0.5 * kS) / kS) * kS + 0.5 * kS - face;
    const double wet_at = std::round((x_wet + face - 0.5 * kS) / kS) * kS + 0.5 * kS - face;
    const double t_dry = kTs - (kTs - kTb) * std::erf(dry_at / eta_scale) / std::erf(lambda);
    const double t_wet = kTi + (kTb - kTi) * std::erfc(wet_at / eta_scale) / std::erfc(lambda);
    EXPECT_NEAR(mean_temperature_at(dry_at), t_dry, 4.0) << "dry side, t = " << t;
    EXPECT_NEAR(mean_temperature_at(wet_at), t_wet, 4.0) << "wet side, t = " << t;
    RecordProperty("front_mm_at_" + std::to_string(int(t)),
                   std::to_string(simulated_front * 1e3) + " vs " + std::to_string(front * 1e3));
  }
}

namespace {

json block_scene(const std::string& solver) {
  json s = solver == "sph" ? json{{"type", "sph"}, {"sph", {{"spacing", 0.002}, {"speed_of_sound", 3.0}}}}
                           : json{{"type", "mpm"}, {"mpm", {{"cell_size", 0.003}, {"heat", "explicit"}}}};
  json material = {{"density", 400.0},
                   {"specific_heat", 2500.0},
                   {"conductivity", 0.3},
                   {"moisture", {{"content", 0.6}, {"gas_fraction", 0.6}, {"liquid_diffusivity", 1e-9}}}};
  if (solver == "sph")
    material["viscosity"] = 20.0;
  else
    material["youngs_modulus"] = 2e4;
  return {
      {"solver", s},
      {"time", {{"end", 1.0}}},
      {"gravity", {0, 0, 0}},
      {"environment", {{"air_temperature", 220.0}, {"heat_transfer_coefficient", 40.0}, {"bake_time_scale", 2000.0}}},
      {"domain", {{"min", {-0.04, -0.04, -0.04}}, {"max", {0.04, 0.04, 0.04}}}},
      {"materials", {{"dough", material}}},
      {"bodies",
       json::array(
           {{{"name", "block"},
             {"material", "dough"},
             {"temperature", 25.0},
             {"shape", {{"type", "box"}, {"min", {-0.015, -0.015, -0.015}}, {"max", {0.015, 0.015, 0.015}}}}}})}};
}

struct Totals {
  double water = 0, sensible = 0;
};
Totals totals(const Solver& s, double c) {
  Totals t;
  const auto& ps = s.particles();
  const auto& m = ps.scalar("mass");
  const auto& w = ps.scalar("water_mass");
  const auto& temp = ps.scalar("temperature");
  for (std::size_t i = 0; i < m.size(); ++i) t.water += w[i], t.sensible += m[i] * c * temp[i];
  return t;
}
double quantity(const Solver& s, const std::string& name) {
  for (const auto& [n, v] : s.frame_quantities())
    if (n == name) return v;
  return std::nan("");
}

}  // namespace

class WaterBudgets : public ::testing::TestWithParam<std::string> {};

TEST_P(WaterBudgets, WaterAndEnergyCloseMoistDoughStaysAtBoilingAndTheCrustDries) {
  json doc = block_scene(GetParam());
  std::unique_ptr<Solver> solver;
  if (GetParam() == "sph")
    solver = test_support::make_sph(doc);
  else
    solver = test_support::make_mpm(doc);
  const double c = 2500;
  const Totals start = totals(*solver, c);
  const ParticleSet start_particles = solver->particles();
  double hottest_moist = -1e9, past_line = -1e9;
  const PoreWater isotherm;  // the block's: the default isotherm and boiling point
  const auto watch = [&] {
    const auto& ps = solver->particles();
    const auto& x = ps.scalar("moisture");
    const auto& t = ps.scalar("temperature");
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (x[i] > 0.3) hottest_moist = std::max(hottest_moist, t[i]);
      // Dough holding water never passes its boiling line (bound water, physics/water.hpp).
      if (x[i] > 0 && t[i] > 100) past_line = std::max(past_line, t[i] - isotherm.boiling_temperature(x[i]));
    }
  };
  // After 3 bake minutes the per-body stats see a crust a fraction of the block thick, drier
  // than the crumb.
  test_support::advance_to(*solver, 0.09, watch);
  const BodyBake early = BakeStatistics(start_particles, 1).compute(solver->particles())[0];
  EXPECT_GT(early.crust_thickness, 0.0);
  EXPECT_LT(early.crust_thickness, 0.015);  // half the block
  EXPECT_LT(early.crust_moisture, early.crumb_moisture);
  std::printf("%s after 3 min: crust %.2f mm thick, crust moisture %.3f, crumb %.3f\n", GetParam().c_str(),
              1e3 * early.crust_thickness, early.crust_moisture, early.crumb_moisture);
  test_support::advance_to(*solver, 0.45, watch);  // 15 bake minutes
  const Totals end = totals(*solver, c);
  const double gone = quantity(*solver, "water_evaporated");
  EXPECT_GT(gone, 0.05 * start.water);  // it really dried
  EXPECT_NEAR(end.water + gone, start.water, 1e-9 * start.water);
  const double heat_in = quantity(*solver, "heat_in"), latent = quantity(*solver, "latent_heat_out");
  // What left took h_fg per kg: exactly in SPH; in MPM vapour that reaches a grid
  // node whose particles hold no water cannot condense there and is booked as
  // gone without its heat (0.02% of the water here; docs/physics.md).
  EXPECT_NEAR(latent, 2.257e6 * gone, (GetParam() == "sph" ? 1e-9 : 1e-3) * latent);
  EXPECT_NEAR(end.sensible + latent - heat_in, start.sensible, 1e-8 * start.sensible);
  EXPECT_LE(hottest_moist, 100.5);
  EXPECT_LE(past_line, 0.01);
  // (Here the moist dough never passes 100 degC, its vapour carrying the heat off: only the dried crust, well
  // below its line, is above it.)
  std::printf("%s: dough holding water above 100 degC, nearest its boiling line: %+.2g K\n", GetParam().c_str(),
              past_line);
  // The crust: dried and past the boiling point somewhere.
  const auto& ps = solver->particles();
  double driest = 1e9, hottest = -1e9;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    driest = std::min(driest, ps.scalar("moisture")[i]);
    hottest = std::max(hottest, ps.scalar("temperature")[i]);
  }
  EXPECT_LT(driest, 0.05);
  EXPECT_GT(hottest, 110.0);
  // The dried crust past the boiling point has browned (Browning.* for the moist crumb).
  double palest_crust = 1;
  for (std::size_t i = 0; i < ps.size(); ++i)
    if (ps.scalar("temperature")[i] > 110) palest_crust = std::min(palest_crust, ps.scalar("browning")[i]);
  EXPECT_GT(palest_crust, 0.0);
  RecordProperty("water_gone_percent", std::to_string(100 * gone / start.water));
}

INSTANTIATE_TEST_SUITE_P(BothSolvers, WaterBudgets, ::testing::Values("sph", "mpm"));

// High up, water boils lower: the same block baked at 2,000 m (79.5 kPa in the standard
// atmosphere, where the steam tables put the boiling point at 93.3 degC) stops its moist dough
// there instead of at 100 degC, and the crust statistics count the dough dried at that point.
class WaterAtAltitude : public ::testing::TestWithParam<std::string> {};

TEST_P(WaterAtAltitude, MoistDoughStopsAtTheBoilingPointOfTheAirsPressure) {
  json doc = block_scene(GetParam());
  doc["environment"]["altitude"] = 2000.0;
  doc["environment"]["mass_transfer_coefficient"] = 0.0;  // water leaves at the boiling front only
  const Scene scene = parse_scene(doc.dump(), "scene.json", ".");
  const double boiling = scene.oven.boiling_point();
  EXPECT_NEAR(boiling, 93.4, 0.1);
  const PoreWater& water = GetParam() == "sph" ? scene.sph.materials[0].moisture : scene.mpm.materials[0].moisture;
  EXPECT_DOUBLE_EQ(water.boiling_point, boiling);
  std::unique_ptr<Solver> solver = make_solver(scene);
  const ParticleSet start_particles = solver->particles();
  double hottest_moist = -1e9, past_line = -1e9;
  test_support::advance_to(*solver, 0.15, [&] {  // 5 bake minutes
    const auto& ps = solver->particles();
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const double x = ps.scalar("moisture")[i], t = ps.scalar("temperature")[i];
      // Moist enough that its water is free (a_w > 0.99 with the default isotherm).
      if (x > 0.45) hottest_moist = std::max(hottest_moist, t);
      if (x > 0) past_line = std::max(past_line, t - water.boiling_temperature(x));
    }
  });
  const BodyBake bake = BakeStatistics(start_particles, 1, boiling).compute(solver->particles())[0];
  std::printf(
      "%s at 2,000 m: free-water dough at most %.2f degC (boils at %.2f), %+.2g K from its line at most, "
      "crust %.2f mm\n",
      GetParam().c_str(), hottest_moist, boiling, past_line, 1e3 * bake.crust_thickness);
  RecordProperty("hottest_moist", std::to_string(hottest_moist));
  EXPECT_LE(hottest_moist, boiling + 0.3);  // not 100 degC
  EXPECT_GE(hottest_moist, boiling - 0.3);  // and the outer dough has reached it
  EXPECT_LE(past_line, 0.01);               // bound water on the boiling line of this pressure
  EXPECT_GT(bake.crust_thickness, 0.0);
}

INSTANTIATE_TEST_SUITE_P(BothSolvers, WaterAtAltitude, ::testing::Values("sph", "mpm"));

// Drying through faces the particles do not resolve (moisture.surface_evaporation supply_limited,
// physics/water.hpp surface_flux): a moist 24 mm cube in air that pulls far harder than the liquid can
// follow (h_m 0.5 m/s, with an isotherm that leaves its face nearly dry), held at 60 degC (air and dough
// at 60, a latent heat of 1 kJ/kg so that evaporation does not cool it), loses its water as Fick's
// diffusion out of a cube whose faces are held dry: the remaining fraction is the product of three plane
// sheets' (a box whose faces are held at one concentration separates by axis), F(t)^3 with
// F = sum 8/((2n+1)^2 pi^2) exp(-(2n+1)^2 pi^2 D t / a^2) (Crank 1975, The Mathematics of Diffusion,
// Eq 4.18). First the depleted layer lies inside the outer particles (their faces' supply,
// 2 rho_d^2 D X0^2 / (pi M)), then the resolved diffusion between particles carries it. D_w is ten times
// a dough's (1e-8 m^2/s at 100 degC, 6e-9 at 60) so that the layer reaches several particles deep in
// half an hour.
class SurfaceDrying : public ::testing::TestWithParam<std::string> {};

TEST_P(SurfaceDrying, ACubesWaterLeavesByFicksDiffusionThroughDriedFaces) {
  constexpr double kSideA = 0.024, kTheta = 60, kX = 0.6, kD100 = 1e-8;
  const bool sph = GetParam() == "sph";
  json s = sph ? json{{"type", "sph"}, {"sph", {{"spacing", 0.002}, {"speed_of_sound", 3.0}}}}
               : json{{"type", "mpm"}, {"mpm", {{"cell_size", 0.002}, {"heat", "explicit"}}}};
  json material = {{"density", 400.0},
                   {"specific_heat", 2500.0},
                   {"conductivity", 0.3},
                   {"moisture",
                    {{"content", kX},
                     {"liquid_diffusivity", kD100},
                     {"vapour_diffusivity", 0.0},
                     {"cell_heat_pipe", 0.0},
                     {"latent_heat", 1000.0},
                     // An isotherm that holds little water at low activity (a = 1: X 0.003 at a_w 0.02),
                     // so the face dries nearly to 0 as the solution has it.
                     {"sorption", {{"oswin_a_offset", 0.0}}},
                     {"surface_evaporation", "supply_limited"}}}};
  if (sph)
    material["viscosity"] = 20.0;
  else
    material["youngs_modulus"] = 2e4;
  const double half = 0.5 * kSideA;
  const json doc = {
      {"solver", s},
      {"time", {{"end", 1.0}}},
      {"gravity", {0, 0, 0}},
      {"environment",
       {{"air_temperature", kTheta},
        {"heat_transfer_coefficient", 50.0},
        {"mass_transfer_coefficient", 0.5},
        {"bake_time_scale", 20000.0}}},
      {"domain", {{"min", {-0.03, -0.03, -0.03}}, {"max", {0.03, 0.03, 0.03}}}},
      {"materials", {{"dough", material}}},
      {"bodies",
       json::array({{{"name", "cube"},
                     {"material", "dough"},
                     {"temperature", kTheta},
                     {"shape", {{"type", "box"}, {"min", {-half, -half, -half}}, {"max", {half, half, half}}}}}})}};
  std::unique_ptr<Solver> solver = make_solver(parse_scene(doc.dump(), "scene.json", "."));
  const auto water_in = [&] {
    double w = 0;
    for (double v : solver->particles().scalar("water_mass")) w += v;
    return w;
  };
  const double water0 = water_in(), d = kD100 * kTheta / 100;
  for (const double bake_seconds : {20.0, 60.0, 150.0, 600.0, 1800.0}) {
    test_support::advance_to(*solver, bake_seconds / 20000.0);
    double sheet = 0;  // F(t) of one plane sheet of thickness a with both faces dry
    for (int n = 0; n < 200; ++n) {
      const double k = (2 * n + 1) * kPi;
      sheet += 8 / (k * k) * std::exp(-k * k * d * bake_seconds / (kSideA * kSideA));
    }
    const double fick = 1 - sheet * sheet * sheet, lost = 1 - water_in() / water0;
    double coldest = 1e9;
    for (double t : solver->particles().scalar("temperature")) coldest = std::min(coldest, t);
    std::printf("%s: after %4.0f s %.4f of the water lost, Fick %.4f (ratio %.3f; layer %.1f mm), coldest %.2f degC\n",
                GetParam().c_str(), bake_seconds, lost, fick, lost / fick, 1e3 * std::sqrt(kPi * d * bake_seconds),
                coldest);
    RecordProperty("ratio_at_" + std::to_string(int(bake_seconds)), std::to_string(lost / fick));
    EXPECT_NEAR(lost / fick, 1.0, 0.08) << "t = " << bake_seconds << " s";
  }
}

INSTANTIATE_TEST_SUITE_P(BothSolvers, SurfaceDrying, ::testing::Values("sph", "mpm"));
