// The laws both solvers share, each tested alone: the oven and bake clock,
// collider temperatures, the surface exchange, the contact law, the health
// scan; the SPH pair terms; the MPM grid (B-spline weights, block colouring).
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <map>
#include <mutex>
#include <set>

#include <Eigen/Dense>

#include "core/errors.hpp"
#include "core/health.hpp"
#include "core/pcg.hpp"
#include "core/quantity.hpp"
#include "sim/bake_stats.hpp"
#include "geometry/contact.hpp"
#include "mpm/grid.hpp"
#include "physics/moisture.hpp"
#include "physics/heat.hpp"
#include "physics/mass_scaling.hpp"
#include "physics/oven.hpp"
#include "physics/rheology.hpp"
#include "sph/forces/artificial_stress.hpp"
#include "sph/forces/artificial_viscosity.hpp"
#include "sph/forces/maxwell.hpp"
#include "sph/forces/pressure.hpp"
#include "sph/forces/surface_tension.hpp"
#include "sph/forces/viscosity.hpp"

using namespace bakesim;

// Mass scaling: the inertia s m takes a force's impulse over Δt/s and its
// waves (speed sqrt(E/(s ρ))) are sqrt(s) times slower; s = 1 changes nothing.
TEST(MassScaling, ImpulseStepAndWaveSlowdown) {
  const MassScaling none, four{4.0};
  EXPECT_FALSE(none.active());
  EXPECT_EQ(none.impulse_step(1e-4), 1e-4);
  EXPECT_EQ(none.wave_slowdown(), 1.0);
  EXPECT_TRUE(four.active());
  EXPECT_DOUBLE_EQ(four.impulse_step(1e-4), 2.5e-5);
  EXPECT_DOUBLE_EQ(four.wave_slowdown(), 2.0);
}

TEST(Oven, BakeClockScalesTimeAndReadsTheScheduleInBakeTime) {
  Oven oven;
  oven.bake_time_scale = 600;
  oven.air_temperature = PiecewiseLinear({{0.0, 20.0}, {1200.0, 220.0}});
  EXPECT_DOUBLE_EQ(oven.bake_time(1.5), 900.0);
  EXPECT_DOUBLE_EQ(oven.bake_step(1e-3), 0.6);
  // 1 s of mechanics is 600 s of bake: half way up the ramp.
  EXPECT_DOUBLE_EQ(oven.air_at(1.0), 120.0);
  EXPECT_DOUBLE_EQ(oven.air_at(5.0), 220.0);  // held after the last point
}

TEST(Oven, ColliderTemperaturesAreReadOncePerBakeTimeAndZeroWithoutASchedule) {
  std::vector<std::optional<PiecewiseLinear>> schedules = {PiecewiseLinear({{0.0, 100.0}, {100.0, 200.0}}),
                                                           std::nullopt, PiecewiseLinear::constant(180.0)};
  ColliderTemperatures t;
  t.read(
      schedules.size(), [&](std::size_t i) -> const auto& { return schedules[i]; }, 50.0);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_DOUBLE_EQ(t[0], 150.0);
  EXPECT_DOUBLE_EQ(t[1], 0.0);
  EXPECT_DOUBLE_EQ(t[2], 180.0);
}

// A particle δ below the face: in steady drying the profile is linear, and
// the face saturation s_f = s − q δ/(D ρ_w) with q = E s_f gives the flux.
TEST(Moisture, EvaporationBelowTheFaceIsDiffusionInSeriesWithTheSurfaceLaw) {
  Moisture w;
  w.saturation = 0.5, w.diffusivity = 1e-8, w.evaporation_rate = 5e-3;
  const double theta = 100, s = 0.4, depth = 1e-3;
  const double q = w.evaporation_flux_below(theta, s, depth);
  const double face = s - q * depth / (w.diffusivity * w.water_density);
  EXPECT_NEAR(q, w.evaporation_flux(theta, face), 1e-15);
  EXPECT_NEAR(q, w.evaporation_flux(theta, s) / 1.5, 1e-15);  // E δ/(D ρ_w) = 0.5
  EXPECT_EQ(w.evaporation_flux_below(theta, s, 0.0), w.evaporation_flux(theta, s));
  w.diffusivity = 0;  // water that cannot move evaporates where it is
  EXPECT_EQ(w.evaporation_flux_below(theta, s, depth), w.evaporation_flux(theta, s));
}

TEST(SurfaceExchange, SumsPartsAndRelaxesExactlyTowardsTheOutside) {
  SurfaceExchange e;
  e.add(2e-4, 10.0, 200.0);   // air: 2 cm², 10 W/m²K, 200 °C
  e.add(1e-4, 500.0, 180.0);  // a hot tray under part of it
  EXPECT_NEAR(e.conductance, 2e-3 + 5e-2, 1e-15);
  // q = Σ β A (θ_c − θ) at θ = 20 °C.
  EXPECT_NEAR(e.heat_rate(20.0), 2e-3 * 180.0 + 5e-2 * 160.0, 1e-12);
  // Lumped particle, one outside: θ(t) = θ_out + (θ0 − θ_out) e^{−βA t / C}.
  const Real c = 0.5, beta = 10, area = 1e-3, dt = 7.0;
  const Real exact = 200.0 + (20.0 - 200.0) * std::exp(-beta * area * dt / c);
  EXPECT_NEAR(SurfaceExchange::relax(20.0, 200.0, beta, area, c, dt), exact, 1e-12);
  // Never overshoots, whatever the step.
  EXPECT_LE(SurfaceExchange::relax(20.0, 200.0, beta, area, c, 1e9), 200.0);
  EXPECT_GT(SurfaceExchange::relax(20.0, 200.0, beta, area, c, 1e9), 199.999);
}

TEST(ContactLaw, ModesFrictionModelsAndDamping) {
  const Vec3 n = Vec3::UnitY();
  const Vec3 in(3.0, -2.0, 0.0), out(3.0, 2.0, 0.0);
  Vec3 v = in;
  apply_contact(v, n, {ContactMode::sticky, FrictionModel::coulomb, 0.0, 1.0});
  EXPECT_EQ(v, Vec3::Zero());
  // separate: only an approaching velocity is changed; slip: both ways.
  v = out;
  apply_contact(v, n, {ContactMode::separate, FrictionModel::coulomb, 0.5, 1.0});
  EXPECT_EQ(v, out);
  v = out;
  apply_contact(v, n, {ContactMode::slip, FrictionModel::coulomb, 0.0, 1.0});
  EXPECT_EQ(v, Vec3(3.0, 0.0, 0.0));
  // Coulomb: |v_t| shrinks by μ |v_n| = 0.5 · 2 = 1, never past zero.
  v = in;
  apply_contact(v, n, {ContactMode::separate, FrictionModel::coulomb, 0.5, 1.0});
  EXPECT_NEAR((v - Vec3(2.0, 0.0, 0.0)).norm(), 0.0, 1e-15);
  v = in;
  apply_contact(v, n, {ContactMode::separate, FrictionModel::coulomb, 10.0, 1.0});
  EXPECT_EQ(v, Vec3::Zero());
  // Velocity share (thesis Eq 3.33): v = (1 − f) v_t − (1 − d) v_n.
  v = in;
  apply_contact(v, n, {ContactMode::separate, FrictionModel::velocity_share, 0.25, 0.5});
  EXPECT_NEAR((v - Vec3(2.25, 1.0, 0.0)).norm(), 0.0, 1e-15);
  // Damping 0 bounces elastically, Coulomb too.
  v = in;
  apply_contact(v, n, {ContactMode::separate, FrictionModel::coulomb, 0.0, 0.0});
  EXPECT_NEAR((v - out).norm(), 0.0, 1e-15);
}

TEST(Health, FirstInvalidIsTheLowestBadIndexOnAnyChunking) {
  std::vector<double> x(20000, 1.0);
  EXPECT_EQ(first_invalid(x.size(), [&](std::size_t i) { return std::isfinite(x[i]); }), x.size());
  x[17001] = NAN;
  x[9000] = INFINITY;
  EXPECT_EQ(first_invalid(x.size(), [&](std::size_t i) { return std::isfinite(x[i]); }), 9000u);
}

TEST(SphForces, PairTermsAreEqualAndOppositeSoMomentumIsConserved) {
  // ∇_i W_ij = −∇_j W_ji; every symmetric pair term then cancels in Σ m a.
  const Vec3 grad(0.3, -1.2, 0.5);
  const Real mi = 2e-3, mj = 3e-3;
  const Vec3 fij = mi * sph::forces::pressure_gradient(mj, 4.0, 7.0, grad);
  const Vec3 fji = mj * sph::forces::pressure_gradient(mi, 7.0, 4.0, -grad);
  EXPECT_NEAR((fij + fji).norm(), 0.0, 1e-15);
  Mat3 si, sj;
  si << 1, 2, 3, 2, 5, 6, 3, 6, 9;
  sj << -4, 1, 0, 1, 2, -1, 0, -1, 3;
  const Vec3 gij = mi * sph::forces::stress_divergence(mj, si, sj, grad);
  const Vec3 gji = mj * sph::forces::stress_divergence(mi, sj, si, -grad);
  EXPECT_NEAR((gij + gji).norm(), 0.0, 1e-15);
  // The pressure term is m_j (P_i/ρ_i² + P_j/ρ_j²) ∇W.
  EXPECT_NEAR((sph::forces::pressure_gradient(mj, 4.0, 7.0, grad) - mj * 11.0 * grad).norm(), 0.0, 1e-15);
}

TEST(SphForces, ViscosityWeightIsNonNegativeAndVanishesAtTheSupport) {
  const Real h = 0.02, c = 45.0 / (kPi * std::pow(h, 6));
  EXPECT_NEAR(sph::forces::viscosity_weight(1.0, 3.0, 1e-6, c, h, h), 0.0, 1e-300);
  const Real w = sph::forces::viscosity_weight(1.0, 3.0, 1e-6, c, h, 0.5 * h);
  EXPECT_NEAR(w, 2.0 * 1e-6 * c * 0.5 * h, 1e-9 * w);
  EXPECT_GT(w, 0.0);
}

TEST(SphForces, ArtificialViscosityActsOnlyOnApproachingPairs) {
  const Vec3 x_ij(0.01, 0, 0);
  const Real r = 0.01, h = 0.02, eps_h2 = 0.01 * h * h;
  // Receding: zero.
  EXPECT_EQ(sph::forces::artificial_viscosity(Vec3(1, 0, 0), x_ij, r, h, eps_h2, 1000, 1000, 1, 1, 20), 0.0);
  // Approaching at 1 m/s: φ = h v·x / (r² + εh²), Π = (−α c φ + β φ²)/ρ̄.
  const Real phi = h * (-0.01) / (r * r + eps_h2);
  const Real expected = (-1.0 * 20.0 * phi + 2.0 * phi * phi) / 1000.0;
  const Real pi = sph::forces::artificial_viscosity(Vec3(-1, 0, 0), x_ij, r, h, eps_h2, 900, 1100, 1, 2, 20);
  EXPECT_NEAR(pi, expected, 1e-12 * std::abs(expected));
  EXPECT_GT(pi, 0.0);
}

TEST(SphForces, ArtificialStressOnlyOpposesTension) {
  Mat3 compress = -5.0 * Mat3::Identity();
  EXPECT_NEAR(sph::forces::artificial_stress_tensor(compress, 0.0, 0.3).norm(), 0.0, 1e-12);
  // Uniaxial tension σ_xx = 10 (over ρ²): R = diag(−ε 10, 0, 0).
  Mat3 tension = Mat3::Zero();
  tension(0, 0) = 10.0;
  const Mat3 r = sph::forces::artificial_stress_tensor(tension, 0.0, 0.3);
  EXPECT_NEAR(r(0, 0), -3.0, 1e-12);
  EXPECT_NEAR(r.norm(), 3.0, 1e-12);
  // A positive pressure cancels the tension: (S − P I) = 0 along x.
  EXPECT_NEAR(sph::forces::artificial_stress_tensor(tension, 10.0, 0.3).norm(), 0.0, 1e-12);
  // The pair term with f^n (n = 4 and a general n agree at n = 4).
  const Vec3 grad(1, 0, 0);
  const Vec3 a4 = sph::forces::artificial_stress(2.0, 0.5, 4.0, r, r, grad);
  EXPECT_NEAR((a4 - 2.0 * 0.0625 * (2.0 * r * grad)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((sph::forces::artificial_stress(2.0, 0.5, 3.0, r, r, grad) - 2.0 * 0.125 * (2.0 * r * grad)).norm(), 0.0,
              1e-15);
}

TEST(SphForces, SurfaceTensionPullsAlongTheNormalByTheCurvature) {
  const Vec3 normal(0, 40, 0);  // ∇C into the fluid
  // ∇²C < 0 at a convex surface: the pull points into the fluid (along N).
  const Vec3 a = sph::forces::surface_tension(0.07, 1000, -5e3, normal, 40.0);
  EXPECT_NEAR(a.y(), 0.07 / 1000 * 5e3, 1e-12);
  EXPECT_EQ(a.x(), 0.0);
}

TEST(MpmGrid, QuadraticBSplineWeightsArePartitionOfUnityAndReproduceLinears) {
  for (Real x : {3.0, 3.25, 3.5, 3.77, 4.499}) {
    const mpm::Axis a = mpm::axis_weights(x);
    Real sum = 0, first = 0;
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(a.w[k], 0.0);
      sum += a.w[k];
      first += a.w[k] * (a.base + k);  // Σ w x_i = x_p
    }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    EXPECT_NEAR(first, x, 1e-14);
    // Second moment Σ w (x_i − x_p)² = 1/4 (the D = Δx²/4 of APIC).
    Real second = 0;
    for (int k = 0; k < 3; ++k) second += a.w[k] * (k - a.frac) * (k - a.frac);
    EXPECT_NEAR(second, 0.25, 1e-14);
  }
}

TEST(MpmGrid, BlocksOfOneColourNeverShareANodeAndTheOrderIsAPermutation) {
  mpm::BlockOrder blocks;
  const int n = 33;  // nodes per axis
  blocks.resize(n, n, n);
  std::vector<Vec3> x;
  for (int i = 0; i < 4000; ++i)
    x.emplace_back(1.0 + 0.007 * (i % 29) * 1.1, 1.0 + 0.003 * (i % 97), 1.0 + 0.0011 * (i % 211));
  const Vec3 origin(0.97, 0.97, 0.97);
  const Real inv_dx = 100.0;
  blocks.sort(x, origin, inv_dx);
  blocks.colour();
  std::vector<std::uint32_t> order = blocks.order();
  std::sort(order.begin(), order.end());
  for (std::size_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i);
  // Every particle is visited once, blocks of one colour have the colour's
  // parity, and within one colour no node is reached from two blocks.
  std::vector<int> visits(x.size(), 0);
  for (std::size_t colour = 0; colour < blocks.colour_blocks().size(); ++colour)
    for (std::uint32_t b : blocks.colour_blocks()[colour]) {
      std::size_t ijk[3];
      blocks.block_index(b, ijk);
      for (int d = 0; d < 3; ++d) EXPECT_EQ(ijk[d] & 1, (colour >> d) & 1);
    }
  std::mutex mutex;
  std::map<std::size_t, std::pair<std::size_t, long>> owner;  // node -> (colour, block)
  blocks.for_each_by_colour(
      x, origin, inv_dx, [&](std::uint32_t p, const mpm::Axis& ax, const mpm::Axis& ay, const mpm::Axis& az) {
        std::lock_guard<std::mutex> lock(mutex);
        ++visits[p];
        const long block =
            (long(std::max(0, ax.base) / 4) * 9 + std::max(0, ay.base) / 4) * 9 + std::max(0, az.base) / 4;
        const std::size_t colour = (std::max(0, ax.base) / 4 & 1) | ((std::max(0, ay.base) / 4 & 1) << 1) |
                                   ((std::max(0, az.base) / 4 & 1) << 2);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
              const std::size_t node = (std::size_t(ax.base + i) * n + (ay.base + j)) * n + (az.base + k);
              auto [it, fresh] = owner.try_emplace(node, colour, block);
              if (!fresh && it->second.first == colour) {
                EXPECT_EQ(it->second.second, block) << "node " << node;
              }
              if (!fresh) it->second = {colour, block};
            }
      });
  for (int v : visits) EXPECT_EQ(v, 1);
}

TEST(ParticleQuantity, ResolvesAttributesAndVelocityPartsByName) {
  ParticleSet ps;
  auto& t = ps.add_scalar("temperature", "degC");
  auto& v = ps.add_vector("velocity", "m/s");
  ps.resize(2);
  t = {20.0, 95.0};
  v = {Vec3(3, 4, 0), Vec3(0, -1, 2)};
  EXPECT_EQ(ParticleQuantity::resolve(ps, "temperature", "probes")(1), 95.0);
  EXPECT_EQ(ParticleQuantity::resolve(ps, "speed", "probes")(0), 5.0);
  EXPECT_EQ(ParticleQuantity::resolve(ps, "velocity_z", "probes")(1), 2.0);
  try {
    ParticleQuantity::resolve(ps, "gas_pressure", "scene.json: probes[0].quantities[1]");
    FAIL();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("probes[0].quantities[1]"), std::string::npos) << msg;
    EXPECT_NE(msg.find("temperature, speed, velocity_x"), std::string::npos) << msg;
  }
}

TEST(BakeStatistics, CoreIsTheColdestCrustIsAreaWeightedAndMoistureIsMeasuredFromTheStart) {
  ParticleSet ps;
  auto& t = ps.add_scalar("temperature", "degC");
  auto& area = ps.add_scalar("air_area", "m^2");
  auto& water = ps.add_scalar("water_mass", "kg");
  auto& body = ps.add_int("body_id");
  auto& mass = ps.add_scalar("mass", "kg");
  ps.resize(5);
  body = {0, 0, 0, 1, 1};
  mass = {3e-3, 3e-3, 4e-3, 8e-3, 1e-3};
  t = {30, 80, 120, 50, 60};
  area = {0, 1e-4, 3e-4, 2e-4, 0};
  water = {1e-3, 1e-3, 2e-3, 4e-3, 0};
  const BakeStatistics stats(ps, 2);
  EXPECT_TRUE(stats.has_water());
  EXPECT_FALSE(stats.has_co2());
  EXPECT_EQ(stats.columns("loaf"),
            (std::vector<std::string>{"core_temperature:loaf", "crust_temperature:loaf", "water:loaf",
                                      "moisture_loss_percent:loaf", "weight_loss_percent:loaf"}));
  water[2] = 0.5e-3;  // the crust dries: 1.5 g of the loaf's 4 g gone
  const std::vector<BodyBake> b = stats.compute(ps);
  EXPECT_EQ(b[0].core_temperature, 30.0);
  EXPECT_NEAR(b[0].crust_temperature, (1e-4 * 80 + 3e-4 * 120) / 4e-4, 1e-12);
  EXPECT_NEAR(b[0].moisture_loss_percent, 37.5, 1e-12);
  EXPECT_NEAR(b[0].weight_loss_percent, 15.0, 1e-12);  // 1.5 g of the loaf's 10 g
  EXPECT_EQ(b[1].core_temperature, 50.0);
  EXPECT_NEAR(b[1].crust_temperature, 50.0, 1e-12);
  EXPECT_NEAR(b[1].moisture_loss_percent, 0.0, 1e-12);
}

TEST(BakeStatistics, CrustIsTheDoughDriedAtTheBoilingPointSpreadOverTheExchangeArea) {
  // SPH-like particles of 1 cm³ (m/ρ), moisture X₀ = 0.8: a boiling surface particle that lost
  // half its water, a dry one past 100 °C, a crumb particle at 90 °C that lost some to vapour.
  ParticleSet ps;
  auto& t = ps.add_scalar("temperature", "degC");
  auto& area = ps.add_scalar("surface_area", "m^2");
  auto& water = ps.add_scalar("water_mass", "kg");
  auto& moisture = ps.add_scalar("moisture", "kg/kg");
  auto& body = ps.add_int("body_id");
  auto& mass = ps.add_scalar("mass", "kg");
  auto& density = ps.add_scalar("density", "kg/m^3");
  ps.resize(3);
  body = {0, 0, 0};
  mass = {1e-3, 1e-3, 1e-3};
  density = {1000, 1000, 1000};
  moisture = {0.8, 0.8, 0.8};
  water = {4e-4, 4e-4, 4e-4};
  t = {20, 20, 20};
  area = {0, 0, 0};
  const BakeStatistics stats(ps, 1);
  EXPECT_TRUE(stats.has_moisture());
  const std::vector<std::string> columns = stats.columns("roll");
  EXPECT_EQ(std::vector<std::string>(columns.end() - 3, columns.end()),
            (std::vector<std::string>{"crust_thickness:roll", "crust_moisture:roll", "crumb_moisture:roll"}));
  const Real face = 1e-4;  // the full cross-section of a 1 cm cube
  moisture = {0.4, 0.0, 0.6};
  t = {100, 130, 90};
  area = {face, 0.5 * face, 0};
  const BodyBake b = stats.compute(ps)[0];
  // Dried at or past boiling: half of the first, all of the second; the crumb's loss is not crust.
  EXPECT_NEAR(b.crust_thickness, (0.5e-6 + 1e-6) / (1.5 * face), 1e-12);
  // Outer shares 1, 0.5, 0.
  EXPECT_NEAR(b.crust_moisture, (1 * 0.4 + 0.5 * 0.0) / 1.5, 1e-12);
  EXPECT_NEAR(b.crumb_moisture, (0.5 * 0.0 + 1 * 0.6) / 1.5, 1e-12);
  // Each body's crust starts at its own material's boiling point: the crumb particle at 90 °C,
  // in a body whose water boils at 88 °C (a material's moisture.boiling_point), has dried there.
  body = {0, 0, 1};
  area = {face, 0.5 * face, face};
  ParticleSet start = ps;
  start.scalar("moisture") = {0.8, 0.8, 0.8};
  const std::vector<BodyBake> own = BakeStatistics(start, std::vector<Real>{100, 88}).compute(ps);
  EXPECT_NEAR(own[0].crust_thickness, (0.5e-6 + 1e-6) / (1.5 * face), 1e-12);
  EXPECT_NEAR(own[1].crust_thickness, 0.25e-6 / face, 1e-12);  // a quarter of its water gone
  const std::vector<BodyBake> oven = BakeStatistics(start, 2, 100).compute(ps);
  EXPECT_EQ(oven[1].crust_thickness, 0);
}

TEST(Pcg, SolvesScalarAndThreeComponentSystemsAndReportsWhatFailed) {
  // A = tridiag(−1, 2 + c, −1), SPD; compare with Eigen's dense solve.
  const std::size_t n = 40;
  const Real c = 0.1;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t i = 0; i < n; ++i) {
    a(i, i) = 2 + c;
    if (i > 0) a(i, i - 1) = a(i - 1, i) = -1;
  }
  std::vector<Real> diag(n, 2 + c);
  auto apply = [&](const auto& in, auto& out) {
    for (std::size_t i = 0; i < n; ++i) {
      out[i] = (2 + c) * in[i];
      if (i > 0) out[i] -= in[i - 1];
      if (i + 1 < n) out[i] -= in[i + 1];
    }
  };
  Eigen::VectorXd b1(n);
  std::vector<Real> b(n), x(n, 0.0);
  std::vector<Vec3> b3(n), x3(n, Vec3::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    b1[i] = b[i] = std::sin(0.3 * i) + 1;
    b3[i] = Vec3(b[i], -2 * b[i], 0.0);  // the third system is already solved by x = 0
  }
  const Eigen::VectorXd exact = a.ldlt().solve(b1);
  PcgScratch<Real> w;
  const auto all = [](std::size_t) { return true; };
  const PcgResult<Real> r = solve_pcg<Real>(n, apply, all, diag, b, x, 1e-24, 200, w);
  EXPECT_TRUE(r.converged());
  for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(x[i], exact[i], 1e-9);
  PcgScratch<Vec3> w3;
  const PcgResult<Vec3> r3 = solve_pcg<Vec3>(n, apply, all, diag, b3, x3, Vec3::Constant(1e-24), 200, w3);
  EXPECT_TRUE(r3.converged());
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(x3[i].x(), exact[i], 1e-9);
    EXPECT_NEAR(x3[i].y(), -2 * exact[i], 1e-9);
    EXPECT_EQ(x3[i].z(), 0.0);
  }
  // Two iterations cannot reach 1e-12: not acceptable, and the error names the setting.
  std::vector<Real> x2(n, 0.0);
  const PcgResult<Real> short_run = solve_pcg<Real>(n, apply, all, diag, b, x2, 1e-24, 2, w);
  EXPECT_EQ(short_run.iterations, 2);
  EXPECT_FALSE(short_run.acceptable());
  EXPECT_THROW(require_acceptable(
                   short_run, 1.0, [] { return std::string("test solve"); }, "max_iterations"),
               SimulationError);
}

TEST(PairConduction, FlowsFromHotToColdAndIsAntisymmetric) {
  // Cubic spline slope at r = h/2 is negative: W'(r)/r < 0.
  const Real dwr = -3.0e5, r = 0.01, eta2 = 0.01 * 0.02 * 0.02;
  const Real into_hot = pair_conduction(1e-6, 0.5, 0.5, 180.0, 20.0, dwr, r, eta2);
  const Real into_cold = pair_conduction(1e-6, 0.5, 0.5, 20.0, 180.0, dwr, r, eta2);
  EXPECT_LT(into_hot, 0.0);  // the hot particle loses heat
  EXPECT_DOUBLE_EQ(into_hot, -into_cold);
  EXPECT_NEAR(into_hot, 1e-6 * 1.0 * 160.0 * (dwr * r * r) / (r * r + eta2), 1e-15);
  EXPECT_EQ(pair_conduction(1e-6, 0.5, 0.5, 50.0, 50.0, dwr, r, eta2), 0.0);
}

// The Herschel–Bulkley law (physics/rheology.hpp): its apparent viscosity is
// τ/γ̇ of the law well above γ̇_r, finite at rest (τ_y/γ̇_r + K γ̇_r^{n−1}),
// and never increasing with the shear rate for n ≤ 1.
TEST(Rheology, HerschelBulkleyApparentViscosityIsTheLawAboveTheRegularisationRate) {
  const HerschelBulkley law{50.0, 8.0, 0.5, 1e-3};
  for (const Real rate : {0.1, 1.0, 10.0, 100.0}) {
    const Real exact = (50.0 + 8.0 * std::sqrt(rate)) / rate;
    EXPECT_NEAR(law.apparent_viscosity(rate), exact, 1e-9 * exact) << "at " << rate;
    EXPECT_NEAR(law.shear_stress(rate), 50.0 + 8.0 * std::sqrt(rate), 1e-12);
  }
  EXPECT_NEAR(law.viscosity_at_rest(), 50.0 / 1e-3 + 8.0 * std::pow(1e-3, -0.5), 1e-6);
  // At γ̇ = γ̇_r the yield part is τ_y (1 − 1/e)/γ̇_r.
  EXPECT_NEAR(law.apparent_viscosity(1e-3), 50.0 * (1 - std::exp(-1.0)) / 1e-3 + 8.0 * std::pow(1e-3, -0.5), 1e-6);
  Real previous = law.apparent_viscosity(0);
  for (Real rate = 1e-6; rate < 1e3; rate *= 1.5) {
    const Real mu = law.apparent_viscosity(rate);
    EXPECT_LE(mu, previous * (1 + 1e-12)) << "at " << rate;
    previous = mu;
  }
  // Newtonian and Bingham limits.
  const HerschelBulkley newtonian{0.0, 2.0, 1.0}, bingham{10.0, 2.0, 1.0, 1e-4};
  EXPECT_DOUBLE_EQ(newtonian.apparent_viscosity(5.0), 2.0);
  EXPECT_NEAR(bingham.apparent_viscosity(5.0), 2.0 + 10.0 / 5.0, 1e-9);
  const VonMisesEquivalent vm = von_mises_equivalent(HerschelBulkley{10.0, 2.0, 1.0});
  EXPECT_NEAR(vm.uniaxial_yield_stress, 10.0 * std::sqrt(3.0), 1e-12);
  EXPECT_DOUBLE_EQ(vm.viscosity, 4.0);
}

// The overstress return of a yield-surface solver: in steady shear (the same
// elastic shear increment G γ̇ dt added each step, the return applied) the
// stress settles at τ_y + K γ̇ⁿ exactly, for any n and any step; the step
// equation itself holds to round-off; n = 1 is the closed form.
TEST(Rheology, RelaxedOverstressGivesTheHerschelBulkleyStressInSteadyShear) {
  const Real shear_modulus = 4e4, yield = 50;
  for (const Real n : {0.4, 1.0, 1.8})
    for (const Real dt : {1e-5, 1e-3}) {
      const HerschelBulkley law{yield, 8.0, n};
      for (const Real rate : {0.5, 3.0, 40.0}) {
        Real x = 0;  // overstress τ − τ_y after each step's return
        for (int step = 0; step < 200000; ++step) {
          const Real next = law.relaxed_overstress(x + shear_modulus * rate * dt, shear_modulus, dt);
          if (std::abs(next - x) < 1e-13 * (1 + x)) break;
          x = next;
        }
        EXPECT_NEAR(yield + x, law.shear_stress(rate), 1e-6 * law.shear_stress(rate))
            << "n " << n << " dt " << dt << " rate " << rate;
      }
      const Real trial = 300, c = shear_modulus * dt;
      const Real x = law.relaxed_overstress(trial, shear_modulus, dt);
      EXPECT_GE(x, 0);
      EXPECT_LE(x, trial);
      EXPECT_NEAR(x + c * std::pow(x / law.consistency, 1 / n), trial, 1e-9 * trial);
    }
  const HerschelBulkley bingham{10.0, 2.0, 1.0};
  EXPECT_DOUBLE_EQ(bingham.relaxed_overstress(30.0, 100.0, 0.01), 30.0 / (1 + 100.0 * 0.01 / 2.0));
  EXPECT_DOUBLE_EQ(bingham.relaxed_overstress(-3.0, 100.0, 0.01), -3.0);  // below yield: untouched
  const HerschelBulkley rate_independent{10.0, 0.0, 1.0};
  EXPECT_DOUBLE_EQ(rate_independent.relaxed_overstress(30.0, 100.0, 0.01), 0.0);
}
