#pragma once
// Laws of the porous solid–water–CO2 mixture of the thermomechanical MPM
// (spec mpm-baking.md 2–3): leavening gas, water transport and pressure,
// thermal expansion, temperature-dependent viscoplastic parameters with
// irreversible gelatinization. Small value types; the solver reads them once
// per material group and evaluates them per particle.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/types.hpp"
#include "physics/curves.hpp"
#include "physics/heat.hpp"

namespace bakesim {

inline constexpr Real kGasConstant = 8.314462618;  // J/(mol K)

// Gas porosity n = (J^P − 1 + n₀) / J^P (spec 3.2), clamped to [0, 0.95].
inline Real gas_porosity(Real plastic_j, Real initial_porosity) {
  return std::clamp((plastic_j - 1 + initial_porosity) / plastic_j, Real(0), Real(0.95));
}

// CO2 from a chemical leavener (spec 3.3):
//   dn/dt = a · ρ₀ · exp(−((θ − θ_r)/Δθ)²)       n: mol per m³ of initial volume
//   P = n R θ_K / (J n_p)                         gauge pressure (n starts at 0)
struct Leavening {
  Real rate = 0;               // a, mol/(kg s) of bake time
  Real peak_temperature = 40;  // θ_r, °C
  Real width = 20;             // Δθ, °C
  // Moles of CO2 the leavener can give per kg of material (an addition: the
  // spec's Gaussian never runs out, so a cake cooling back through θ_r after
  // the oven would rise again). Infinite: the spec.
  Real amount = std::numeric_limits<Real>::infinity();
  bool active() const { return rate > 0; }
  Real generation_rate(Real temperature, Real density) const {
    const Real z = (temperature - peak_temperature) / width;
    return rate * density * std::exp(-z * z);
  }
  // n after dt of bake time, never beyond the leavener's amount.
  Real generated(Real moles, Real dt, Real temperature, Real density) const {
    return std::min(moles + dt * generation_rate(temperature, density), std::max(moles, amount * density));
  }
  // J·P (the Kirchhoff pressure) for n moles per initial volume; the porosity
  // is floored at `kMinPorosity` so a dough without pores cannot reach an
  // infinite pressure.
  static constexpr Real kMinPorosity = 0.02;
  static Real kirchhoff_pressure(Real moles, Real temperature, Real porosity) {
    return moles * kGasConstant * (temperature + kZeroCelsius) / std::max(porosity, kMinPorosity);
  }
};

// Water carried by the solid (spec 2, 3.4, 4.2). Saturation s = m_w / (ρ_w V).
//   diffusive flux     q = −D(θ) ρ_w ∇s,  D(θ) = diffusivity · θ⁺ / 100 °C
//   evaporation        q·n = E(θ) s,      E(θ) = evaporation_rate · θ⁺ / 100 °C
//   pressure           σ_w = −ξ (s − s₀) I
// (the spec's K θ and β_w θ with θ in °C, parameterised by their values at 100 °C).
struct Moisture {
  Real saturation = 0;        // s₀; 0: the material carries no water
  Real diffusivity = 0;       // m²/s at 100 °C
  Real evaporation_rate = 0;  // kg/(m² s) from a saturated surface at 100 °C
  Real stiffness = 0;         // ξ, Pa
  Real water_density = 1000;  // ρ_w, kg/m³
  bool active() const { return saturation > 0; }
  static Real temperature_factor(Real temperature) { return std::max(temperature, Real(0)) / 100.0; }
  Real diffusion_coefficient(Real temperature) const { return diffusivity * temperature_factor(temperature); }
  Real evaporation_flux(Real temperature, Real s) const {
    return evaporation_rate * temperature_factor(temperature) * s;
  }
  Real pressure(Real s) const { return stiffness * (s - saturation); }
};

// Temperature dependence of the viscoplastic parameters (spec 3.2, paper
// Fig 8): piecewise-linear τ_y(θ) and η(θ); a particle that reaches the
// setting (gelatinization) temperature keeps the values at that temperature.
struct SettingCurves {
  PiecewiseLinear yield_stress;
  PiecewiseLinear viscosity;
  Real set_temperature = std::numeric_limits<Real>::infinity();  // θ4, °C
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
  // The temperature the curves are read at.
  Real effective_temperature(Real temperature, bool gelatinized) const {
    return gelatinized ? set_temperature : temperature;
  }
};

}  // namespace bakesim
