// Channel flows against their analytic solutions (issue 26): a fluid between
// two no-slip plates at y = 0 and y = L, periodic along x and z, driven along
// x by a body force F from rest.
//  - Poiseuille start-up (Morris, Fox & Zhu 1997, Eq 21):
//      v(y, t) = F/(2ν) y (L − y)
//                − Σ_n 4 F L² / (ν π³ (2n+1)³) sin((2n+1) π y / L) e^{−(2n+1)² π² ν t / L²}
//  - Bingham plane Poiseuille (e.g. Bird, Dai & Yarusso 1983): with the
//    pressure gradient G = ρF, half-width b = L/2 and η = |y − L/2|, the plug
//    |η| < y₀ = τ_y/G moves at u_p = G (b − y₀)² / (2μ_p), and outside it
//      u(η) = G (b² − η²) / (2μ_p) − τ_y (b − η) / μ_p.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <tuple>
#include <vector>

#include "helpers.hpp"
#include "mpm/solver.hpp"
#include "physics/rheology.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

// Morris et al. (1997) Eq 21, summed until the terms stop mattering.
double poiseuille_startup(double y, double t, double force, double nu, double length) {
  double v = force / (2 * nu) * y * (length - y);
  for (int n = 0; n < 200; ++n) {
    const double k = 2 * n + 1;
    v -= 4 * force * length * length / (nu * std::pow(kPi, 3) * k * k * k) * std::sin(k * kPi * y / length) *
         std::exp(-k * k * kPi * kPi * nu * t / (length * length));
  }
  return v;
}

// The steady Bingham channel profile (see the head of the file).
double bingham_channel(double y, double force, double rho, double mu, double yield_stress, double length) {
  const double g = rho * force, b = 0.5 * length, y0 = yield_stress / g;
  const double eta = std::min(std::abs(y - b), b);
  if (eta <= y0) return g * (b - y0) * (b - y0) / (2 * mu);
  return g * (b * b - eta * eta) / (2 * mu) - yield_stress * (b - eta) / mu;
}

// The steady Herschel–Bulkley channel (τ = τ_y + K γ̇ⁿ), same geometry:
//   u(η) = n/(n+1) (G/K)^{1/n} [(b − y₀)^{(n+1)/n} − (η − y₀)^{(n+1)/n}] for η > y₀,
// the plug moving at its value for η = y₀ (n = 1: bingham_channel).
double herschel_bulkley_channel(double y, double force, double rho, double consistency, double flow_index,
                                double yield_stress, double length) {
  const double g = rho * force, b = 0.5 * length, y0 = yield_stress / g, m = (flow_index + 1) / flow_index;
  const double eta = std::max(std::min(std::abs(y - b), b), y0);
  return flow_index / (flow_index + 1) * std::pow(g / consistency, 1 / flow_index) *
         (std::pow(b - y0, m) - std::pow(eta - y0, m));
}

struct Channel {
  double length = 1e-3;    // plate distance L, m
  double nu = 1e-6;        // kinematic viscosity, m²/s
  double force = 2e-4;     // body force per mass along x, m/s²
  int across = 20;         // particles across L
  int periodic_cells = 6;  // particles along x and z
  std::string viscosity_solver = "explicit";
  double yield_stress = 0;       // τ_y, Pa (Bingham when > 0)
  double regularisation = 0;     // γ̇_r, 1/s
  double speed_of_sound = 0.01;  // m/s: 400 times the fastest flow
  double max_dt = 1e-3;          // s
};

json sph_channel(const Channel& c) {
  const double s = c.length / c.across;
  const double w = c.periodic_cells * s;
  const double rho = 1000;
  auto plate = [&](double y, double ny) {
    return json{{"name", ny > 0 ? "bottom-plate" : "top-plate"},
                {"shape", {{"type", "plane"}, {"point", {0, y, 0}}, {"normal", {0, ny, 0}}}},
                {"contact", "sticky"}};
  };
  return {{"solver",
           {{"type", "sph"},
            {"max_dt", c.max_dt},
            {"sph", {{"spacing", s}, {"speed_of_sound", c.speed_of_sound}, {"viscosity_solver", c.viscosity_solver}}}}},
          {"time", {{"end", 1.0}}},
          {"gravity", {c.force, 0, 0}},
          {"domain", {{"min", {0, -c.length, 0}}, {"max", {w, 2 * c.length, w}}, {"periodic", {"x", "z"}}}},
          {"materials",
           {{"fluid", c.yield_stress > 0
                          ? json{{"density", rho},
                                 {"viscosity", c.nu * rho},
                                 {"herschel_bulkley",
                                  {{"yield_stress", c.yield_stress}, {"regularisation_rate", c.regularisation}}}}
                          : json{{"density", rho}, {"viscosity", c.nu * rho}}}}},
          {"colliders", json::array({plate(0, 1), plate(c.length, -1)})},
          {"bodies", json::array({{{"name", "fluid"},
                                   {"material", "fluid"},
                                   {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {w, c.length, w}}}}}})}};
}

// Mean x-velocity of the particles in each layer (sorted by y), with the
// layer's mean y.
std::vector<std::pair<double, double>> layer_profile(const ParticleSet& ps, double spacing, double length) {
  const auto& x = ps.vector("position");
  const auto& v = ps.vector("velocity");
  const int layers = int(std::lround(length / spacing));
  std::vector<double> sum_v(std::size_t(layers), 0), sum_y(std::size_t(layers), 0), count(std::size_t(layers), 0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const int k = std::clamp(int(std::floor(x[i].y() / spacing)), 0, layers - 1);
    sum_v[std::size_t(k)] += v[i].x();
    sum_y[std::size_t(k)] += x[i].y();
    count[std::size_t(k)] += 1;
  }
  std::vector<std::pair<double, double>> out;
  for (int k = 0; k < layers; ++k)
    if (count[std::size_t(k)] > 0)
      out.emplace_back(sum_y[std::size_t(k)] / count[std::size_t(k)], sum_v[std::size_t(k)] / count[std::size_t(k)]);
  return out;
}

// The mean x-velocity of the two layers beside the mid-plane (a plug's speed).
double centre_speed(const ParticleSet& ps, double spacing, double length) {
  const auto profile = layer_profile(ps, spacing, length);
  return 0.5 * (profile[profile.size() / 2 - 1].second + profile[profile.size() / 2].second);
}

// Mid-plane velocity: the mean of the two layers beside y = L/2, against the
// series at their mean heights.
struct MidPlane {
  double measured = 0, expected = 0;
};
MidPlane mid_plane(const ParticleSet& ps, const Channel& c, double t) {
  const double s = c.length / c.across;
  const auto profile = layer_profile(ps, s, c.length);
  MidPlane m;
  int n = 0;
  for (const auto& [y, v] : profile)
    if (std::abs(y - 0.5 * c.length) < 0.75 * s) {
      m.measured += v;
      m.expected += poiseuille_startup(y, t, c.force, c.nu, c.length);
      ++n;
    }
  m.measured /= n;
  m.expected /= n;
  return m;
}

}  // namespace

TEST(ChannelSeries, MorrisSeriesStartsAtRestAndEndsParabolic) {
  EXPECT_NEAR(poiseuille_startup(0.5e-3, 0.0, 2e-4, 1e-6, 1e-3), 0.0, 1e-9);
  EXPECT_NEAR(poiseuille_startup(0.5e-3, 100.0, 2e-4, 1e-6, 1e-3), 2.5e-5, 1e-12);
  // The Herschel–Bulkley profile reduces to the Bingham one at n = 1.
  for (double y : {0.0, 0.01, 0.03, 0.05, 0.08})
    EXPECT_NEAR(herschel_bulkley_channel(y, 10, 1000, 50, 1.0, 250, 0.1), bingham_channel(y, 10, 1000, 50, 250, 0.1),
                1e-12);
}

class PoiseuilleStartUp : public ::testing::TestWithParam<std::tuple<std::string, int>> {};

// Issue 26: the mid-plane velocity within 2% of the series from 0.0225 s
// (Morris's first curve, 18% of the final speed) to the steady state, with
// either viscosity solver. Measured (docs/validation.md): steady-state error
// +1.1% at 10 particles across, +0.4% at 20, +0.2% at 40 (explicit).
TEST_P(PoiseuilleStartUp, MidPlaneVelocityFollowsTheSeriesWithinTwoPercent) {
  Channel c;
  c.viscosity_solver = std::get<0>(GetParam());
  c.across = std::get<1>(GetParam());
  auto sph = test_support::make_sph(sph_channel(c));
  const double times[] = {0.0225, 0.045, 0.1125, 0.225, 1.0};
  for (double t : times) {
    test_support::advance_to(*sph, t);
    const MidPlane m = mid_plane(sph->particles(), c, t);
    const double error = m.measured / m.expected - 1;
    std::printf("%d across, t = %.4f s: mid-plane %.4e m/s, series %.4e, error %+.2f%%\n", c.across, t, m.measured,
                m.expected, 100 * error);
    EXPECT_LT(std::abs(error), 0.02) << "at t = " << t;
  }
  // The steady profile, layer by layer, within 2% of the centre speed.
  const double v_max = c.force * c.length * c.length / (8 * c.nu);
  for (const auto& [y, v] : layer_profile(sph->particles(), c.length / c.across, c.length))
    EXPECT_NEAR(v, poiseuille_startup(y, 1.0, c.force, c.nu, c.length), 0.02 * v_max) << "at y = " << y;
}

INSTANTIATE_TEST_SUITE_P(SolverAndResolution, PoiseuilleStartUp,
                         ::testing::Values(std::make_tuple("explicit", 20), std::make_tuple("implicit", 10),
                                           std::make_tuple("implicit", 20)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_" + std::to_string(std::get<1>(info.param));
                         });
// The finest resolution of the convergence study (18 s explicit): run with
// --gtest_also_run_disabled_tests.
INSTANTIATE_TEST_SUITE_P(DISABLED_Fine, PoiseuilleStartUp,
                         ::testing::Values(std::make_tuple("explicit", 40), std::make_tuple("implicit", 40)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_" + std::to_string(std::get<1>(info.param));
                         });

// Issue 26: a Bingham fluid between the plates settles to the plug flow: the
// plug within 5% of its analytic velocity, the profile within 5% of the plug
// speed layer by layer. Plug half-width y₀ = b/2 (τ_y = G b/2), γ̇_r a
// hundredth of the wall shear rate, 20 particles across. The regularised
// plug takes about ten viscous times L²/ν to settle (measured: −3.3% at 5 s,
// +1.6% at 10 s, +1.4% at 20 s; at 10 particles across still −15% and rising
// at 20 s: docs/validation.md).
TEST(BinghamChannel, SphPlugVelocityAndProfileSettleWithinFivePercent) {
  Channel c;
  c.viscosity_solver = "implicit";
  c.speed_of_sound = 0.0025;  // 400 times the plug speed; steps of 8 ms
  c.max_dt = 0.01;
  const double rho = 1000, g = rho * c.force, b = 0.5 * c.length;
  c.yield_stress = g * 0.5 * b;
  const double mu = c.nu * rho;
  const double u_plug = bingham_channel(b, c.force, rho, mu, c.yield_stress, c.length);
  c.regularisation = 0.01 * u_plug / (0.5 * b);  // the wall shear rate is about u_p / (b − y₀)
  auto sph = test_support::make_sph(sph_channel(c));
  auto plug = [&] { return centre_speed(sph->particles(), c.length / c.across, c.length); };
  test_support::advance_to(*sph, 10.0);
  const double at_10 = plug();
  test_support::advance_to(*sph, 20.0);
  const double at_20 = plug();
  std::printf("plug at 10 s %.4e m/s, at 20 s %.4e, analytic %.4e: error %+.2f%%\n", at_10, at_20, u_plug,
              100 * (at_20 / u_plug - 1));
  EXPECT_NEAR(at_20 / at_10, 1.0, 0.01) << "settled";
  EXPECT_NEAR(at_20, u_plug, 0.05 * u_plug);
  for (const auto& [y, v] : layer_profile(sph->particles(), c.length / c.across, c.length))
    EXPECT_NEAR(v, bingham_channel(y, c.force, rho, mu, c.yield_stress, c.length), 0.05 * u_plug) << "at y = " << y;
}

// Issue 26: a shear wave v_x = A sin(2π y / λ) in a box periodic along all
// three axes decays as e^{−ν k² t} (k = 2π/λ). Measured: −0.21% at λ = 20
// spacings, −0.05% at 40; the thesis's uncalibrated coefficient is 1.2% low
// on the lattice (viscosity_lattice_calibration), which this test would catch.
TEST(ShearWave, DecaysAtTheViscousRateInAFullyPeriodicBox) {
  for (const int wavelength : {20, 40}) {
    const double nu = 1e-6, rho = 1000, s = 5e-5, lambda = wavelength * s, w = 6 * s;
    const double amplitude = 1e-5, k = 2 * kPi / lambda;
    auto sph = test_support::make_sph(test_support::periodic_box_scene(
        w, lambda, {{"spacing", s}, {"speed_of_sound", 0.01}, {"viscosity_solver", "explicit"}},
        {{"density", rho}, {"viscosity", nu * rho}}));
    test_support::start_shear_wave(*sph, k, amplitude);
    auto measured = [&] { return test_support::shear_wave_amplitude(*sph, k); };
    const double t_end = 1.0 / (nu * k * k);  // one e-folding
    test_support::advance_to(*sph, t_end);
    const double rate = -std::log(measured() / amplitude) / t_end, exact = nu * k * k;
    std::printf("wavelength %d spacings: decay rate %.4f 1/s, exact %.4f, error %+.2f%%\n", wavelength, rate, exact,
                100 * (rate / exact - 1));
    EXPECT_NEAR(rate / exact, 1.0, 0.005);
  }
}

// Quasi-static mass scaling in SPH (solver.mass_scaling s): every force and
// the weight accelerate the inertia s m. In the fully periodic box a shear
// wave decays at ν k²/s, with the explicit viscosity (through the kick) and
// with the implicit one (the solve's (M + (Δt/s) K) v = M v*), and the whole
// fluid falls at g/s. Measured (max_dt 5e-5 s): the decay rate at s = 4
// times 4 is 0.9993 (explicit) and 1.0013 (implicit) of the rate at s = 1,
// which are −0.72% and −0.66% from ν k²; the fall is g/s to 1e-14.
TEST(ShearWave, MassScalingDividesTheViscousDecayAndTheFallByTheScale) {
  const double nu = 1e-6, rho = 1000, s = 5e-5, lambda = 20 * s, w = 6 * s, scale = 4, g = 9.81;
  const double amplitude = 1e-5, k = 2 * kPi / lambda;
  for (const std::string solver : {"explicit", "implicit"}) {
    json scene = test_support::periodic_box_scene(
        w, lambda, {{"spacing", s}, {"speed_of_sound", 0.01}, {"viscosity_solver", solver}},
        {{"density", rho}, {"viscosity", nu * rho}}, 5e-5);
    auto decay_rate = [&](double mass_scaling) {
      scene["solver"]["mass_scaling"] = mass_scaling;
      auto sph = test_support::make_sph(scene);
      test_support::start_shear_wave(*sph, k, amplitude);
      const double t_end = mass_scaling / (nu * k * k);  // one e-folding of the scaled decay
      test_support::advance_to(*sph, t_end);
      return -std::log(test_support::shear_wave_amplitude(*sph, k) / amplitude) / t_end;
    };
    const double unscaled = decay_rate(1), scaled = decay_rate(scale);
    std::printf("%s viscosity: decay rate %.4f 1/s, with mass scaling %g %.4f (x%g: %.5f of it); nu k^2 %.4f\n",
                solver.c_str(), unscaled, scale, scaled, scale, scale * scaled / unscaled, nu * k * k);
    EXPECT_NEAR(scale * scaled / unscaled, 1.0, 0.003) << solver;
    EXPECT_NEAR(scale * scaled / (nu * k * k), 1.0, 0.01) << solver;
    // The same box under gravity, at rest: it falls as one body.
    scene["solver"]["mass_scaling"] = scale;
    scene["gravity"] = {0, -g, 0};
    auto falling = test_support::make_sph(scene);
    test_support::advance_to(*falling, 0.002);
    double fall = 0;
    for (const Vec3& v : falling->particles().vector("velocity")) fall += v.y();
    fall /= double(falling->particles().size());
    EXPECT_NEAR(-fall / (g * falling->time() / scale), 1.0, 1e-9) << solver;
  }
}

namespace {

// The same Bingham channel in MPM, at a scale where its elastic wave allows
// steps of ~0.2 ms: plates 0.1 m apart, periodic along x and z (4 cells), a
// von Mises material whose steady shear is the shared Bingham law
// (von_mises_equivalent: yield √3 τ_y, η = 2K).
json mpm_bingham_channel(int across, double yield_stress, double consistency, double force, double length,
                         double flow_index = 0) {
  const double dx = length / across, w = 4 * dx;
  const HerschelBulkley law{yield_stress, consistency, 1.0};
  const VonMisesEquivalent vm = von_mises_equivalent(law);
  // flow_index > 0: the herschel_bulkley model with the law's own numbers.
  const json plasticity =
      flow_index > 0
          ? json{{"model", "herschel_bulkley"},
                 {"yield_stress", yield_stress},
                 {"viscosity", consistency},
                 {"flow_index", flow_index}}
          : json{{"model", "von_mises"}, {"yield_stress", vm.uniaxial_yield_stress}, {"viscosity", vm.viscosity}};
  auto plate = [&](double y, double ny) {
    return json{{"name", ny > 0 ? "bottom-plate" : "top-plate"},
                {"shape", {{"type", "plane"}, {"point", {0, y, 0}}, {"normal", {0, ny, 0}}}},
                {"contact", "sticky"}};
  };
  return {{"solver", {{"type", "mpm"}, {"mpm", {{"cell_size", dx}, {"heat", "off"}, {"model", "baseline"}}}}},
          {"time", {{"end", 10.0}}},
          {"gravity", {force, 0, 0}},
          {"domain", {{"min", {0, -4 * dx, 0}}, {"max", {w, length + 4 * dx, w}}, {"periodic", {"x", "z"}}}},
          {"materials",
           {{"bingham",
             {{"density", 1000.0}, {"youngs_modulus", 1e5}, {"poisson_ratio", 0.3}, {"plasticity", plasticity}}}}},
          {"colliders", json::array({plate(0, 1), plate(length, -1)})},
          {"bodies", json::array({{{"name", "fluid"},
                                   {"material", "bingham"},
                                   {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {w, length, w}}}}}})}};
}

}  // namespace

// Issue 26: the Bingham channel in MPM, from rest (plug half the channel,
// as the SPH case): settled by 0.6 s (no change to 1 s); plug error −4.5% at
// 10 cells across, +0.14% at 20, +0.09% at 40 (Newtonian, τ_y = 0: −0.21% at
// 20, −0.03% at 40); before the wall's traction reached the first node row
// (add_wall_ghost_stress) +7.7/+6.7/+3.4% (docs/validation.md). CI runs 20
// across against 2%, every layer too; 40 across is a disabled case (25 s).
class MpmBinghamChannel : public ::testing::TestWithParam<std::tuple<int, double>> {};

TEST_P(MpmBinghamChannel, PlugSettlesAndFollowsTheAnalyticProfile) {
  const auto [across, tolerance] = GetParam();
  const double length = 0.1, rho = 1000, force = 10, consistency = 50;
  const double b = 0.5 * length, g = rho * force, yield_stress = g * 0.5 * b;
  const double u_plug = bingham_channel(b, force, rho, consistency, yield_stress, length);
  auto mpm = test_support::make_mpm(mpm_bingham_channel(across, yield_stress, consistency, force, length));
  const std::size_t count = mpm->particles().size();
  auto plug = [&] { return centre_speed(mpm->particles(), 0.5 * length / across, length); };
  test_support::advance_to(*mpm, 0.6);
  const double at_1 = plug();
  test_support::advance_to(*mpm, 1.0);
  const double at_2 = plug();
  std::printf("MPM %d across: plug %.4e m/s at 0.6 s, %.4e at 1 s, analytic %.4e: error %+.2f%%\n", across, at_1, at_2,
              u_plug, 100 * (at_2 / u_plug - 1));
  EXPECT_NEAR(at_2 / at_1, 1.0, 0.01) << "settled";
  EXPECT_EQ(mpm->particles().size(), count);
  EXPECT_NEAR(at_2, u_plug, tolerance * u_plug);
  for (const auto& [y, v] : layer_profile(mpm->particles(), 0.5 * length / across, length))
    EXPECT_NEAR(v, bingham_channel(y, force, rho, consistency, yield_stress, length), tolerance * u_plug)
        << "at y = " << y;
}

INSTANTIATE_TEST_SUITE_P(Cells, MpmBinghamChannel, ::testing::Values(std::make_tuple(20, 0.02)),
                         [](const auto& info) { return std::to_string(std::get<0>(info.param)) + "_across"; });
INSTANTIATE_TEST_SUITE_P(DISABLED_Fine, MpmBinghamChannel, ::testing::Values(std::make_tuple(40, 0.01)),
                         [](const auto& info) { return std::to_string(std::get<0>(info.param)) + "_across"; });

// Issue 26: a shear-thinning Herschel–Bulkley fluid (n = 0.5) in the same MPM
// channel with the herschel_bulkley plasticity model (the shared law's
// return): τ_y = 250 Pa (plug half the channel), K = 93 Pa·s^0.5 (analytic
// plug 0.0602 m/s, wall shear rate 7.2/s). Through this model n = 1, K = 50
// gives the von Mises channel's plug to the last digit. Measured plug error
// −1.8% at 20 cells across, −0.19% at 40 (docs/validation.md; +15.8% and
// +9.9% before the wall ghosts: the missing wall traction counts three times
// the Bingham one here because the plug speed goes as (b − y₀)^{1+1/n}). CI
// checks 20 across against the 5%, the disabled case 40 across
// against 1%.
class MpmHerschelBulkleyChannel : public ::testing::TestWithParam<std::tuple<int, double>> {};

TEST_P(MpmHerschelBulkleyChannel, ShearThinningPlugSettlesOnTheAnalyticProfile) {
  const auto [across, tolerance] = GetParam();
  const double length = 0.1, rho = 1000, force = 10, consistency = 93, n = 0.5;
  const double b = 0.5 * length, yield_stress = rho * force * 0.5 * b;
  const double u_plug = herschel_bulkley_channel(b, force, rho, consistency, n, yield_stress, length);
  auto mpm = test_support::make_mpm(mpm_bingham_channel(across, yield_stress, consistency, force, length, n));
  auto plug = [&] { return centre_speed(mpm->particles(), 0.5 * length / across, length); };
  test_support::advance_to(*mpm, 0.75);
  const double early = plug();
  test_support::advance_to(*mpm, 1.25);
  const double late = plug();
  std::printf(
      "MPM Herschel-Bulkley n = 0.5, %d across: plug %.4e m/s at 0.75 s, %.4e at 1.25 s, analytic %.4e: "
      "error %+.2f%%\n",
      across, early, late, u_plug, 100 * (late / u_plug - 1));
  EXPECT_NEAR(late / early, 1.0, 0.01) << "settled";
  EXPECT_NEAR(late, u_plug, tolerance * u_plug);
  for (const auto& [y, v] : layer_profile(mpm->particles(), 0.5 * length / across, length))
    EXPECT_NEAR(v, herschel_bulkley_channel(y, force, rho, consistency, n, yield_stress, length), tolerance * u_plug)
        << "at y = " << y;
}

INSTANTIATE_TEST_SUITE_P(Cells, MpmHerschelBulkleyChannel, ::testing::Values(std::make_tuple(20, 0.05)),
                         [](const auto& info) { return std::to_string(std::get<0>(info.param)) + "_across"; });
INSTANTIATE_TEST_SUITE_P(DISABLED_Fine, MpmHerschelBulkleyChannel, ::testing::Values(std::make_tuple(40, 0.01)),
                         [](const auto& info) { return std::to_string(std::get<0>(info.param)) + "_across"; });

// Issue 26, moving no-slip walls: plane Couette flow. The top plate slides
// along x at U (a keyframed sticky plane), no body force; the steady profile
// is u = U y / L in both solvers, the wall's velocity reaching the flow
// through the SPH viscous wall term and MPM's mirrored nodes.
TEST(CouetteFlow, ASlidingStickyPlateDragsALinearProfileInBothSolvers) {
  const double speed = 1e-5;  // SPH: m/s (L = 1 mm, ν = 1e-6: steady after ~L²/ν = 1 s)
  Channel c;
  c.force = 0;
  json sph_scene = sph_channel(c);
  sph_scene["colliders"][1]["motion"] = {
      {"keyframes", json::array({{{"time", 0}}, {{"time", 10}, {"translation", {10 * speed, 0, 0}}}})}};
  auto sph = test_support::make_sph(sph_scene);
  test_support::advance_to(*sph, 2.0);
  double worst = 0;
  for (const auto& [y, v] : layer_profile(sph->particles(), c.length / c.across, c.length)) {
    EXPECT_NEAR(v, speed * y / c.length, 0.01 * speed) << "SPH at y = " << y;
    worst = std::max(worst, std::abs(v - speed * y / c.length) / speed);
  }
  std::printf("SPH Couette: largest layer error %.2f%% of U\n", 100 * worst);

  // MPM at its own scale: plates 0.1 m apart, K = 50 Pa s (ν = 0.05 m²/s), U = 0.1 m/s.
  const double length = 0.1, mpm_speed = 0.1;
  json mpm_scene = mpm_bingham_channel(20, 0.0, 50.0, 0.0, length);
  mpm_scene["colliders"][1]["motion"] = {
      {"keyframes", json::array({{{"time", 0}}, {{"time", 10}, {"translation", {10 * mpm_speed, 0, 0}}}})}};
  auto mpm = test_support::make_mpm(mpm_scene);
  test_support::advance_to(*mpm, 1.0);
  worst = 0;
  for (const auto& [y, v] : layer_profile(mpm->particles(), 0.5 * length / 20, length)) {
    EXPECT_NEAR(v, mpm_speed * y / length, 0.01 * mpm_speed) << "MPM at y = " << y;
    worst = std::max(worst, std::abs(v - mpm_speed * y / length) / mpm_speed);
  }
  std::printf("MPM Couette: largest layer error %.2f%% of U\n", 100 * worst);
}

// Studies of the stress-form viscosity (solver.sph.viscosity_operator
// "stress") beside sticky walls, a known defect (docs/validation.md,
// "The stress form beside sticky walls"; the scene loader warns). Its
// corrected gradient is exact for linear fields from the particles on one
// side of a wall, so it does not see the wall's velocity, and a mode that
// alternates layer by layer costs it no dissipation: the wall's drag excites
// it. Run with --gtest_also_run_disabled_tests; each prints its profile.
namespace {
void print_profile(const char* label, const ParticleSet& ps, double spacing, double length,
                   const std::function<double(double)>& expected) {
  std::printf("%s, layer speed over the analytic one from the wall to the centre:", label);
  const auto profile = layer_profile(ps, spacing, length);
  for (std::size_t k = 0; k < profile.size() / 2; ++k)
    std::printf(" %.3f", profile[k].second / expected(profile[k].first));
  std::printf("\n");
}
}  // namespace

// The Poiseuille channel of PoiseuilleStartUp (20 across, implicit) with the
// stress form, steady at 1 s: 1.026, 0.709, 0.988, 0.875, 0.980, 0.922, ...,
// 0.958 at the centre (the Laplacian operator: 1.025, 1.011, ..., 1.004).
TEST(StressViscosity, DISABLED_PoiseuilleBetweenStickyPlatesStudy) {
  Channel c;
  c.viscosity_solver = "implicit";
  json scene = sph_channel(c);
  scene["solver"]["sph"]["viscosity_operator"] = "stress";
  auto sph = test_support::make_sph(scene);
  test_support::advance_to(*sph, 1.0);
  print_profile("stress-form Poiseuille", sph->particles(), c.length / c.across, c.length,
                [&](double y) { return poiseuille_startup(y, 1.0, c.force, c.nu, c.length); });
}

// The MPM Bingham channel's numbers (plates 0.1 m apart, F 10 m/s², K 50
// Pa·s, τ_y 250 Pa, G 38.5 kPa, plug 0.0625 m/s) with the elastoviscoplastic
// form and the stress form, 20 across, speed of sound 2 m/s: the plug runs at
// about 2.8 times its speed (0.17–0.18 m/s from 0.3 s), the wall layer slips
// at 0.05 m/s (0.012 analytic). The regularised form with the Laplacian
// operator in the same channel: +1.0% at 1.5 s.
TEST(StressViscosity, DISABLED_ElastoviscoplasticBinghamChannelStudy) {
  Channel c;
  c.length = 0.1;
  c.force = 10;
  c.nu = 0.05;
  c.viscosity_solver = "implicit";
  c.speed_of_sound = 2.0;
  c.max_dt = 0.002;
  c.yield_stress = 250;
  c.regularisation = 0.025;
  json scene = sph_channel(c);
  auto& sph = scene["solver"]["sph"];
  sph["viscosity_operator"] = "stress";
  sph["elasticity_solver"] = "implicit";
  sph["negative_pressure"] = "keep";
  auto& m = scene["materials"]["fluid"];
  m["elasticity"] = 2 * 1e5 / 2.6;  // μ_e = 2G of MPM's E = 10⁵ Pa, ν = 0.3
  m["herschel_bulkley"] = {{"yield_stress", c.yield_stress}, {"form", "elastoviscoplastic"}};
  auto solver = test_support::make_sph(scene);
  const double rho = 1000, mu = c.nu * rho;
  for (double t : {0.3, 0.6, 1.0, 1.5}) {
    test_support::advance_to(*solver, t);
    char label[64];
    std::snprintf(label, sizeof label, "elastoviscoplastic channel at %.1f s", t);
    print_profile(label, solver->particles(), c.length / c.across, c.length,
                  [&](double y) { return bingham_channel(y, c.force, rho, mu, c.yield_stress, c.length); });
  }
}
