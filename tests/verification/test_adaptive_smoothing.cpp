// Adaptive smoothing length (thesis Eq 3.53–3.56). On a lattice expanded by a
// factor k the SPH density with support k·h0 is exactly ρ0/k³ (the kernel
// sum scales as 1/k³), so h_i = h0 (ρ_i/ρ0)^(−1/3) (Liu and Liu, Eq 3.53:
// the rest-density reference of Eq 3.54 with ε_g = 1/3) has the fixed point
// h = k·h0: an expanded body gets back its neighbours.
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

constexpr double kSpacing = 0.002, kHalf = 0.012;

json block(const json& adaptive) {
  return {{"solver", {{"type", "sph"}, {"sph", {{"spacing", kSpacing}, {"adaptive_smoothing", adaptive}}}}},
          {"time", {{"end", 1.0}}},
          {"gravity", {0, 0, 0}},
          {"domain", {{"min", {-0.05, -0.05, -0.05}}, {"max", {0.05, 0.05, 0.05}}}},
          {"materials", {{"dough", {{"density", 1000.0}, {"viscosity", 0.01}}}}},
          {"bodies",
           json::array(
               {{{"name", "block"},
                 {"material", "dough"},
                 {"shape", {{"type", "box"}, {"min", {-kHalf, -kHalf, -kHalf}}, {"max", {kHalf, kHalf, kHalf}}}}}})}};
}

// Interior particles: a full support (1.5 h0 at most) from the surface.
template <class Fn>
void for_interior(const ParticleSet& ps, double half, double margin, Fn&& fn) {
  const auto& x = ps.vector("position");
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i].cwiseAbs().maxCoeff() < half - margin) fn(i);
}

}  // namespace

TEST(AdaptiveSmoothing, ExpandedLatticeRecoversLiuLiuLengthDensityAndNeighbours) {
  const double k = 1.2;
  auto solver = test_support::make_sph(
      block({{"enabled", true}, {"reference", "rest_density"}, {"sensitivity", 1.0 / 3.0}, {"range", {0.8, 1.5}}}));
  const double h0 = solver->support();
  // Neighbour count of interior particles at rest.
  double rest_count = 0;
  int rest_n = 0;
  for_interior(solver->particles(), kHalf, 1.5 * h0, [&](std::size_t i) {
    rest_count += solver->neighbours().count(i);
    ++rest_n;
  });
  rest_count /= rest_n;
  auto& x = solver->mutable_particles().vector("position");
  for (Vec3& p : x) p *= k;
  solver->refresh();
  // Expanded: negative pressure is clamped and nothing moves; h converges
  // to its fixed point in a few steps.
  for (int s = 0; s < 8; ++s) solver->step(1e-5);
  const ParticleSet& ps = solver->particles();
  const auto& h = ps.scalar("smoothing_length");
  const auto& rho = ps.scalar("density");
  double worst_h = 0, worst_rho = 0, count = 0;
  int n = 0;
  for_interior(ps, k * kHalf, 1.6 * k * h0, [&](std::size_t i) {
    worst_h = std::max(worst_h, std::abs(h[i] / (k * h0) - 1.0));
    worst_rho = std::max(worst_rho, std::abs(rho[i] * k * k * k / 1000.0 - 1.0));
    // Lattice points at exactly the support distance carry zero weight and
    // are listed or not by round-off; count those strictly inside.
    const auto& lists = solver->neighbours();
    for (std::uint32_t q = 0; q < lists.count(i); ++q)
      count += lists.distances(i)[q] < 0.999 * 0.5 * (h[i] + h[lists.begin(i)[q]]);
    ++n;
  });
  ASSERT_GT(n, 100);
  EXPECT_LT(worst_h, 0.01) << worst_h;
  EXPECT_LT(worst_rho, 0.02) << worst_rho;
  EXPECT_NEAR(count / n, rest_count, 0.05 * rest_count) << "rest " << rest_count;
}

TEST(AdaptiveSmoothing, FixedSmoothingLengthStaysExpandedAndLosesNeighbours) {
  // The same expansion without adaptation: the density estimate of the
  // expanded interior is ρ0/k³ only to the kernel's accuracy at this
  // spacing, and the neighbour count drops by about k³ (the thesis's reason
  // for Eq 3.54).
  const double k = 1.2;
  auto solver = test_support::make_sph(block({{"enabled", false}}));
  const double h0 = solver->support();
  auto& x = solver->mutable_particles().vector("position");
  for (Vec3& p : x) p *= k;
  solver->refresh();
  double count = 0;
  int n = 0;
  for_interior(solver->particles(), k * kHalf, 1.2 * k * h0, [&](std::size_t i) {
    count += solver->neighbours().count(i);
    ++n;
  });
  EXPECT_LT(count / n, 33.0 / (k * k * k) * 1.15);
}

TEST(AdaptiveSmoothing, ZeroSensitivityGivesTheScaledFixedLength) {
  auto solver =
      test_support::make_sph(block({{"enabled", true}, {"sensitivity", 0.0}, {"scale", 1.1}, {"range", {0.8, 1.5}}}));
  for (int s = 0; s < 3; ++s) solver->step(1e-5);
  for (double h : solver->particles().scalar("smoothing_length")) ASSERT_NEAR(h, 1.1 * solver->support(), 1e-15);
}

TEST(AdaptiveSmoothing, GeometricMeanReferenceLengthensSurfaceParticles) {
  // Eq 3.54–3.55: surface particles have too few neighbours, a low density
  // against the mean and so a longer h; the interior is at the mean.
  auto solver = test_support::make_sph(block({{"enabled", true}}));
  for (int s = 0; s < 3; ++s) solver->step(1e-5);
  const ParticleSet& ps = solver->particles();
  const auto& h = ps.scalar("smoothing_length");
  const auto& x = ps.vector("position");
  const double h0 = solver->support();
  double corner = 0, centre = 1e9;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double d = x[i].cwiseAbs().maxCoeff();
    if (x[i].cwiseAbs().minCoeff() > kHalf - kSpacing) corner = std::max(corner, h[i]);
    if (d < kSpacing) centre = std::min(centre, h[i]);
  }
  EXPECT_GT(corner, 1.3 * h0);
  EXPECT_LT(centre, 1.0 * h0);
  EXPECT_GT(centre, 0.8 * h0);
}
