// A still water column settles to hydrostatic pressure: at mid-depth the
// pressure is ρ g h within 5% (h = depth below the free surface). Weakly
// compressible SPH rings with acoustic waves; α_Π = 0.1 (Eq 3.36) damps them,
// and the pressure is averaged over every step from 0.2 s to 0.5 s (the
// mean is 4% above ρ g h there, the same as when averaged to 1 s). The
// divergence-free pressure holds the same column without ringing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

constexpr double kWidth = 0.06, kHeight = 0.12, kDepth = 0.032, kSpacing = 0.004, kG = 9.81, kRho0 = 1000.0;

// The water column, with the given SPH settings beside its spacing.
json column_scene(json sph) {
  sph["spacing"] = kSpacing;
  return {{"solver", {{"type", "sph"}, {"sph", sph}}},
          {"time", {{"end", 0.5}}},
          {"domain", {{"min", {0, 0, 0}}, {"max", {kWidth, 0.15, kDepth}}}},
          {"materials", {{"water", {{"density", kRho0}, {"viscosity", 1e-3}, {"xsph", 0.1}}}}},
          {"bodies",
           {{{"name", "column"},
             {"material", "water"},
             {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {kWidth, kHeight, kDepth}}}}}}}};
}

// Pressure of the particles of the mid-depth slab, away from the side walls,
// against ρ g (H − y) for the same particles, summed over the steps it sees.
struct MidDepthPressure {
  double measured = 0, expected = 0;
  long samples = 0;
  void add(const ParticleSet& ps) {
    const double h = 2 * kSpacing;
    const auto& x = ps.vector("position");
    const auto& p = ps.scalar("pressure");
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const Vec3& xi = x[i];
      if (std::abs(xi.y() - kHeight / 2) > kSpacing || xi.x() < h || xi.x() > kWidth - h || xi.z() < h ||
          xi.z() > kDepth - h)
        continue;
      measured += p[i];
      expected += kRho0 * kG * (kHeight - xi.y());
      ++samples;
    }
  }
  double relative_error() const { return (measured - expected) / expected; }
};

double fastest(const ParticleSet& ps) {
  double vmax = 0;
  for (const Vec3& v : ps.vector("velocity")) vmax = std::max(vmax, v.norm());
  return vmax;
}

}  // namespace

TEST(Hydrostatic, MidDepthPressureIsRhoGH) {
  auto solver = test_support::make_sph(column_scene({{"artificial_viscosity", {{"alpha", 0.1}}}}));
  // Let the start-up transient pass.
  test_support::advance_to(*solver, 0.2);
  // Over every step up to 0.5 s.
  MidDepthPressure tally;
  test_support::advance_to(*solver, 0.5, [&] { tally.add(solver->particles()); });
  ASSERT_GT(tally.samples, 100);
  const double expected = tally.expected / tally.samples;
  EXPECT_NEAR(tally.relative_error(), 0, 0.05)
      << "measured " << tally.measured / tally.samples << " Pa, expected " << expected << " Pa";
  RecordProperty("relative_error", std::to_string(tally.relative_error()));
  // The probe (Shepard interpolation at the centre) agrees to within the particle noise.
  const double probe = solver->sample(Vec3(kWidth / 2, kHeight / 2, kDepth / 2), {"pressure"})[0];
  EXPECT_NEAR(probe, expected, 0.25 * expected);
  // The column is at rest.
  EXPECT_LT(fastest(solver->particles()), 0.05 * std::sqrt(2 * kG * kHeight));
}

// The same column with the divergence-free pressure (solver.sph.pressure_solver,
// DFSPH) and without artificial viscosity: no acoustic ringing to damp. The
// density of the particles held within the solve's tolerance, the column at
// rest, and steps no longer bounded by the speed of sound (the weakly
// compressible column takes its CFL step of about 1e-4 s; at rest this one
// takes max_dt). Measured (docs/validation.md), portable build / native
// (FMA) build: pressure +5.5% / +6.2% (weakly compressible: +3.8%; the
// symmetric SPH gradient next to the side walls needs more pressure than
// ρ g, and the interior feels it), mean |ρ/ρ0 − 1| inside 0.01%, rms speed
// 7.1 / 7.4 mm/s, fastest 20 / 16 mm/s. With a density tolerance of 0.1%
// instead of 0.01% the column filled with unpressed voids (mean 0.9%).
TEST(DivergenceFree, StillColumnHoldsHydrostaticPressureAndRestDensity) {
  auto solver = test_support::make_sph(column_scene({{"pressure_solver", "divergence_free"}}));
  ASSERT_TRUE(solver->divergence_free());
  EXPECT_NE(solver->summary().find("pressure   divergence-free"), std::string::npos);  // what `validate` says
  test_support::advance_to(*solver, 0.2);
  MidDepthPressure tally;
  double worst_density_error = 0;
  long steps = 0;
  const ParticleSet& ps = solver->particles();
  test_support::advance_to(*solver, 0.5, [&] {
    ++steps;
    worst_density_error = std::max(worst_density_error, solver->last_density_error());
    tally.add(ps);
  });
  ASSERT_GT(tally.samples, 100);
  std::printf("divergence-free column: %ld steps in 0.3 s, mid-depth pressure %+.2f%%\n", steps,
              100 * tally.relative_error());
  EXPECT_NEAR(tally.relative_error(), 0, 0.08);
  RecordProperty("relative_error", std::to_string(tally.relative_error()));
  // Each density solve stopped at its tolerance (0.01% mean predicted error)
  // or, after its 100 iterations, not far above it (measured: 0.025% at worst).
  EXPECT_LE(worst_density_error, 5e-4);
  // Inside the column (more than h from every face) the density is at rest
  // within 0.05% on the mean and 1% at any particle.
  const double h = 2 * kSpacing;
  const auto& x = ps.vector("position");
  const auto& rho = ps.scalar("density");
  double worst_inside = 0, sum_inside = 0;
  long inside = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const Vec3& xi = x[i];
    if (xi.y() < h || xi.y() > kHeight - 2 * h || xi.x() < h || xi.x() > kWidth - h || xi.z() < h ||
        xi.z() > kDepth - h)
      continue;
    worst_inside = std::max(worst_inside, std::abs(rho[i] / kRho0 - 1));
    sum_inside += std::abs(rho[i] / kRho0 - 1);
    ++inside;
  }
  ASSERT_GT(inside, 100);
  std::printf("inside: mean |rho/rho0 - 1| %.4f, worst %.4f\n", sum_inside / inside, worst_inside);
  EXPECT_LT(sum_inside / inside, 5e-4);
  EXPECT_LT(worst_inside, 0.01);
  // At rest: the fastest particle and the root-mean-square speed.
  double sum_v2 = 0;
  for (const Vec3& v : ps.vector("velocity")) sum_v2 += v.squaredNorm();
  const double rms = std::sqrt(sum_v2 / double(ps.size()));
  std::printf("fastest %.4f m/s, rms %.4f m/s\n", fastest(ps), rms);
  EXPECT_LT(fastest(ps), 0.05 * std::sqrt(2 * kG * kHeight));
  EXPECT_LT(rms, 0.01 * std::sqrt(2 * kG * kHeight));
  // 0.3 s at rest in at most 1,000 steps (weakly compressible: about 3,000).
  EXPECT_LE(steps, 1000);
}
