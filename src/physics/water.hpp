#pragma once
// Water, vapour and latent heat in baking dough: the one law both solvers use
// (docs/physics.md "Water, vapour and latent heat"; shared/spec
// water-and-latent-heat.md, after Thorvaldsson & Janestad 1999 and Zhang &
// Datta 2006).
//
// Per particle the state is its liquid water W (kg) beside the dry solid it
// belongs to; the vapour in the pores is in local equilibrium with it,
//   ρ_v = a_w(X, T) p_sat(T) M_w / (R T_K),   X = W / m_dry (dry basis),
// and is not stored: φ_g ρ_v is under 0.6 kg/m³ against 100–200 kg/m³ of
// liquid (0.3–0.6%), and leaving its storage out removes the vapour's own
// time scale (Δx²/D_v, milliseconds) from the step. What moves is
//   vapour   q_v = −φ_g D_v(T) ∇ρ_v            (evaporates where it leaves,
//                                                condenses where it arrives,
//                                                carrying h_fg: the heat pipe)
//   liquid   q_w = −D_w(T) ∇c_w,  c_w = W / V   (Fick; no latent heat)
//   surface  m = h_m (ρ_v,s − ρ_v,air)          (leaves as vapour, takes h_fg)
// and the boiling cap: the pores are open to the oven, so moist dough does not
// heat past the boiling point; the energy beyond it boils water off (vented),
// and only dry dough (the crust) heats further.
#include <algorithm>
#include <cmath>
#include <optional>

#include <limits>

#include "core/types.hpp"
#include "physics/browning.hpp"
#include "physics/constants.hpp"
#include "physics/heat.hpp"

namespace bakesim {

inline constexpr Real kWaterMolarMass = 0.018015;  // M_w, kg/mol
inline constexpr Real kAtmosphere = 101325.0;      // p_atm, Pa
inline constexpr Real kLatentHeatAt100 = 2.257e6;  // h_fg at 100 °C, J/kg (steam tables)
inline constexpr Real kAirMolarMass = 0.028965;    // kg/mol, dry air
inline constexpr Real kAirSpecificHeat = 1012.0;   // J/(kg K), dry air at 100–200 °C (1009–1023)

// Saturation vapour pressure of water (Pa) at θ °C: the Antoine equation,
// log₁₀ p[mmHg] = A − B / (C + θ), with the constants for 1–100 °C
// (A 8.07131, B 1730.63, C 233.426) and for 99–374 °C (A 8.14019, B 1810.94,
// C 244.485) (Dortmund Data Bank constants as tabulated for water), switched
// where they meet, at 108.27 °C, so that p_sat is continuous; it stays within
// 1% of the IAPWS-IF97 saturation line from 20 to 180 °C and within 0.4% up to
// 120 °C (tests/unit/test_water.cpp).
Real saturation_vapour_pressure(Real celsius);
// d p_sat / dθ, Pa/K.
Real saturation_vapour_pressure_slope(Real celsius);
// θ (°C) where p_sat(θ) = p (Pa): the same Antoine equation solved for θ.
Real saturation_temperature(Real pressure);
// The boiling point of free water under the pressure p (Pa), °C: the Antoine
// curve's saturation temperature, shifted by its 0.003 K error at 1 atm so that
// water boils at exactly 100 °C there (95.0 °C at 84.6 kPa, about 1,500 m up).
Real boiling_point_at(Real pressure);
// r^1.75 = r √(r √r) (the temperature law of vapour diffusivity, every
// particle every step: two square roots cost less than pow).
inline Real power_1_75(Real r) { return r * std::sqrt(r * std::sqrt(r)); }

// Water activity of the dough from its moisture X (kg water / kg dry solid):
// the Oswin isotherm X = (a / 100) (a_w / (1 − a_w))ⁿ with a = exp(c₁ T_K + c₂),
// inverted: a_w = y / (1 + y), y = (100 X / a)^(1/n). a_w → 0 as the dough
// dries and → 1 for moist dough.
struct SorptionIsotherm {
  // The scene's defaults (schema): a_w 0.97 at X = 0.3, 0.45 at X = 0.1.
  Real oswin_a_slope = 0;       // c₁, 1/K
  Real oswin_a_offset = 2.361;  // c₂ (a = 10.6)
  Real oswin_exponent = 0.3;    // n
  Real activity(Real moisture, Real celsius) const;
  // The isotherm inverted: the moisture X in equilibrium with activity a_w at θ.
  Real moisture_at(Real water_activity, Real celsius) const;
  // The same from parts, for a caller that evaluates the isotherm many times at
  // one θ (the surface's face solve): a = exp(c₁ T_K + c₂) once, then
  // y = (100 X / a)^(1/n), a_w = y / (1 + y), and X(a_w) at that a.
  Real prefactor(Real celsius) const;
  Real activity_ratio(Real moisture, Real prefactor) const;
  Real moisture_with_prefactor(Real water_activity, Real prefactor) const;
};

// The material's water: the parameters of the law above.
struct PoreWater {
  Real moisture = 0;                 // initial X₀, kg/kg dry; 0: no water
  Real liquid_diffusivity = 0;       // D_w at 100 °C, m²/s; D_w(θ) = D_w θ⁺ / 100 °C
  Real vapour_diffusivity = 2.6e-5;  // D_v of vapour in the pore gas at 25 °C, m²/s
  Real tortuosity = 1;               // τ: the effective D is φ_g D_v (T_K / 298.15)^1.75 / τ
  Real gas_fraction = 0.6;           // φ_g, volume fraction of gas in the dough
  Real cell_heat_pipe = 1;           // share of the closed-cell heat pipe (below), 0–1
  // The crumb's cells open as it bakes (a foam becomes a sponge) and the
  // closed-cell heat pipe stops: its share falls by the opened fraction
  // 1/2 + atan((θ − θ_open)/w)/π (the pores-opening function of
  // breadBakingFoam, github.com/techMathGroup/breadBakingFoam, opening at
  // 75 °C in their set-up of the Zhang loaf). Vapour then moves only through
  // the pores (vapour_conductance).
  std::optional<Real> pore_opening_temperature;  // θ_open, °C; none: the cells stay closed
  Real pore_opening_width = 1.25;                // w, K
  // Share of the cells still closed at θ: 1 without pore opening.
  Real closed_cell_share(Real celsius) const {
    if (!pore_opening_temperature) return 1;
    return 0.5 - std::atan((celsius - *pore_opening_temperature) / pore_opening_width) / kPi;
  }
  std::optional<Real> dry_conductivity;  // k of the dried dough (crust), W/(m K); none: the material's
  Real latent_heat = kLatentHeatAt100;   // h_fg, J/kg
  // How water leaves a surface element below the boiling point (surface_flux).
  enum class SurfaceEvaporation { free, supply_limited };
  SurfaceEvaporation surface_evaporation = SurfaceEvaporation::free;
  Real boiling_point = 100;         // θ_b, °C: boiling_point_at(the oven's air pressure) unless the scene gives it
  Real air_pressure = kAtmosphere;  // p of the pore gas (the oven's air), Pa: D_v ∝ 1/p
  SorptionIsotherm sorption;

  bool active() const { return moisture > 0; }
  // Dry basis: a particle of mass m is dry solid and water, m_w = m X₀ / (1 + X₀) at the start.
  Real initial_water(Real mass) const { return mass * moisture / (1 + moisture); }
  Real moisture_of(Real water, Real mass) const { return water * (1 + moisture) / mass; }
  Real dry_mass(Real mass) const { return mass / (1 + moisture); }
  // Bound water (boiling-point elevation by sorption): the pores are open to
  // the oven at the pressure p_b = p_sat(θ_b), and water held at activity a_w
  // boils where its vapour pressure a_w(X, θ) p_sat(θ) reaches p_b. Above θ_b
  // dough therefore keeps the moisture boiling_moisture(θ) = X(a_w = p_b /
  // p_sat(θ)) of its isotherm (∞ at or below θ_b, where free water boils): with
  // the default isotherm moist crumb (X = 0.5, a_w 0.994) boils 0.16 K above
  // θ_b, and a crust at 160 °C keeps 0.065 kg/kg instead of boiling dry.
  Real boiling_moisture(Real celsius) const;
  // d boiling_moisture / dθ, kg/(kg K) (< 0).
  Real boiling_moisture_slope(Real celsius) const;
  // The temperature at which dough of moisture X boils (the inverse of the
  // above; θ_b for X at or above the isotherm's a_w → 1, up to 370 °C).
  Real boiling_temperature(Real moisture_now) const;
  // Equilibrium vapour density in the pore gas, kg/m³, never above the boiling point's.
  Real vapour_density(Real celsius, Real moisture_now) const;
  // The gas fraction of dough that has expanded to `volume_ratio` times its
  // initial volume: the volume it gained is gas, φ = 1 − (1 − φ₀)/J (≤ 0.95).
  Real expanded_gas_fraction(Real volume_ratio) const {
    return std::clamp(1 - (1 - gas_fraction) / std::max(volume_ratio, Real(1e-3)), gas_fraction, Real(0.95));
  }
  // φ_g D_eff(θ), the coefficient of q_v = −(φ_g D) ∇ρ_v, m²/s.
  Real vapour_conductance(Real celsius, Real phi) const {
    const Real tk = std::max(celsius, Real(-50)) + kZeroCelsius;
    return phi * free_vapour_diffusivity(tk) / tortuosity;
  }
  // D_v of vapour in air at T_K and the air's pressure (binary diffusion goes as T^1.75 / p).
  Real free_vapour_diffusivity(Real kelvin) const {
    return vapour_diffusivity * power_1_75(kelvin / 298.15) * (kAtmosphere / air_pressure);
  }
  Real vapour_conductance(Real celsius) const { return vapour_conductance(celsius, gas_fraction); }
  // The closed-cell heat pipe, W/(m K): in each gas cell of moist dough water
  // evaporates on the warm wall, the vapour crosses the cell by free diffusion
  // and condenses on the cool wall, and the condensate returns through the cell
  // walls, so heat moves without net water (de Vries 1958; for bread, Zhang et
  // al. 2025 find it carries about 60% of the crumb's effective conductivity in
  // closed pores): k_cell = share · φ_g h_fg D_v(θ) a_w dρ_sat/dθ, with the free
  // diffusivity (no tortuosity: the vapour crosses one cell). Added to the
  // conductivity of moist dough below the boiling point.
  Real cell_conductivity(Real celsius, Real moisture_now, Real phi) const;
  // Both of one particle at once, vapour_density and cell_conductivity to the
  // bit, from one saturation pressure and one activity (each evaluates both;
  // the MPM constitutive phase takes the two for every moist point every step).
  struct PoreVapour {
    Real density, cell_conductivity;
  };
  PoreVapour pore_vapour(Real celsius, Real moisture_now, Real phi) const;
  // The conductivity change of dough that has dried from X₀ to X, W/(m K):
  // linear from the material's k (moist) to dry_conductivity (dry), so a crust
  // insulates the crumb (shared/spec: 0.2–0.4 crumb, 0.05–0.1 crust).
  Real drying_conductivity_change(Real conductivity, Real moisture_now) const {
    if (!dry_conductivity || !(moisture > 0)) return 0;
    return dried_fraction(moisture_now) * (*dry_conductivity - conductivity);
  }
  // How the conductivity follows the dough's expansion (expanded_gas_fraction):
  // `constant` keeps it (the seeds), `parallel` puts the solid matrix and the
  // gas side by side, k(φ) = k_m (1 − φ) + k_g φ with k_m from the unexpanded
  // dough's k at φ₀, so a loaf that doubles its volume conducts through half
  // the solid (the parallel model Jury, Monteau, Comiti & Le-Bail 2007 fit to
  // bread's conductivity during baking).
  enum class ExpandedConductivity { constant, parallel };
  ExpandedConductivity expanded_conductivity = ExpandedConductivity::constant;
  // k of the pore gas, W/(m K): air at 300 K (Incropera, Table A.4: 0.0263).
  static constexpr Real kGasConductivity = 0.0263;
  // The conductivity change of dough of the material's k that has dried to X
  // and expanded to gas fraction φ: drying_conductivity_change, then the
  // expansion law applied to the dried dough's k.
  Real matrix_conductivity_change(Real conductivity, Real moisture_now, Real phi) const {
    const Real drying = drying_conductivity_change(conductivity, moisture_now);
    if (expanded_conductivity == ExpandedConductivity::constant || !(phi > gas_fraction)) return drying;
    const Real unexpanded = conductivity + drying;
    const Real matrix = std::max(unexpanded - kGasConductivity * gas_fraction, Real(0)) / (1 - gas_fraction);
    return matrix * (1 - phi) + kGasConductivity * phi - conductivity;
  }
  // Share of the particle's water gone, 0 (as mixed) to 1 (dry): the outer
  // part of a surface particle that has dried into crust (physics/heat.hpp,
  // CrustFace). Water that condensed above the initial content counts as 0.
  Real dried_fraction(Real moisture_now) const {
    if (!(moisture > 0)) return 1;
    return std::clamp(1 - moisture_now / moisture, Real(0), Real(1));
  }
  // k of the dried crust: dry_conductivity, or the material's k (no heat pipe: no water).
  Real crust_conductivity(Real conductivity) const { return dry_conductivity.value_or(conductivity); }
  // The profile from a particle of this moist dough to its face (physics/heat.hpp): L from its centre, its
  // moisture X and water W now, the material's k; its moist part conducts with k_m.
  CrustFace crust_face(Real face_distance, Real moisture_now, Real water, Real conductivity,
                       Real moist_conductivity) const {
    CrustFace face;
    face.face_distance = face_distance;
    face.dried_fraction = dried_fraction(moisture_now);
    face.crust_conductivity = crust_conductivity(conductivity);
    face.moist_conductivity = moist_conductivity;
    face.moist = water > 0;
    face.boiling_point = boiling_point;
    return face;
  }
  // The temperature a surface must pass to brown (physics/browning.hpp, advance_above): moist dough's
  // boiling point when the solver carries its moisture (`carried`), else −∞ (browns at any temperature).
  Real browning_threshold(bool carried) const {
    return carried && active() ? boiling_point + kBrowningAboveBoiling : -std::numeric_limits<Real>::infinity();
  }
  Real liquid_diffusion(Real celsius) const { return liquid_diffusivity * std::max(celsius, Real(0)) / 100.0; }
  // Water leaving a surface element (particle or point) of dry mass m_d,
  // volume V and area A facing the air at θ with moisture X, kg/(m² s)
  // (< 0: the air's vapour condenses), by m = h_m (ρ_v,face − ρ_v,air).
  // `free`: the face holds the element's mean moisture, ρ_v,face = ρ_v(θ, X).
  // `supply_limited`: the face dries ahead of the element, and the liquid
  // reaches it by diffusion across the depleted layer inside the element
  // (an element is millimetres thick, the layer a fraction of one early in a
  // bake). For a layer of initial moisture X₀ and dry density ρ_d = m_d / V
  // whose face has stood at X_s, the profile is Fick's erfc one (Crank 1975,
  // Eq 3.14), which passes J = ρ_d (X₀ − X_s) √(D_w / (π t)) after losing
  // M = 2 ρ_d (X₀ − X_s) √(D_w t / π) per area; with t eliminated,
  // J = 2 ρ_d² D_w(θ) (X₀ − X_s)² / (π M), M = m_d (X₀ − X) / A the element's
  // own loss per area, taken over the step `step` (bake seconds) exactly (M²
  // grows by 2 K Δt; 0: the instantaneous rate). Once the layer's depth
  // δ = π M / (2 ρ_d X₀) passes the element's face distance L = V / (2A), the
  // element's own loss no longer measures the layer's, and the face takes the
  // resolved gradient from its centre, ρ_d D_w (X − X_s) / L (blended in
  // linearly up to δ = 2L). X_s balances the supply against the air's pull
  // h_m (ρ_v(θ, X_s) − ρ_v,air) (Newton's method in [0, X₀]): a wet face at
  // first (the free rate), then falling-rate drying (liquid_diffusivity > 0;
  // 0 gives no flux). `vapour_now` is the element's ρ_v(θ, X), which the
  // solvers hold.
  Real surface_flux(Real vapour_now, Real celsius, Real moisture_now, Real dry_mass, Real volume, Real area,
                    Real mass_transfer, Real air_vapour, Real step = 0) const;
  // Largest diffusivity of the coupled heat–water system a particle of
  // heat capacity per volume ρc (J/(m³K)) and dry density ρ_dry (kg/m³) sees
  // at θ and X, m²/s: the explicit step bound is Δx² / (2·dim·this).
  Real effective_diffusivity(Real celsius, Real moisture_now, Real heat_capacity_density, Real dry_density) const;
  // What both solvers bound their step by: effective_diffusivity at the hottest
  // moist temperature, over the moistures a drying particle passes (X₀ to
  // X₀/20), for dough of rest density ρ and c_p expanded up to `volume_ratio`
  // (more gas, less heat capacity per volume).
  Real step_diffusivity(Real hottest, Real density, Real specific_heat, Real volume_ratio) const;
};

// The boiling cap on one particle: heat capacity C (J/K), its temperature
// after this step's heat and water fluxes, its liquid water W (kg). Where
// W > 0 and θ > θ_b the energy C (θ − θ_b) boils off up to W (kg) at h_fg;
// whatever is left heats the now dry particle. Energy is conserved exactly:
// C θ_in = C θ_out + h_fg boiled. (Free water only: the solvers use the
// bound-water cap below.)
struct Boiling {
  Real temperature;
  Real water;
  Real boiled;
};
// The boiling cap with bound water (PoreWater::boiling_moisture): a particle
// of dry mass m_d at θ holding W > m_d X_b(θ) boils water off until it lies
// on its boiling line, C (θ − θ_out) = h_fg (W − m_d X_b(θ_out)), solved for
// θ_out by Newton's method from the line's temperature for W (the left side
// falls and the right rises with θ_out; X_b is convex, so the iterates rise
// to the root without passing it); the water left is m_d X_b(θ_out) and
// θ_out = θ − h_fg boiled / C, so energy is conserved exactly.
Boiling boil_bound(const PoreWater& pw, Real heat_capacity, Real temperature, Real water, Real dry_mass);
inline Boiling boil(Real heat_capacity, Real temperature, Real water, Real boiling_point, Real latent_heat) {
  if (!(water > 0) || !(temperature > boiling_point) || !(heat_capacity > 0)) return {temperature, water, 0};
  const Real excess = heat_capacity * (temperature - boiling_point);
  const Real boiled = std::min(water, excess / latent_heat);
  return {boiling_point + (excess - boiled * latent_heat) / heat_capacity, water - boiled, boiled};
}

// One particle's phase change after its water moved: `vapour_gain` kg arrived
// as vapour (< 0: left as vapour) and condenses (evaporates) there, giving
// (taking) h_fg; then the boiling cap (with bound water) on the water it now
// holds. `latent` is the energy the water took with it, J (C θ_in = C θ_out +
// latent). `mass`: the particle's (dry solid and initial water).
struct PhaseChange {
  Real temperature;
  Real water;
  Real boiled;
  Real latent;
};
inline PhaseChange condense_and_boil(const PoreWater& pw, Real heat_capacity, Real temperature, Real water,
                                     Real vapour_gain, Real mass) {
  const Real heated = temperature + pw.latent_heat * vapour_gain / heat_capacity;
  const Boiling b = boil_bound(pw, heat_capacity, heated, water, pw.dry_mass(mass));
  return {b.temperature, b.water, b.boiled, pw.latent_heat * (b.boiled - vapour_gain)};
}

// Surface mass transfer coefficient h_m (m/s) from the heat transfer
// coefficient by the Chilton–Colburn analogy, h_m = h / (ρ_air c_p,air Le^(2/3)),
// with the dry air's density at the oven temperature and pressure (1 atm unless given).
inline Real mass_transfer_coefficient(Real heat_transfer_coefficient, Real air_celsius, Real air_pressure = kAtmosphere,
                                      Real lewis_number = 0.85) {
  const Real tk = std::max(air_celsius, Real(-50)) + kZeroCelsius;
  const Real rho_air = air_pressure * kAirMolarMass / (kGasConstant * tk);
  return heat_transfer_coefficient / (rho_air * kAirSpecificHeat * std::pow(lewis_number, 2.0 / 3.0));
}

}  // namespace bakesim
