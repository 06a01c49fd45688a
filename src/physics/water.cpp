#include "physics/water.hpp"

#include <limits>
#include <numbers>

namespace bakesim {

namespace {
constexpr Real kMmHg = 133.322368;  // Pa
struct Antoine {
  Real a, b, c;
};
constexpr Antoine kLow{8.07131, 1730.63, 233.426}, kHigh{8.14019, 1810.94, 244.485};
// Where the two branches give the same pressure (143.0 kPa): switching there keeps p_sat continuous.
// Switched at 100 °C, where they differ by 0.55%, the boiling line of bound water jumped there, and
// a particle whose line crossed 100 °C (a boiling point below 100: altitude) boiled off its water
// and fell 6 K below its line in one step.
constexpr Real kBranchesMeet = 108.26631;
const Antoine& antoine_for(Real celsius) { return celsius < kBranchesMeet ? kLow : kHigh; }
// d p_sat/dθ from p_sat itself (one exponential for both).
Real slope_of_saturation_pressure(Real pressure, Real celsius) {
  const Antoine& k = antoine_for(celsius);
  return pressure * std::numbers::ln10 * k.b / ((k.c + celsius) * (k.c + celsius));
}
}  // namespace

// 10^x as e^(x ln 10): the phases call these for every particle every step,
// and exp costs a fraction of pow.
Real saturation_vapour_pressure(Real celsius) {
  const Antoine& k = antoine_for(celsius);
  return kMmHg * std::exp(std::numbers::ln10 * (k.a - k.b / (k.c + celsius)));
}

// The Antoine equation solved for θ on the branch that holds it.
Real saturation_temperature(Real pressure) {
  const Real log_mmhg = std::log10(pressure / kMmHg);
  const Real low = kLow.b / (kLow.a - log_mmhg) - kLow.c;
  if (low < kBranchesMeet) return low;
  return kHigh.b / (kHigh.a - log_mmhg) - kHigh.c;
}

Real boiling_point_at(Real pressure) {
  return 100 + (saturation_temperature(pressure) - saturation_temperature(kAtmosphere));
}

namespace {
constexpr Real kHottestBoiling = 370;  // °C, below water's critical point (374 °C)
}  // namespace

Real saturation_vapour_pressure_slope(Real celsius) {
  return slope_of_saturation_pressure(saturation_vapour_pressure(celsius), celsius);
}

Real SorptionIsotherm::prefactor(Real celsius) const {
  return std::exp(oswin_a_slope * (celsius + kZeroCelsius) + oswin_a_offset);
}

Real SorptionIsotherm::activity_ratio(Real moisture, Real a) const {
  return moisture > 0 ? std::pow(100.0 * moisture / a, 1.0 / oswin_exponent) : 0;
}

Real SorptionIsotherm::activity(Real moisture, Real celsius) const {
  if (!(moisture > 0)) return 0;
  const Real y = activity_ratio(moisture, prefactor(celsius));
  return y / (1 + y);
}

Real SorptionIsotherm::moisture_with_prefactor(Real water_activity, Real a) const {
  if (!(water_activity > 0)) return 0;
  if (!(water_activity < 1)) return std::numeric_limits<Real>::infinity();
  return a / 100.0 * std::pow(water_activity / (1 - water_activity), oswin_exponent);
}

Real SorptionIsotherm::moisture_at(Real water_activity, Real celsius) const {
  return moisture_with_prefactor(water_activity, prefactor(celsius));
}

namespace {
// The boiling line at θ > θ_b for the ambient pressure p_b: X_b and dX_b/dθ
// from one p_sat and one power. X = (a/100) (a_w/(1 − a_w))ⁿ with
// a_w = p_b/p_sat(θ): d ln X/dθ = c₁ − n (p_sat'/p_sat) / (1 − a_w).
struct BoilingLine {
  Real moisture, slope;
};
BoilingLine boiling_line(const SorptionIsotherm& sorption, Real ambient, Real celsius) {
  const Real p = saturation_vapour_pressure(celsius), activity = ambient / p;
  if (!(activity < 1)) return {std::numeric_limits<Real>::infinity(), -std::numeric_limits<Real>::infinity()};
  const Real x = sorption.moisture_at(activity, celsius);
  const Real log_slope =
      sorption.oswin_a_slope - sorption.oswin_exponent * slope_of_saturation_pressure(p, celsius) / p / (1 - activity);
  return {x, x * log_slope};
}
}  // namespace

Real PoreWater::boiling_moisture(Real celsius) const {
  if (!(celsius > boiling_point)) return std::numeric_limits<Real>::infinity();
  return boiling_line(sorption, saturation_vapour_pressure(boiling_point), celsius).moisture;
}

Real PoreWater::boiling_moisture_slope(Real celsius) const {
  if (!(celsius > boiling_point)) return -std::numeric_limits<Real>::infinity();
  return boiling_line(sorption, saturation_vapour_pressure(boiling_point), celsius).slope;
}

namespace {
// The temperature at which dough of moisture X boils against the ambient pressure p_b (PoreWater::
// boiling_temperature; p_b passed in, as boil_bound already holds it).
Real line_temperature(const PoreWater& pw, Real ambient, Real moisture_now) {
  const SorptionIsotherm& sorption = pw.sorption;
  if (!(moisture_now > 0)) return kHottestBoiling;
  if (sorption.oswin_a_slope == 0) {  // a_w does not depend on θ: p_sat(θ) = p_b / a_w
    const Real activity = sorption.activity(moisture_now, pw.boiling_point);
    if (!(activity < 1)) return pw.boiling_point;
    if (!(activity > 0)) return kHottestBoiling;
    return std::clamp(saturation_temperature(ambient / activity), pw.boiling_point, kHottestBoiling);
  }
  // a(θ) varies: bisect a_w(X, θ) p_sat(θ) − p_b, which changes sign once between θ_b and 370 °C
  // for the isotherms the schema allows (p_sat grows far faster than a_w can fall).
  auto excess = [&](Real theta) {
    return sorption.activity(moisture_now, theta) * saturation_vapour_pressure(theta) - ambient;
  };
  Real lo = pw.boiling_point, hi = kHottestBoiling;
  if (!(excess(lo) < 0)) return pw.boiling_point;
  if (excess(hi) < 0) return kHottestBoiling;
  for (int i = 0; i < 100 && hi - lo > 1e-12 * hi; ++i) {
    const Real mid = 0.5 * (lo + hi);
    (excess(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
}  // namespace

Real PoreWater::boiling_temperature(Real moisture_now) const {
  return line_temperature(*this, saturation_vapour_pressure(boiling_point), moisture_now);
}

Boiling boil_bound(const PoreWater& pw, Real heat_capacity, Real temperature, Real water, Real dry_mass) {
  if (!(water > 0) || !(temperature > pw.boiling_point) || !(heat_capacity > 0)) return {temperature, water, 0};
  const Real latent = pw.latent_heat;
  if (!(dry_mass > 0)) return boil(heat_capacity, temperature, water, pw.boiling_point, latent);
  // The line's temperature for W: at or above it the particle holds all its water bound (a crust below its line).
  const Real ambient = saturation_vapour_pressure(pw.boiling_point);
  Real theta = line_temperature(pw, ambient, water / dry_mass);
  if (!(temperature > theta)) return {temperature, water, 0};
  // So wet that it boils within a microkelvin of θ_b: free water.
  if (theta < pw.boiling_point + 1e-6) return boil(heat_capacity, temperature, water, pw.boiling_point, latent);
  // Newton on g(θ') = C (θ − θ') − h_fg (W − m_d X_b(θ')), from the line's temperature for W (g > 0 there,
  // < 0 at θ). A step s leaves an error of order s²/(θ' − θ_b) (the line's curvature): below 1e-7 K the
  // step is taken on the tangent without another evaluation (most steps of dough at its plateau: one).
  Real bound = water;  // m_d X_b(θ'): the water the line keeps at θ'
  for (int iteration = 0; iteration < 60; ++iteration) {
    const BoilingLine line = boiling_line(pw.sorption, ambient, theta);
    bound = dry_mass * line.moisture;
    const Real g = heat_capacity * (temperature - theta) - latent * (water - bound);
    const Real slope = -heat_capacity + latent * dry_mass * line.slope;
    if (!(g > 0) || !std::isfinite(slope)) break;
    const Real step = std::min(-g / slope, temperature - theta);
    if (step * step < 1e-7 * (theta - pw.boiling_point)) {
      bound += dry_mass * line.slope * step;
      break;
    }
    theta += step;
  }
  const Real boiled = std::clamp(water - bound, Real(0), water);
  return {temperature - latent * boiled / heat_capacity, water - boiled, boiled};
}

namespace {
// Vapour of partial pressure p at θ as an ideal gas, kg/m³.
Real ideal_vapour_density(Real pressure, Real celsius) {
  return pressure * kWaterMolarMass / (kGasConstant * (celsius + kZeroCelsius));
}
// The closed-cell heat pipe (PoreWater::cell_conductivity) works in moist
// dough below its boiling point, and then takes the activity and p = p_sat(θ).
bool heat_pipe_works(const PoreWater& w, Real celsius, Real moisture_now) {
  return w.cell_heat_pipe > 0 && moisture_now > 0 && celsius < w.boiling_point;
}
Real heat_pipe(const PoreWater& w, Real celsius, Real activity, Real p, Real phi) {
  const Real tk = std::max(celsius, Real(-50)) + kZeroCelsius;
  const Real dp = slope_of_saturation_pressure(p, celsius);
  const Real drho_sat = kWaterMolarMass / (kGasConstant * tk) * (dp - p / tk);  // d(p M / R T)/dθ
  return w.cell_heat_pipe * w.closed_cell_share(celsius) * phi * w.latent_heat * w.free_vapour_diffusivity(tk) *
         activity * drho_sat;
}
}  // namespace

Real PoreWater::vapour_density(Real celsius, Real moisture_now) const {
  const Real theta = std::min(celsius, boiling_point);
  return ideal_vapour_density(sorption.activity(moisture_now, theta) * saturation_vapour_pressure(theta), theta);
}

Real PoreWater::surface_flux(Real vapour_now, Real celsius, Real moisture_now, Real dry_mass, Real volume, Real area,
                             Real mass_transfer, Real air_vapour, Real step) const {
  const Real mean_face = mass_transfer * (vapour_now - air_vapour);
  if (surface_evaporation == SurfaceEvaporation::free || !(mean_face > 0)) return mean_face;
  if (!(area > 0) || !(volume > 0) || !(dry_mass > 0)) return 0;
  const Real reference = std::max(moisture, moisture_now), dry_density = dry_mass / volume;
  // The loss per area, kept above a nanometre's worth of water (a face that has lost none is wet: the free rate).
  const Real lost = std::max(dry_mass * (moisture - moisture_now) / area, 1e-9 * dry_density * reference);
  const Real diffusivity = liquid_diffusion(celsius);
  if (!(diffusivity > 0)) return 0;  // no liquid moves: a face that has dried stays dry
  // The erfc layer's depth for this loss, δ = π M / (2 ρ_d X₀), against the element's face distance
  // L = V / (2 A): once δ passes L the layer's erfc tail reaches the elements behind it, the element's own
  // loss no longer measures the layer's, and the face takes the resolved gradient from the element's
  // centre, ρ_d D (X − X_s) / L (blended over L < δ < 2L).
  const Real half_depth = volume / (2 * area);
  const Real layer = kPi * lost / (2 * dry_density * reference * half_depth);  // δ / L
  const Real resolved = std::clamp(layer - 1, Real(0), Real(1));
  // dM/dt = K / M with K = 2 ρ_d² D (X₀ − X_s)² / π, taken over the step exactly (M² grows by 2 K Δt):
  // the mean rate (√(M² + 2 K Δt) − M) / Δt, so that the first steps of a wet face neither overshoot nor
  // lag the square-root law whatever the step (K / M as Δt → 0).
  const Real unresolved_k = (1 - resolved) * 2 * dry_density * dry_density * diffusivity / kPi;
  const Real resolved_rate = resolved * dry_density * diffusivity / half_depth;
  const Real theta = std::min(celsius, boiling_point);
  const Real saturated = ideal_vapour_density(saturation_vapour_pressure(theta), theta);
  // The isotherm's a (one exp) once, then a_w = y / (1 + y) per trial (SorptionIsotherm).
  const Real oswin_a = sorption.prefactor(theta);
  const Real inverse_exponent = 1 / sorption.oswin_exponent;
  // g(X_s) = supply(X_s) − pull(X_s) and its slope: the supply falls and the pull rises with X_s, so g
  // falls from > 0 at X_s = 0 (a dry face pulls nothing) to ≤ 0 at X₀; Newton's method kept inside the
  // bracket (bisection where a step would leave it), a few trials where bisection took 30.
  struct Trial {
    Real g, slope, pull;
  };
  const auto trial = [&](Real face) {
    const Real y = sorption.activity_ratio(face, oswin_a);
    const Real activity = y / (1 + y);
    const Real pull = mass_transfer * (activity * saturated - air_vapour);
    const Real pull_slope =
        face > 0 ? mass_transfer * saturated * y * inverse_exponent / (face * (1 + y) * (1 + y)) : 0;
    const Real gap = reference - face, k = unresolved_k * gap * gap, k_slope = -2 * unresolved_k * gap;
    Real supply, supply_slope;
    if (step > 0) {
      const Real root = std::sqrt(lost * lost + 2 * k * step);
      supply = (root - lost) / step, supply_slope = k_slope / root;
    } else {
      supply = k / lost, supply_slope = k_slope / lost;
    }
    if (moisture_now > face) supply += resolved_rate * (moisture_now - face), supply_slope -= resolved_rate;
    return Trial{supply - pull, supply_slope - pull_slope, pull};
  };
  // Start where the pull takes what a dry face is supplied (the isotherm inverted once): the face is
  // usually far drier than X₀, so this lies within a few per cent of the root; else at X₀, where a pull
  // weaker than the supply leaves the face wet (the free rate).
  Real dry = 0, wet = reference, face = wet;
  const Real dry_supply = trial(0).g - mass_transfer * air_vapour;  // supply(0); pull(0) = −h_m ρ_v,air
  const Real activity = (dry_supply / mass_transfer + air_vapour) / saturated;
  const Real guess = sorption.moisture_with_prefactor(activity, oswin_a);  // 0 or ∞ outside (0, 1): kept wet
  if (guess > 0 && guess < wet) face = guess;
  Trial at = trial(face);
  if (face == wet && !(at.g < 0)) return std::max(at.pull, Real(0));
  for (int k = 0; k < 60; ++k) {
    (at.g > 0 ? dry : wet) = face;
    Real next = at.slope < 0 ? face - at.g / at.slope : 0.5 * (dry + wet);
    if (!(next > dry && next < wet)) next = 0.5 * (dry + wet);
    const bool converged = std::abs(next - face) <= 1e-6 * reference;
    face = next;
    at = trial(face);
    if (converged || wet - dry <= 1e-6 * reference) break;
  }
  return std::max(at.pull, Real(0));
}

Real PoreWater::step_diffusivity(Real hottest, Real density, Real specific_heat, Real volume_ratio) const {
  // For the most expanded particle: its gas fraction has grown and its heat capacity and dry mass per volume
  // have fallen by J. (Scaling the unexpanded value by J φ(J)/φ₀ instead divided by φ₀: a material without
  // pores, φ₀ = 0, whose particles a density fluctuation expands by 1%, got a bound 10⁴ times too small.)
  const Real j = std::max(volume_ratio, Real(1));
  PoreWater expanded = *this;
  expanded.gas_fraction = expanded_gas_fraction(j);
  const Real theta = std::min(hottest, boiling_point), dry = density / (1 + moisture);
  Real d = 0;
  for (const Real x : {moisture, 0.5 * moisture, 0.2 * moisture, 0.05 * moisture})
    d = std::max(d, expanded.effective_diffusivity(theta, x, density * specific_heat / j, dry / j));
  return d;
}

Real PoreWater::cell_conductivity(Real celsius, Real moisture_now, Real phi) const {
  if (!heat_pipe_works(*this, celsius, moisture_now)) return 0;
  return heat_pipe(*this, celsius, sorption.activity(moisture_now, celsius), saturation_vapour_pressure(celsius), phi);
}

PoreWater::PoreVapour PoreWater::pore_vapour(Real celsius, Real moisture_now, Real phi) const {
  // Below the boiling point vapour_density's θ is the particle's own, the one
  // cell_conductivity takes: there the two share p_sat and a_w.
  const Real theta = std::min(celsius, boiling_point);
  const Real activity = sorption.activity(moisture_now, theta), p = saturation_vapour_pressure(theta);
  return {ideal_vapour_density(activity * p, theta),
          heat_pipe_works(*this, celsius, moisture_now) ? heat_pipe(*this, celsius, activity, p, phi) : 0};
}

Real PoreWater::effective_diffusivity(Real celsius, Real moisture_now, Real heat_capacity_density,
                                      Real dry_density) const {
  // ∂ρ_v/∂θ and ∂ρ_v/∂X by differences: the law is smooth, the bound only needs its size.
  const Real theta = std::min(celsius, boiling_point - 0.5);
  const Real x = std::max(moisture_now, Real(1e-4));
  const Real dr_dt = (vapour_density(theta + 0.5, x) - vapour_density(theta - 0.5, x));
  const Real dx = 1e-3 * std::max(x, Real(0.01));
  const Real dr_dx = std::abs(vapour_density(theta, x + dx) - vapour_density(theta, std::max(x - dx, Real(0)))) /
                     (x + dx - std::max(x - dx, Real(0)));
  const Real conductance = vapour_conductance(celsius);
  Real d = liquid_diffusion(celsius);
  if (heat_capacity_density > 0) {
    d = std::max(d, latent_heat * conductance * std::abs(dr_dt) / heat_capacity_density);
    // The closed-cell heat pipe adds to the conduction (near the boiling point, where it is largest).
    d = std::max(d,
                 cell_conductivity(std::min(celsius, boiling_point - 0.01), x, gas_fraction) / heat_capacity_density);
  }
  if (dry_density > 0) d = std::max(d, conductance * dr_dx / dry_density);
  return d;
}

}  // namespace bakesim
