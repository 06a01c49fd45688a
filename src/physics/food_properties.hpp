#pragma once
// Thermal properties of a food from its composition: Choi & Okos (1986),
// "Effects of temperature and composition on the thermal properties of foods",
// in Food Engineering and Process Applications, vol. 1, pp. 93-101 (Elsevier),
// as tabulated in the ASHRAE Handbook - Refrigeration, "Thermal properties of
// foods". Each major component (water, protein, fat, carbohydrate, fibre,
// ash) has a density, specific heat and conductivity quadratic in the
// temperature (°C, valid -40...150 °C); the food's
//   density        1/ρ = Σ x_i/ρ_i        (mass fractions x_i), times (1 − ε) for air,
//   specific heat  c = Σ x_i c_i,
//   conductivity   k = Σ v_i k_i          (volume fractions v_i = (x_i/ρ_i) ρ, the parallel model),
// and a porosity ε (the volume share of air, e.g. a risen dough or a whipped
// batter) puts air in parallel: k ← (1 − ε) k + ε k_air. docs/materials.md.
#include <array>

#include "core/types.hpp"

namespace bakesim {

enum class FoodComponent { water, protein, fat, carbohydrate, fibre, ash };
inline constexpr int kFoodComponents = 6;

// Mass fractions, summing to 1 (carbohydrate without the fibre).
struct FoodComposition {
  std::array<Real, kFoodComponents> mass_fraction{};  // in FoodComponent order
  Real porosity = 0;                                  // volume share of air
  Real& operator[](FoodComponent c) { return mass_fraction[int(c)]; }
  Real operator[](FoodComponent c) const { return mass_fraction[int(c)]; }
  Real total() const {
    Real s = 0;
    for (Real x : mass_fraction) s += x;
    return s;
  }
};

struct ThermalProperties {
  Real density;        // kg/m³ (with the air)
  Real specific_heat;  // J/(kg K)
  Real conductivity;   // W/(m K)
};

// One component's properties at temperature_c (°C).
ThermalProperties component_properties(FoodComponent c, Real temperature_c);
// The food's, at temperature_c.
ThermalProperties food_properties(const FoodComposition& food, Real temperature_c);

}  // namespace bakesim
