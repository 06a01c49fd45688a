#include "physics/water.hpp"

#include <numbers>

namespace bakesim {

namespace {
constexpr Real kMmHg = 133.322368;  // Pa
struct Antoine {
  Real a, b, c;
};
constexpr Antoine kLow{8.07131, 1730.63, 233.426}, kHigh{8.14019, 1810.94, 244.485};
const Antoine& antoine_for(Real celsius) { return celsius < 100 ? kLow : kHigh; }
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

Real saturation_vapour_pressure_slope(Real celsius) {
  return slope_of_saturation_pressure(saturation_vapour_pressure(celsius), celsius);
}

Real SorptionIsotherm::activity(Real moisture, Real celsius) const {
  if (!(moisture > 0)) return 0;
  const Real a = std::exp(oswin_a_slope * (celsius + kZeroCelsius) + oswin_a_offset);
  const Real y = std::pow(100.0 * moisture / a, 1.0 / oswin_exponent);
  return y / (1 + y);
}

Real PoreWater::vapour_density(Real celsius, Real moisture_now) const {
  const Real theta = std::min(celsius, boiling_point);
  const Real p = sorption.activity(moisture_now, theta) * saturation_vapour_pressure(theta);
  return p * kWaterMolarMass / (kGasConstant * (theta + kZeroCelsius));
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
  if (!(cell_heat_pipe > 0) || !(moisture_now > 0) || !(celsius < boiling_point)) return 0;
  const Real tk = std::max(celsius, Real(-50)) + kZeroCelsius;
  const Real p = saturation_vapour_pressure(celsius), dp = slope_of_saturation_pressure(p, celsius);
  const Real drho_sat = kWaterMolarMass / (kGasConstant * tk) * (dp - p / tk);  // d(p M / R T)/dθ
  const Real free_diffusivity = vapour_diffusivity * power_1_75(tk / 298.15);
  return cell_heat_pipe * phi * latent_heat * free_diffusivity * sorption.activity(moisture_now, celsius) * drho_sat;
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
