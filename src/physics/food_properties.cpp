#include "physics/food_properties.hpp"

namespace bakesim {

namespace {

struct Quadratic {
  Real c0, c1, c2;
  Real operator()(Real t) const { return c0 + c1 * t + c2 * t * t; }
};

// Choi & Okos (1986): ρ in kg/m³, c in kJ/(kg K), k in W/(m K); t in °C.
struct ComponentLaw {
  Quadratic density, specific_heat, conductivity;
};

constexpr ComponentLaw kLaws[kFoodComponents] = {
    // water
    {{997.18, 3.1439e-3, -3.7574e-3}, {4.1762, -9.0864e-5, 5.4731e-6}, {0.57109, 1.7625e-3, -6.7036e-6}},
    // protein
    {{1329.9, -0.5184, 0}, {2.0082, 1.2089e-3, -1.3129e-6}, {0.17881, 1.1958e-3, -2.7178e-6}},
    // fat
    {{925.59, -0.41757, 0}, {1.9842, 1.4733e-3, -4.8008e-6}, {0.18071, -2.7604e-4, -1.7749e-7}},
    // carbohydrate
    {{1599.1, -0.31046, 0}, {1.5488, 1.9625e-3, -5.9399e-6}, {0.20141, 1.3874e-3, -4.3312e-6}},
    // fibre
    {{1311.5, -0.36589, 0}, {1.8459, 1.8306e-3, -4.6509e-6}, {0.18331, 1.2497e-3, -3.1683e-6}},
    // ash
    {{2423.8, -0.28063, 0}, {1.0926, 1.8896e-3, -3.6817e-6}, {0.32962, 1.4011e-3, -2.9069e-6}},
};

// Still air near room temperature (it barely matters next to the solids).
constexpr Real kAirConductivity = 0.026;

}  // namespace

ThermalProperties component_properties(FoodComponent c, Real t) {
  const ComponentLaw& law = kLaws[int(c)];
  return {law.density(t), 1000.0 * law.specific_heat(t), law.conductivity(t)};
}

ThermalProperties food_properties(const FoodComposition& food, Real t) {
  Real specific_volume = 0, specific_heat = 0;
  std::array<ThermalProperties, kFoodComponents> p{};
  for (int i = 0; i < kFoodComponents; ++i) {
    p[i] = component_properties(FoodComponent(i), t);
    specific_volume += food.mass_fraction[i] / p[i].density;
    specific_heat += food.mass_fraction[i] * p[i].specific_heat;
  }
  const Real solid_density = 1.0 / specific_volume;
  Real conductivity = 0;
  for (int i = 0; i < kFoodComponents; ++i)
    conductivity += food.mass_fraction[i] / p[i].density * solid_density * p[i].conductivity;
  const Real e = food.porosity;
  return {(1 - e) * solid_density, specific_heat, (1 - e) * conductivity + e * kAirConductivity};
}

}  // namespace bakesim
