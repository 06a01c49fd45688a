// A standing elastic shear wave in a fully periodic SPH box: the Maxwell
// stress (Eq 3.20, λ far longer than the run, so purely elastic) against the
// continuum wave, explicit and semi-implicit (solver.sph.elasticity_solver).
//
// v_x = A sin(k y) at rest stress; dS_xy/dt = μ_e D'_xy = (μ_e/2) ∂v_x/∂y and
// ρ dv_x/dt = ∂S_xy/∂y give shear waves of speed c = √(μ_e / 2ρ):
//   v_x = A sin(k y) cos(ω t),  S_xy = ρ c A cos(k y) sin(ω t),  ω = c k,
// so z = P_v + i P_S/(ρ c) (the projections of v_x on sin(k y) and of S_xy on
// cos(k y)) turns at ω with |z| = A. The explicit scheme must follow it at
// its elastic bound; the semi-implicit one, at steps 5 and 20 times that
// bound, must follow its own linear amplification (semi_implicit_wave).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "helpers.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

constexpr double kWaveSpacing = 1e-3, kWaveDensity = 1000, kWaveElasticity = 2000;  // c = 1 m/s
constexpr int kWaveLength = 20;                                                     // spacings
constexpr double kWaveAmplitude = 1e-5;                                             // m/s: linear

json elastic_box(const char* elasticity_solver, double max_dt) {
  const double s = kWaveSpacing;
  return test_support::periodic_box_scene(
      6 * s, kWaveLength * s, {{"spacing", s}, {"speed_of_sound", 0.01}, {"elasticity_solver", elasticity_solver}},
      {{"density", kWaveDensity}, {"viscosity", 0.0}, {"elasticity", kWaveElasticity}, {"relaxation_time", 1e9}},
      max_dt);
}

struct Wave {
  std::complex<double> z;  // P_v + i P_S / (ρ c)
  double dt = 0;           // the step the solver took
};

// Runs `steps` steps of the solver's own stable step and returns z at the end.
Wave run_wave(const char* elasticity_solver, double max_dt, int steps) {
  auto sph = test_support::make_sph(elastic_box(elasticity_solver, max_dt));
  const double k = 2 * kPi / (kWaveLength * kWaveSpacing), c = std::sqrt(kWaveElasticity / (2 * kWaveDensity));
  test_support::start_shear_wave(*sph, k, kWaveAmplitude);
  Wave out;
  out.dt = sph->max_stable_dt();
  for (int n = 0; n < steps; ++n) sph->step(out.dt);
  const auto& x = sph->particles().vector("position");
  const auto& v = sph->particles().vector("velocity");
  double pv = 0, ps_ = 0, ss = 0, cc = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double sn = std::sin(k * x[i].y()), cs = std::cos(k * x[i].y());
    pv += v[i].x() * sn;
    ss += sn * sn;
    ps_ += sph->stress(i)(0, 1) * cs;
    cc += cs * cs;
  }
  out.z = {pv / ss, ps_ / cc / (kWaveDensity * c)};
  return out;
}

}  // namespace

TEST(ElasticShearWave, ExplicitTurnsAtTheWaveFrequencyAndKeepsItsAmplitude) {
  const double k = 2 * kPi / (kWaveLength * kWaveSpacing), omega = std::sqrt(kWaveElasticity / (2 * kWaveDensity)) * k;
  // A quarter period at the elastic bound (about 18 steps).
  const Wave probe = run_wave("explicit", 1.0, 0);
  const int steps = int(std::lround(0.5 * kPi / omega / probe.dt));
  const Wave w = run_wave("explicit", 1.0, steps);
  const double phase = std::arg(w.z), expected = omega * w.dt * steps;
  const double amplitude = std::abs(w.z) / kWaveAmplitude;
  std::printf("explicit: dt %.3e s, %d steps, phase %.4f rad (continuum %.4f, %+.2f%%), amplitude %.4f\n", w.dt, steps,
              phase, expected, 100 * (phase / expected - 1), amplitude);
  EXPECT_NEAR(phase / expected, 1.0, 0.03);
  EXPECT_NEAR(amplitude, 1.0, 0.03);
}

// The semi-implicit scheme on the continuum wave, θ = ω dt, u = P_v/A and
// w = P_S/(ρ c A): the leap-frog applies the explicit stress force as the
// mean of the last two force phases' (each from the stress at its step's
// start), the implicit solve adds the step's increment, and the stress takes
// the increment of the solved velocity:
//   (1 + θ²) u_{n+1} = u_n − θ (w_{n−1} + w_n)/2,   w_{n+1} = w_n + θ u_{n+1}.
// Its roots satisfy (1 + θ²) λ² − (2 + θ²/2) λ + 1 + θ²/2 = 0: complex for
// every θ, |λ|² = (1 + θ²/2)/(1 + θ²) < 1, stable at any step (backward
// Euler's own would be 1/(1 + θ²)).
std::complex<double> semi_implicit_wave(double theta, int steps) {
  double u = 1, w = 0, w_before = 0;
  for (int n = 0; n < steps; ++n) {
    const double u_next = (u - 0.5 * theta * (w_before + w)) / (1 + theta * theta);
    w_before = w;
    w += theta * u_next;
    u = u_next;
  }
  return {u, w};
}

TEST(ElasticShearWave, ImplicitBeyondTheElasticBoundFollowsItsSchemesAmplification) {
  const double k = 2 * kPi / (kWaveLength * kWaveSpacing), omega = std::sqrt(kWaveElasticity / (2 * kWaveDensity)) * k;
  const double bound = run_wave("explicit", 1.0, 0).dt;
  for (const double factor : {5.0, 20.0}) {
    const Wave probe = run_wave("implicit", factor * bound, 0);
    ASSERT_NEAR(probe.dt, factor * bound, 1e-12 * bound);  // the elastic bound no longer applies
    const int steps = 12;
    const Wave w = run_wave("implicit", factor * bound, steps);
    const std::complex<double> expected = semi_implicit_wave(omega * w.dt, steps);
    const double amplitude = std::abs(w.z) / kWaveAmplitude;
    // The phase difference, wrapped to (−π, π], over the phase turned.
    const double phase_error = std::arg(w.z / kWaveAmplitude / expected);
    double turned = 0;
    for (int n = 1; n <= steps; ++n)
      turned += std::abs(std::arg(semi_implicit_wave(omega * w.dt, n) / semi_implicit_wave(omega * w.dt, n - 1)));
    std::printf(
        "implicit: dt %.3e s (omega dt %.3f), %d steps, amplitude %.4f (scheme %.4f, %+.2f%%), phase "
        "%+.4f rad off over %.3f rad\n",
        w.dt, omega * w.dt, steps, amplitude, std::abs(expected), 100 * (amplitude / std::abs(expected) - 1),
        phase_error, turned);
    EXPECT_NEAR(amplitude / std::abs(expected), 1.0, 0.03);
    EXPECT_LT(std::abs(phase_error), 0.02 * turned);
    EXPECT_LT(amplitude, 1.0);
  }
}

// XSPH (Eq 3.34) smooths a shear wave by the same amount per second whatever
// the step: the thesis's once-per-step correction is scaled by dt over the CFL
// bound at rest (docs/physics.md, "XSPH"). Applied once per step unscaled, a
// quarter of the step would smooth four times as much over the same time.
TEST(Xsph, SmoothsAShearWaveAtTheSameRatePerSecondWhateverTheStep) {
  const double s = kWaveSpacing, lambda = kWaveLength * s, w = 6 * s, c = 0.01, k = 2 * kPi / lambda;
  const double reference_step = 0.4 * s / c;  // cfl ħ / c with ħ = h/2 = s
  auto decay = [&](int substeps) {
    auto sph = test_support::make_sph(test_support::periodic_box_scene(
        w, lambda, {{"spacing", s}, {"speed_of_sound", c}}, {{"density", 1000.0}, {"viscosity", 0.0}, {"xsph", 0.5}}));
    test_support::start_shear_wave(*sph, k, kWaveAmplitude);
    for (int n = 0; n < 10 * substeps; ++n) sph->step(reference_step / substeps);
    return -std::log(test_support::shear_wave_amplitude(*sph, k) / kWaveAmplitude);  // e-foldings over 10 steps
  };
  const double full = decay(1), quarter = decay(4);
  std::printf("XSPH over 10 reference steps: %.4f e-foldings at the reference step, %.4f at a quarter of it\n", full,
              quarter);
  EXPECT_GT(full, 0.05);  // it does smooth
  EXPECT_NEAR(quarter / full, 1.0, 0.1);
}
