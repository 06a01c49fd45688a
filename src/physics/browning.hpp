#pragma once
// Crust browning kinetics (Zanoni, Peri & Bruno 1995, LWT 28:604): the colour
// difference ΔE between the raw dough and the heated crust follows first-order
// kinetics towards the burnt value ΔE∞,
//   dΔE/dt = k(θ) (ΔE∞ − ΔE),   k(θ) = k0 exp(−Ea / (R θ_K)),
// measured on dried crumb at 140–250 °C: ΔE∞ = 52, k0 = 42 000 1/s,
// Ea = 64 151 J/mol. The state each solver carries is the browning index
// B = ΔE / ΔE∞ in [0, 1): 0 raw, → 1 burnt. Browning runs on the bake clock.
#include <cmath>
#include <vector>

#include "core/parallel.hpp"
#include "core/types.hpp"
#include "physics/constants.hpp"

namespace bakesim {

struct BrowningKinetics {
  Real max_colour_difference = 52.0;  // ΔE∞ (CIE L*a*b* distance of the burnt crust)
  Real rate_constant = 42000.0;       // k0, 1/s
  Real activation_energy = 64151.0;   // Ea, J/mol

  // k(θ) in 1/s for a temperature in °C.
  Real rate(Real temperature_c) const {
    return rate_constant * std::exp(-activation_energy / (kGasConstant * (temperature_c + kZeroCelsius)));
  }
  // Exact over a step at constant temperature: B ← 1 − (1 − B) e^{−k Δt}.
  Real advance(Real index, Real temperature_c, Real dt_bake) const {
    return 1.0 - (1.0 - index) * std::exp(-rate(temperature_c) * dt_bake);
  }
  Real colour_difference(Real index) const { return index * max_colour_difference; }
  // Every particle's index over one step of bake time dt_bake, each at its own
  // temperature (the browning phase of both solvers).
  void advance_all(std::vector<Real>& index, const std::vector<Real>& temperature, Real dt_bake) const {
    parallel_for(index.size(), [&](std::size_t i) { index[i] = advance(index[i], temperature[i], dt_bake); });
  }
};

}  // namespace bakesim
