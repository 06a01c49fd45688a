#pragma once
// Crust browning kinetics (Zanoni, Peri & Bruno 1995, LWT 28:604): the colour
// difference ΔE between the raw dough and the heated crust follows first-order
// kinetics towards the burnt value ΔE∞,
//   dΔE/dt = k(θ) (ΔE∞ − ΔE),   k(θ) = k0 exp(−Ea / (R θ_K)),
// measured on dried crumb at 140–250 °C: ΔE∞ = 52, k0 = 42 000 1/s,
// Ea = 64 151 J/mol. The state each solver carries is the browning index
// B = ΔE / ΔE∞ in [0, 1): 0 raw, → 1 burnt. Browning runs on the bake clock.
#include <cmath>

#include "core/types.hpp"
#include "physics/constants.hpp"

namespace bakesim {

// How far past its boiling point moist dough's surface must be to brown: one
// kelvin, above the boiling line of dough still holding 0.3 kg/kg (100.9 °C
// with the default isotherm: bound water boils a little above θ_b,
// physics/water.hpp), so the moist crumb's plateau does not count.
inline constexpr Real kBrowningAboveBoiling = 1.0;

struct BrowningKinetics {
  Real max_colour_difference = 52.0;  // ΔE∞ (CIE L*a*b* distance of the burnt crust)
  Real rate_constant = 42000.0;       // k0, 1/s
  Real activation_energy = 64151.0;   // Ea, J/mol

  // k(θ) in 1/s for a temperature in °C.
  Real rate(Real temperature_c) const {
    return rate_constant * std::exp(-activation_energy / (kGasConstant * (temperature_c + kZeroCelsius)));
  }
  // Exact over a step at constant temperature: B ← 1 − (1 − B) e^{−k Δt}.
  // Nearly every step is short against browning's time scale (k Δt stays
  // below 1e-3 on 0.03 s of bake, a bake clock's step, up to a 276 °C face),
  // and there e^{−x} is its series to x⁴: the first term left out, x⁵/120, is
  // below 1e-17, under the double's round-off; one exp call less a particle
  // and step.
  Real advance(Real index, Real temperature_c, Real dt_bake) const {
    const Real x = rate(temperature_c) * dt_bake;
    const Real decay = x < 1e-3 ? 1 - x * (1 - x * (0.5 - x * (1.0 / 6 - x * (1.0 / 24)))) : std::exp(-x);
    return 1.0 - (1.0 - index) * decay;
  }
  Real colour_difference(Real index) const { return index * max_colour_difference; }
  // Over one step where the surface is above `from` °C, else unchanged. Moist
  // dough browns only once it has dried past the boiling point (the spec's
  // "browning then runs only where the crust is above 100 °C"; Zanoni et al.
  // measured the kinetics on dried crumb): the crumb, held at or below it by
  // its water, stays pale. Materials without water pass −∞ and brown at any
  // temperature.
  Real advance_above(Real index, Real temperature_c, Real from_c, Real dt_bake) const {
    return temperature_c > from_c ? advance(index, temperature_c, dt_bake) : index;
  }
};

}  // namespace bakesim
