#pragma once
// Irreversible setting of the viscoplastic dough (spec mpm-baking.md 3.2, paper
// Fig 8): temperature-dependent yield stress and viscosity, frozen at the
// gelatinization temperature once a particle reaches it, and the brittleness
// of the dried set crust (a departure, docs/physics.md).
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/types.hpp"
#include "physics/curves.hpp"

namespace bakesim {

// Irreversible setting, one rule for both solvers (scene key
// materials.NAME.set_temperature): until a particle first reaches θ_set its
// temperature-dependent properties follow its current temperature; from then
// on they follow the highest temperature it has reached, so baked dough stays
// set when it cools. θ_set = −273.15 °C: set from the start (the thesis's
// irreversible curves, always at the peak); +∞: never (reversible curves).
// With MPM curves that are flat beyond θ_set (the paper's Fig 8 ends at θ4)
// this is the paper's rule: a gelatinized particle keeps the values at θ4.
struct IrreversibleSetting {
  Real temperature = std::numeric_limits<Real>::infinity();  // θ_set, °C
  bool ever() const { return temperature < std::numeric_limits<Real>::infinity(); }
  bool is_set(Real peak_temperature) const { return peak_temperature >= temperature; }
  // The temperature the property curves are read at.
  Real property_temperature(Real temperature_now, Real peak_temperature) const {
    return is_set(peak_temperature) ? peak_temperature : temperature_now;
  }
};

// Temperature dependence of the viscoplastic parameters (spec 3.2, paper
// Fig 8): piecewise-linear τ_y(θ) and η(θ), read at the temperature the
// setting rule gives.
struct SettingCurves {
  PiecewiseLinear yield_stress;
  PiecewiseLinear viscosity;
  // Brittleness of the dried set material (a departure, docs/physics.md): a set
  // particle's τ_y × exp(−k b (J^P/J^P_set − 1)) for plastic dilation past
  // J^P_set, its value at setting. b ramps from 0 to 1 as the fraction d of its
  // water the particle has lost goes from d_b to 2 d_b (a dried, glassy crust
  // is brittle; the moist crumb below keeps its strength). k = 0: the paper.
  Real set_softening = 0;          // k
  Real brittle_water_loss = 0.05;  // d_b
  Real softening_factor(Real plastic_j, Real plastic_j_at_set, Real water_lost) const {
    if (set_softening <= 0 || plastic_j <= plastic_j_at_set || water_lost <= brittle_water_loss) return 1;
    const Real b = std::min((water_lost - brittle_water_loss) / brittle_water_loss, Real(1));
    return std::exp(-set_softening * b * (plastic_j / plastic_j_at_set - 1));
  }
};

}  // namespace bakesim
