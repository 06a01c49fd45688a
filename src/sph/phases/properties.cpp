// Phases properties (temperature-dependent μ, μ_e, λ, ε and the rise state,
// Eq 4.1–4.4, 3.48–3.52) and smoothing (per-particle h, Eq 3.54–3.56).
#include "sph/solver.hpp"

#include <cmath>
#include <limits>

#include "core/parallel.hpp"
#include "physics/constants.hpp"
#include "physics/rheology.hpp"
#include "sph/curve_temperature.hpp"

namespace bakesim::sph {

// Eq 4.1–4.4: viscosity, elasticity, relaxation time and XSPH tuner follow
// each particle's temperature, or the peak it reached once it has set
// (irreversible setting, physics/setting.hpp). Each curve is visited once per material; the particle loop sees
// a plain callable. Then the rise state of Eq 3.48–3.52.
void SphSolver::phase_properties(bool temperature_changed) {
  ScopedPhase t(timers_, t_properties_);
  const std::size_t n = x_.size();
  if (follows_peak_ && temperature_changed)
    parallel_for(
        n, [&](std::size_t i) { peak_temperature_[i] = std::max(peak_temperature_[i], temperature_[i]); }, 4096);
  auto follow = [&](int id, const TemperatureCurve& c, std::vector<Real>& out, Real lo, Real hi) {
    if (is_constant(c) || !temperature_changed) return;
    const CurveTemperature at(setup_.materials[id].set, temperature_, peak_temperature_);
    std::visit(
        [&](const auto& curve) {
          parallel_for(
              n,
              [&](std::size_t i) {
                if (material_[i] != id) return;
                out[i] = std::clamp(curve(at(i)), lo, hi);
              },
              4096);
        },
        c);
  };
  const Real inf = std::numeric_limits<Real>::infinity();
  for (std::size_t mi = 0; mi < setup_.materials.size(); ++mi) {
    const Material& mat = setup_.materials[mi];
    const int id = static_cast<int>(mi);
    const bool evp = elastoviscoplastic(mat);  // μ 0 and λ kNeverRelaxes throughout
    if (!evp) follow(id, mat.viscosity, mu_, 0.0, inf);
    follow(id, mat.xsph, eps_, 0.0, 1.0);
    follow(id, mat.elasticity, elasticity_, 0.0, inf);
    if (!evp) follow(id, mat.relaxation_time, relaxation_, 1e-9, inf);  // λ > 0 (Eq 3.20 divides by it)
    if (regularised_yield_flow(mat)) apparent_viscosity(id);
  }
  // Bubbles start rising once heating begins; a bubble stops when it has
  // expanded max_expansion times, and every particle of the body switches to
  // the risen Tait law at end_temperature (ρ_f: its density then, Eq 3.52).
  parallel_for(
      n,
      [&](std::size_t i) {
        const Body& b = setup_.bodies[body_[i]];
        if (b.bubbles.fraction <= 0 || rise_state_[i] == 2) return;
        const Real rho0 = setup_.materials[material_[i]].rest_density;
        const bool rising = rise_state_[i] == 1;
        if (bubble_[i] && !rising && temperature_[i] > b.temperature + 0.5) rise_state_[i] = 1;
        const bool done = temperature_[i] >= b.bubbles.end_temperature ||
                          (bubble_[i] && rise_state_[i] == 1 && rho0 / rho_[i] >= b.bubbles.max_expansion);
        if (done) {
          rise_state_[i] = 2;
          set_density_[i] = std::min(rho_[i], rho0);
          set_temperature_[i] = temperature_[i];
        }
      },
      4096);
}

// A yield-stress material's μ: the Herschel–Bulkley apparent viscosity
// (physics/rheology.hpp) at the particle's shear rate γ̇ = √(2 D:D), D the
// symmetric part of the velocity gradient (Eq 3.27) of the velocities just
// solved; K and τ_y from the material's curves at the temperature its curves
// read. The next step's forces and implicit solve use it (lagged viscosity).
void SphSolver::apparent_viscosity(int id) {
  const Material& mat = setup_.materials[std::size_t(id)];
  const CurveTemperature at(mat.set, temperature_, peak_temperature_);
  const bool corrected = setup_.settings.stress_viscosity && correction_.size() == x_.size();
  for_each_yield_law(mat, id, material_, at, [&](std::size_t i, const HerschelBulkley& law) {
    const Mat3 l = velocity_gradient(i, nullptr, corrected);
    Mat3 d = 0.5 * (l + l.transpose());
    if (corrected) d -= (d.trace() / 3) * Mat3::Identity();
    mu_[i] = law.apparent_viscosity(std::sqrt(2.0 * d.squaredNorm()));
  });
}

// Eq 3.54–3.55: h_i = k_g (ρ_i/ρ_ref)^(−ε_g) h0 for the next step, with
// ρ_ref the geometric mean of ρ/ρ0 over all particles (each material against
// its own rest density) or ρ0 itself; clamped to the configured range.
void SphSolver::phase_smoothing() {
  if (!adaptive_) return;
  ScopedPhase t(timers_, t_smoothing_);
  const AdaptiveSmoothing& a = setup_.settings.adaptive;
  const std::size_t n = x_.size();
  Real log_mean = 0;
  if (a.geometric_mean && n > 0) {
    log_mean = deterministic_sum(
                   n, [&](std::size_t i) { return std::log(rho_[i] / setup_.materials[material_[i]].rest_density); }) /
               Real(n);
  }
  const Real lo = a.min_ratio * h_, hi = a.max_ratio * h_;
  parallel_for(
      n,
      [&](std::size_t i) {
        const Real relative = std::log(rho_[i] / setup_.materials[material_[i]].rest_density) - log_mean;
        smoothing_[i] = std::clamp(a.scale * std::exp(-a.sensitivity * relative) * h_, lo, hi);
      },
      4096);
}

}  // namespace bakesim::sph
