// Cylinder slump of a Bingham material against the slump-test relation
// (issue 26). Murata (1984), corrected by Schowalter & Christensen (1998)
// and written for a cylinder by Pashias, Boger, Summers & Glenister (1996,
// J. Rheol. 40:1179): a column of height H, whose vertical stress at depth z
// is ρ g z, yields where that stress exceeds the uniaxial yield stress σ_y;
// the unyielded top keeps its height σ_y/(ρg) and the yielded part below
// compresses until the stress at each level is σ_y again. With
// σ' = σ_y / (ρ g H) the dimensionless slump is
//     s' = s / H = 1 − σ' (1 − ln σ')          (σ' ≤ 1; 0 above).
// Pashias writes it with the Tresca shear yield stress, σ_y = 2 τ_y; for the
// tensorial (von Mises) Bingham law both solvers use, σ_y = √3 τ_y (the
// uniaxial stress whose √J₂ is τ_y), so σ' is the natural variable.
// The relation neglects shear on the base and inertia: the floor here is free
// slip and the material viscous enough that the column does not overshoot.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <tuple>
#include <vector>

#include "helpers.hpp"
#include "mpm/solver.hpp"
#include "physics/rheology.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

double slump_relation(double sigma) { return sigma >= 1 ? 0.0 : 1 - sigma * (1 - std::log(sigma)); }

constexpr double kHeight = 0.1;  // m; the cylinder's height equals its diameter (Pashias)
constexpr double kDensity = 1000;
constexpr double kGravity = 9.81;

// Highest point of the material (the flat unyielded top).
double top(const ParticleSet& ps) {
  double y = -1e30;
  for (const auto& x : ps.vector("position")) y = std::max(y, x.y());
  return y;
}

// MPM: a quarter of the cylinder against two slip planes at x = 0 and z = 0,
// its planes of symmetry (slip, not the domain's separating walls: the
// quarter would slide away from them and collapse without its hoop stress).
json symmetry_plane(const std::string& name, const Vec3& normal) {
  return {{"name", name},
          {"shape", {{"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {normal.x(), normal.y(), normal.z()}}}},
          {"contact", "slip"}};
}

// `aspect`: the column's height over its diameter (Pashias's cylinders: 1).
json mpm_slump(int cells_across, double sigma, double viscosity, double aspect = 1) {
  const double r = 0.5 * kHeight / aspect, dx = 2 * r / cells_across;
  const double yield_stress = sigma * kDensity * kGravity * kHeight;
  const double w = 3 * r;
  return {
      {"solver", {{"type", "mpm"}, {"mpm", {{"cell_size", dx}, {"heat", "off"}, {"model", "baseline"}}}}},
      {"time", {{"end", 10.0}}},
      {"gravity", {0, -kGravity, 0}},
      {"domain", {{"min", {-4 * dx, 0, -4 * dx}}, {"max", {w, 1.2 * kHeight, w}}}},
      {"colliders",
       json::array({symmetry_plane("x-symmetry", Vec3(1, 0, 0)), symmetry_plane("z-symmetry", Vec3(0, 0, 1))})},
      {"materials",
       {{"bingham",
         {{"density", kDensity},
          {"youngs_modulus", 1e5},
          {"poisson_ratio", 0.3},
          {"plasticity", {{"model", "von_mises"}, {"yield_stress", yield_stress}, {"viscosity", viscosity}}}}}}},
      {"bodies",
       json::array(
           {{{"name", "column"},
             {"material", "bingham"},
             {"shape",
              {{"type", "difference"},
               {"base", {{"type", "cylinder"}, {"center", {0, 0.5 * kHeight, 0}}, {"radius", r}, {"height", kHeight}}},
               {"subtract", json::array({{{"type", "box"}, {"min", {-r, -0.1, -r}}, {"max", {0, 0.2, r}}},
                                         {{"type", "box"}, {"min", {-r, -0.1, -r}}, {"max", {r, 0.2, 0}}}})}}}}})}};
}

// SPH: the whole cylinder on the domain's free-slip floor, a Bingham fluid
// of shear yield stress σ_y/√3 (its von Mises uniaxial yield is σ_y).
// `across`: particles across the diameter; `aspect`: the column's height over its diameter.
json sph_slump(int across, double sigma, double plastic_viscosity, double regularisation, double aspect = 1) {
  const double r = 0.5 * kHeight / aspect, s = 2 * r / across, w = 1.5 * kHeight;
  const double shear_yield = sigma * kDensity * kGravity * kHeight / std::sqrt(3.0);
  return {{"solver", {{"type", "sph"}, {"sph", {{"spacing", s}, {"viscosity_solver", "implicit"}}}}},
          {"time", {{"end", 10.0}}},
          {"gravity", {0, -kGravity, 0}},
          {"domain", {{"min", {-w, 0, -w}}, {"max", {w, 1.2 * kHeight, w}}}},
          {"materials",
           {{"bingham", sigma > 0 ? json{{"density", kDensity},
                                         {"viscosity", plastic_viscosity},
                                         {"herschel_bulkley",
                                          {{"yield_stress", shear_yield}, {"regularisation_rate", regularisation}}}}
                                  : json{{"density", kDensity}, {"viscosity", plastic_viscosity}}}}},
          {"bodies",
           json::array(
               {{{"name", "column"},
                 {"material", "bingham"},
                 {"shape",
                  {{"type", "cylinder"}, {"center", {0, 0.5 * kHeight, 0}}, {"radius", r}, {"height", kHeight}}}}})}};
}

struct Slump {
  double measured = 0, expected = 0, kinetic_per_mass = 0;
};

Slump run_mpm_slump(int cells_across, double sigma, double viscosity, double duration, double mass_scaling = 1,
                    long* steps = nullptr, double aspect = 1) {
  json scene = mpm_slump(cells_across, sigma, viscosity, aspect);
  scene["solver"]["mass_scaling"] = mass_scaling;
  auto mpm = test_support::make_mpm(scene);
  const double start = top(mpm->particles());
  long count = 0;
  test_support::advance_to(*mpm, duration, [&] { ++count; });
  if (steps) *steps = count;
  Slump s;
  s.measured = (start - top(mpm->particles())) / kHeight;
  s.expected = slump_relation(sigma);
  const auto& v = mpm->particles().vector("velocity");
  for (const auto& vi : v) s.kinetic_per_mass += 0.5 * vi.squaredNorm() / double(v.size());
  return s;
}

}  // namespace

TEST(SlumpRelation, MatchesPashiasAtItsKnownPoints) {
  EXPECT_DOUBLE_EQ(slump_relation(1.0), 0.0);
  EXPECT_NEAR(slump_relation(0.5), 1 - 0.5 * (1 + std::log(2.0)), 1e-15);
  // Pashias's form with τ' = τ_y/(ρgH): s' = 1 − 2τ'(1 − ln 2τ'); τ' = 0.1 → 0.478.
  EXPECT_NEAR(slump_relation(0.2), 0.478, 5e-4);
}

// Issue 26: the MPM slump of a von Mises Bingham column (H = D = 10 cm,
// E = 100 kPa, η = 50 Pa s: overdamped, settled by 1.5 s) over σ' = 0.2-0.7,
// at 10 cells across the diameter. Measured (docs/validation.md): 10 cells
// +0.037, +0.062, +0.049, −0.003; 20 cells +0.061 (σ' = 0.3) and +0.047
// (0.5), within 0.002 of 10 cells: converged, and the difference left is the
// relation's own (it takes each slice's stress as uniaxial; the column's
// elastic compression adds ~0.005). The 0.05 is not met at σ' = 0.3.
class MpmSlump : public ::testing::TestWithParam<std::tuple<int, double>> {};

TEST_P(MpmSlump, SettlesNearTheSlumpTestRelation) {
  const auto [cells, sigma] = GetParam();
  const Slump s = run_mpm_slump(cells, sigma, 50.0, 1.5);
  std::printf("MPM %d cells across, sigma' %.2f: slump %.4f, relation %.4f, difference %+.4f\n", cells, sigma,
              s.measured, s.expected, s.measured - s.expected);
  RecordProperty("slump", std::to_string(s.measured));
  EXPECT_LT(s.kinetic_per_mass, 1e-5) << "settled";
  EXPECT_NEAR(s.measured, s.expected, 0.07);
}

INSTANTIATE_TEST_SUITE_P(TenCells, MpmSlump,
                         ::testing::Values(std::make_tuple(10, 0.2), std::make_tuple(10, 0.3), std::make_tuple(10, 0.5),
                                           std::make_tuple(10, 0.7)),
                         [](const auto& info) {
                           return std::to_string(std::get<0>(info.param)) + "_cells_sigma_" +
                                  std::to_string(int(std::lround(100 * std::get<1>(info.param))));
                         });

// Quasi-static mass scaling (solver.mass_scaling): the column's final
// state is an equilibrium of its weight and yield stress reached by a
// creeping flow, neither of which depends on its inertia while the motion
// stays overdamped. With η = 200 Pa s (3 s) the slump at mass scaling 1, 4
// and 16 was measured 0.1966, 0.1955 and 0.1945 in 8,702, 4,351 and 3,000
// steps (16: at max_dt); with η = 50 the heavier column is no longer
// overdamped and overshoots (0.246 at 16 against 0.202): docs/physics.md.
TEST(MpmSlump, MassScalingSettlesAtTheSameSlumpInFewerSteps) {
  long steps_true = 0, steps_scaled = 0;
  const Slump unscaled = run_mpm_slump(10, 0.5, 200.0, 3.0, 1.0, &steps_true);
  const Slump scaled = run_mpm_slump(10, 0.5, 200.0, 3.0, 16.0, &steps_scaled);
  std::printf("MPM slump sigma' 0.5, 10 cells, eta 200: %.4f in %ld steps; mass scaling 16: %.4f in %ld steps\n",
              unscaled.measured, steps_true, scaled.measured, steps_scaled);
  RecordProperty("slump_unscaled", std::to_string(unscaled.measured));
  RecordProperty("slump_scaled", std::to_string(scaled.measured));
  EXPECT_NEAR(scaled.measured, unscaled.measured, 0.005);
  EXPECT_LT(scaled.kinetic_per_mass, 1e-5) << "settled";
  EXPECT_LT(double(steps_scaled), 0.4 * double(steps_true));
}

// The convergence study's finer case (about 2 minutes each): run with
// --gtest_also_run_disabled_tests.
INSTANTIATE_TEST_SUITE_P(DISABLED_TwentyCells, MpmSlump,
                         ::testing::Values(std::make_tuple(20, 0.3), std::make_tuple(20, 0.5)), [](const auto& info) {
                           return std::to_string(std::get<0>(info.param)) + "_cells_sigma_" +
                                  std::to_string(int(std::lround(100 * std::get<1>(info.param))));
                         });

// SPH: measured, not yet asserted (docs/validation.md). With the thesis's
// Laplacian viscosity the column collapses far past the relation (a free
// column resists extension about ten times too weakly); with the stress form
// it slumps more slowly at first but keeps creeping (0.289 at 0.7 s against
// the relation's 0.153) and costs minutes per simulated second.
TEST(SphSlump, DISABLED_StressFormHistory) {
  json scene = sph_slump(20, 0.5, 50.0, 0.01);
  scene["solver"]["sph"]["viscosity_operator"] = "stress";
  auto sph = test_support::make_sph(scene);
  const double start = top(sph->particles());
  for (double t = 0.1; t < 1.01; t += 0.1) {
    test_support::advance_to(*sph, t);
    std::printf("t %.1f s: slump %.4f (relation %.4f)\n", t, (start - top(sph->particles())) / kHeight,
                slump_relation(0.5));
  }
}

// The stress-form viscosity (solver.sph.viscosity_operator = stress) damps
// only deformation: a free ball of very viscous fluid spinning rigidly keeps
// its angular velocity (D = 0 exactly for the corrected gradients, and the
// force conserves angular momentum), where the Laplacian form brakes its
// surface. A shear wave in a periodic box decays at ν k² as with the
// Laplacian (to the tolerance stated below).
namespace {
struct Spin {
  double angular_momentum = 0, angular_velocity = 0;  // both relative to the start
};
Spin spin_after(const std::string& op, double duration) {
  const double s = 0.005, omega = 2.0;
  const json scene = {
      {"solver",
       {{"type", "sph"},
        {"sph",
         {{"spacing", s}, {"speed_of_sound", 5.0}, {"viscosity_solver", "implicit"}, {"viscosity_operator", op}}}}},
      {"time", {{"end", 1.0}}},
      {"gravity", {0, 0, 0}},
      {"domain", {{"min", {-0.1, -0.1, -0.1}}, {"max", {0.1, 0.1, 0.1}}}},
      {"materials", {{"syrup", {{"density", 1000.0}, {"viscosity", 500.0}}}}},
      {"bodies", json::array({{{"name", "ball"},
                               {"material", "syrup"},
                               {"shape", {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 0.04}}}}})}};
  auto sph = test_support::make_sph(scene);
  auto& ps = sph->mutable_particles();
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const Vec3 x = ps.vector("position")[i];
    ps.vector("velocity")[i] = Vec3(-omega * x.z(), 0, omega * x.x());  // about the y axis
  }
  sph->refresh();
  auto angular_momentum = [&] {  // L_y per unit particle mass
    const auto& x = sph->particles().vector("position");
    const auto& v = sph->particles().vector("velocity");
    double l = 0;
    for (std::size_t i = 0; i < x.size(); ++i) l += x[i].z() * v[i].x() - x[i].x() * v[i].z();
    return l;
  };
  const double l0 = angular_momentum();
  test_support::advance_to(*sph, duration);
  // Angular velocity about y: L_y / I_yy of the particles.
  const auto& x = sph->particles().vector("position");
  double inertia = 0;
  for (const Vec3& xi : x) inertia += xi.x() * xi.x() + xi.z() * xi.z();
  const double l = angular_momentum();
  return {l / l0, -l / inertia / omega};
}
}  // namespace

TEST(StressViscosity, ARigidlySpinningViscousBallKeepsItsSpin) {
  // ν = 0.5 m²/s: the viscous time R²/ν of the 4 cm ball is 3 ms; 0.05 s is
  // seventeen of them and a tenth of a turn.
  const Spin stress = spin_after("stress", 0.05), laplacian = spin_after("laplacian", 0.05);
  std::printf("after 0.05 s: stress form L/L0 %.7f, omega/omega0 %.5f; Laplacian L/L0 %.5f\n", stress.angular_momentum,
              stress.angular_velocity, laplacian.angular_momentum);
  EXPECT_NEAR(stress.angular_momentum, 1.0, 1e-6);
  // The ball widens a little as it spins (ω falls as its inertia grows: measured −0.7%).
  EXPECT_GT(stress.angular_velocity, 0.99);
  EXPECT_LT(laplacian.angular_momentum, 0.5);  // the defect the stress form removes
}

// A wall the body rests on holds it inside the viscous solve (the particles
// touching it keep the wall's normal velocity; docs/physics.md, "Walls in the
// implicit viscous solve"). A Newtonian column as tall as it is wide, μ = 28,300 Pa·s (the
// yield-stress slump's at-rest viscosity), on the free-slip floor: under its
// own weight it should shorten by ρgH²t/(6μ) (uniaxial slices; 0.0006 H in
// 0.1 s) plus the weakly compressible column's hydrostatic compression
// (ρgH/(2ρc²), 0.0021 H at c = 15.3 m/s): 0.0027 H. Left to the pressure
// alone the floor's reaction reached the body through the pressure's
// compression only, a step late, and the column sank at 1.5 cm/s as a
// whole: 0.0119 H (measured). With the support, 0.0035 H (measured: the
// column also keeps losing volume, 0.7% in 0.1 s, which the estimate
// leaves out). Ten particles across, stress-form viscosity.
TEST(StressViscosity, AStiffColumnRestsOnItsFloor) {
  json scene = sph_slump(10, 0.0, 28300.0, 0.0);
  scene["solver"]["sph"]["viscosity_operator"] = "stress";
  auto sph = test_support::make_sph(scene);
  const double start = top(sph->particles());
  test_support::advance_to(*sph, 0.1);
  const double slump = (start - top(sph->particles())) / kHeight;
  std::printf("stiff column: %.4f of its height in 0.1 s (estimate 0.0027)\n", slump);
  EXPECT_GT(slump, 0.0);
  EXPECT_LT(slump, 0.007);
}

// The wall pushes and never pulls: a viscous column on the floor whose upper
// half is thrown upward (no gravity) leaves the floor whole, with the
// momentum it was given. Its bottom particles start at rest on the floor, so
// the support holds them until the solve's reaction there turns tensile and
// lets them go; held, they would take momentum out of the column.
TEST(StressViscosity, AWallLetsGoOfABodyMovingAway) {
  json scene = sph_slump(10, 0.0, 28300.0, 0.0);
  scene["solver"]["sph"]["viscosity_operator"] = "stress";
  scene["gravity"] = {0, 0, 0};
  auto sph = test_support::make_sph(scene);
  auto& ps = sph->mutable_particles();
  const auto& mass = ps.scalar("mass");
  double momentum0 = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (ps.vector("position")[i].y() > 0.5 * kHeight) ps.vector("velocity")[i] = Vec3(0, 0.1, 0);
    momentum0 += mass[i] * ps.vector("velocity")[i].y();
  }
  sph->refresh();
  test_support::advance_to(*sph, 0.01);
  double momentum = 0, lowest = 1e30;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    momentum += mass[i] * ps.vector("velocity")[i].y();
    lowest = std::min(lowest, ps.vector("position")[i].y());
  }
  double bottom_speed = 0;
  int bottom = 0;
  for (std::size_t i = 0; i < ps.size(); ++i)
    if (ps.vector("position")[i].y() < lowest + 0.002) bottom_speed += ps.vector("velocity")[i].y(), ++bottom;
  std::printf("momentum kept %.9f, lowest particle %.5f m (was 0.005), bottom layer rises at %.4f m/s\n",
              momentum / momentum0, lowest, bottom_speed / bottom);
  EXPECT_NEAR(momentum / momentum0, 1.0, 1e-6);
  EXPECT_GT(lowest, 0.005 + 1e-4);  // held, the bottom layer stayed at 0.005 m and kept 0.77 of the momentum
}

// The relation's uniaxial slices (each level's stress vertical, no shear
// between levels) hold better the more slender the column (Roussel & Coussot
// 2005 separate a slump regime, H >> R, from a spreading one). At the same 10 cells across
// the MPM slump comes to it as the column's height over its diameter grows
// (measured, docs/validation.md; the disabled study below prints them):
// sigma' 0.3: +0.065, +0.086, +0.039, +0.013 at H/D 1, 2, 4, 8; sigma' 0.5:
// +0.051, +0.049, +0.018, +0.0065. So what is left at Pashias's H/D = 1
// (+0.05 to +0.06 at any resolution) is the relation's, not the solver's.
TEST(MpmSlump, ASlenderColumnSettlesOnTheRelation) {
  const Slump squat = run_mpm_slump(10, 0.5, 50.0, 1.5);
  const Slump slender = run_mpm_slump(10, 0.5, 50.0, 2.5, 1.0, nullptr, 4.0);
  std::printf("MPM sigma' 0.50, 10 cells across: H/D 1 slump %.4f (%+.4f), H/D 4 slump %.4f (%+.4f), relation %.4f\n",
              squat.measured, squat.measured - squat.expected, slender.measured, slender.measured - slender.expected,
              slender.expected);
  RecordProperty("slump_slender", std::to_string(slender.measured));
  EXPECT_LT(slender.kinetic_per_mass, 1e-5) << "settled";
  EXPECT_NEAR(slender.measured, slender.expected, 0.025);  // measured +0.018
  EXPECT_GT(squat.measured - squat.expected, 2 * std::abs(slender.measured - slender.expected));
}

// The study behind those figures (about 12 minutes on two threads; run with
// --gtest_also_run_disabled_tests).
TEST(MpmSlump, DISABLED_AspectRatioStudy) {
  for (double sigma : {0.3, 0.5})
    for (double aspect : {1.0, 2.0, 4.0, 8.0}) {
      const Slump s = run_mpm_slump(10, sigma, 50.0, 1.5 + 0.5 * aspect, 1.0, nullptr, aspect);
      std::printf("MPM H/D %.0f, sigma' %.2f: slump %.4f, relation %.4f, difference %+.4f, kinetic %.2e\n", aspect,
                  sigma, s.measured, s.expected, s.measured - s.expected, s.kinetic_per_mass);
      std::fflush(stdout);
    }
}

// The elastoviscoplastic form (material.herschel_bulkley.form; Saramito
// 2007): the Maxwell stress is an elastic solid's below the yield stress and
// returns to τ_y + K γ̇_p above it, the law of MPM's plasticity, with its
// elastic modulus (G = E/(2(1 + ν)) of MPM's E = 10⁵ Pa, ν = 0.3) and K = 25
// Pa·s (MPM's η = 50 Pa·s is a shear viscosity of η/2). With the stress-form
// viscosity the stress's rate reads the corrected velocity gradient and its
// force is that gradient's adjoint (docs/physics.md, "Elastoviscoplastic
// yield stress").
namespace {
json sph_evp_slump(int across, double sigma, double smoothing_ratio = 0, double aspect = 1) {
  json scene = sph_slump(across, sigma, 25.0, 0.01, aspect);
  auto& sph = scene["solver"]["sph"];
  if (smoothing_ratio > 0) sph["smoothing_ratio"] = smoothing_ratio;
  sph["viscosity_operator"] = "stress";
  sph["elasticity_solver"] = "implicit";
  sph["negative_pressure"] = "keep";  // a solid's floor layer carries tension (docs/validation.md)
  auto& m = scene["materials"]["bingham"];
  m["elasticity"] = 2 * 1e5 / (2 * 1.3);  // μ_e = 2G
  m["herschel_bulkley"] = {{"yield_stress", sigma * kDensity * kGravity * kHeight / std::sqrt(3.0)},
                           {"form", "elastoviscoplastic"}};
  return scene;
}
double kinetic_per_mass(const ParticleSet& ps) {
  double k = 0;
  for (const auto& v : ps.vector("velocity")) k += 0.5 * v.squaredNorm();
  return k / double(ps.size());
}
struct SphSlumpHistory {
  double at_1s = 0, at_end = 0, kinetic = 0;
};
SphSlumpHistory run_evp_slump(int across, double sigma, double end, double smoothing_ratio = 0, double aspect = 1) {
  auto sph = test_support::make_sph(sph_evp_slump(across, sigma, smoothing_ratio, aspect));
  const double start = top(sph->particles());
  SphSlumpHistory h;
  test_support::advance_to(*sph, 1.0);
  h.at_1s = (start - top(sph->particles())) / kHeight;
  test_support::advance_to(*sph, end);
  h.at_end = (start - top(sph->particles())) / kHeight;
  h.kinetic = kinetic_per_mass(sph->particles());
  std::printf(
      "SPH elastoviscoplastic, %d across, H/D %.0f, h/dx %.2f, sigma' %.2f: slump %.4f at 1 s, %.4f at %.1f s "
      "(relation %.4f), kinetic %.2e J/kg\n",
      across, aspect, sph->setup().settings.smoothing_ratio, sigma, h.at_1s, h.at_end, end, slump_relation(sigma),
      h.kinetic);
  std::fflush(stdout);
  return h;
}
}  // namespace

// Where the regularised form keeps creeping (0.011 H per 0.1 s at 1 s,
// docs/validation.md), the elastoviscoplastic column comes to rest: kinetic
// energy 9e-12 J/kg at 1.5 s, the top still by 1e-4 H after 1 s. Ten across
// it stops at 0.104 (the relation 0.153, MPM 0.204), twenty across at 0.217
// (SphSlump.DISABLED_ElastoviscoplasticTwentyAcross).
TEST(SphSlump, ElastoviscoplasticColumnComesToRest) {
  const SphSlumpHistory h = run_evp_slump(10, 0.5, 1.5);
  EXPECT_LT(h.kinetic, 1e-9);
  EXPECT_LT(std::abs(h.at_end - h.at_1s), 1e-3);
  EXPECT_GT(h.at_end, 0.5 * slump_relation(0.5));  // it yields and slumps, by about the relation's amount
  EXPECT_LT(h.at_end, slump_relation(0.5) + 0.1);
}

TEST(SphSlump, DISABLED_ElastoviscoplasticTwentyAcross) {
  const SphSlumpHistory h = run_evp_slump(20, 0.5, 1.5);
  EXPECT_LT(h.kinetic, 1e-6);
  EXPECT_NEAR(h.at_end, slump_relation(0.5), 0.07);
}

// The support of 2.5 spacings (the schema's advice for this form) over the
// yield stresses the MPM test covers, twenty across (4 minutes each on 2
// threads): docs/validation.md, "Cylinder slump".
TEST(SphSlump, DISABLED_WiderSupportOverYieldStresses) {
  for (double sigma : {0.2, 0.3, 0.5, 0.7}) run_evp_slump(20, sigma, 2.0, 2.5);
}

// The slender column of MPM's test (H/D 4, where the relation's uniaxial
// slices hold), ten across its diameter, h = 2.5 spacings (its first second
// took 2 min 13 s on 2 threads): it slumps 0.22 by 0.4 s, past MPM's
// settled 0.171, then tips over and collapses (0.719 at 1 s;
// docs/validation.md). MPM's quarter column between its symmetry planes
// cannot tip.
TEST(SphSlump, DISABLED_SlenderColumnStudy) { run_evp_slump(10, 0.5, 2.5, 2.5, 4.0); }

// How far the particles' stresses agree with their neighbours' (the study
// behind docs/validation.md, "Where the twenty-across column loses its
// strength"): for each particle below `height`, the norm of the weighted
// mean of the deviatoric stresses within h (weights (1 − r/h)³, itself
// included) over the norm of its own, averaged. 1 where the stress field is
// smooth on the kernel's scale; a load is carried by what neighbours agree on.
namespace {
double stress_agreement(const sph::SphSolver& sph, double support, double height) {
  const auto& x = sph.particles().vector("position");
  std::vector<Mat3> stress(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) stress[i] = sph.stress(i);
  double sum = 0;
  int count = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i].y() > height || stress[i].norm() == 0) continue;
    Mat3 mean = Mat3::Zero();
    double weights = 0;
    for (std::size_t j = 0; j < x.size(); ++j) {
      const double q = (x[i] - x[j]).norm() / support;
      if (q >= 1) continue;
      const double w = (1 - q) * (1 - q) * (1 - q);
      mean += w * stress[j];
      weights += w;
    }
    sum += (mean / weights).norm() / stress[i].norm();
    ++count;
  }
  return count ? sum / count : 1.0;
}
}  // namespace

// Ten and twenty across at σ' = 0.5 (about 10 s and 3 minutes on 2 threads):
// the agreement in the bottom 4 cm while the column flows, with its slump.
TEST(SphSlump, DISABLED_StressAgreementStudy) {
  for (int across : {10, 20}) {
    auto sph = test_support::make_sph(sph_evp_slump(across, 0.5));
    const double start = top(sph->particles());
    for (double t : {0.05, 0.1, 0.2, 0.3, 0.4, 0.6, 1.0, 1.5}) {
      test_support::advance_to(*sph, t);
      std::printf("%d across, t %.2f s: slump %.4f, stress agreement below 4 cm %.3f\n", across, t,
                  (start - top(sph->particles())) / kHeight, stress_agreement(*sph, sph->support(), 0.04));
      std::fflush(stdout);
    }
  }
}

// An elastic column (Maxwell stress that never relaxes, G = 5 kPa, on the
// free-slip floor, laterally free) stands under its weight in uniaxial
// stress, σ_yy = −ρ g (H − y): its top sinks by ρ g H²/(2E), E = 9KG/(3K + G)
// with the weakly compressible bulk modulus K = ρc² (0.0329 H here). With the
// corrected gradient and its adjoint it settles and converges to that at first
// order: 0.54 of it ten across, 0.77 twenty across (2 minutes on 2 threads).
// With the Laplacian operator (the symmetric form, the uncorrected gradient
// and the Laplacian's elastic predictor) the same column keeps sinking
// (0.085 H at 1 s, 0.0057 H per 0.2 s).
namespace {
double elastic_column_sag(int across) {
  json scene = sph_slump(across, 0.0, 20.0, 0.0);
  auto& sph = scene["solver"]["sph"];
  sph["viscosity_operator"] = "stress";
  sph["elasticity_solver"] = "implicit";
  sph["negative_pressure"] = "keep";
  auto& m = scene["materials"]["bingham"];
  m["elasticity"] = 1e4;  // μ_e = 2G
  m["relaxation_time"] = 1e9;
  auto solver = test_support::make_sph(scene);
  const double c = solver->setup().settings.speed_of_sound;  // 15.3 m/s for this column
  const double bulk = kDensity * c * c, shear = 5e3, young = 9 * bulk * shear / (3 * bulk + shear);
  const double expected = kDensity * kGravity * kHeight / (2 * young);
  const double start = top(solver->particles());
  test_support::advance_to(*solver, 0.8);
  const double at_08 = (start - top(solver->particles())) / kHeight;
  test_support::advance_to(*solver, 1.0);
  const double sag = (start - top(solver->particles())) / kHeight;
  const double kinetic = kinetic_per_mass(solver->particles());
  std::printf(
      "elastic column, %d across: sag %.4f H at 1 s (%.4f at 0.8 s), uniaxial %.4f H, ratio %.3f, kinetic "
      "%.2e J/kg\n",
      across, sag, at_08, expected, sag / expected, kinetic);
  EXPECT_LT(std::abs(sag - at_08), 5e-4) << "settled, not creeping (the symmetric form: 0.0057 H per 0.2 s)";
  EXPECT_LT(kinetic, 1e-6);
  return sag / expected;
}
}  // namespace

TEST(SphElasticColumn, StandsOnItsFloorInUniaxialStress) {
  const double ratio = elastic_column_sag(10);
  EXPECT_GT(ratio, 0.45);
  EXPECT_LT(ratio, 0.65);
}

TEST(SphElasticColumn, DISABLED_ConvergesTowardsTheUniaxialSag) {
  const double ratio = elastic_column_sag(20);
  EXPECT_GT(ratio, 0.7);
  EXPECT_LT(ratio, 0.85);
}
