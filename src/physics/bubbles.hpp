#pragma once
// Bubble particles (thesis 3.3.3, Eq 3.48–3.52) and the Tait law they switch
// back to. Temperatures in the gas law are absolute (kelvin).
#include <algorithm>
#include <cmath>

#include "core/types.hpp"
#include "physics/constants.hpp"

namespace bakesim {

// Eq 3.50: isobaric ideal-gas volume ratio V_b = V_b0 T / T0, V_b0 = 1.
inline Real bubble_volume_ratio(Real temperature_c, Real initial_temperature_c) {
  return (temperature_c + kZeroCelsius) / (initial_temperature_c + kZeroCelsius);
}

// Eq 3.48 with Eq 3.49–3.50: P = B (ρ/ρ0) (V_b − 1). The throttling factor uses
// the particle's SPH density ρ (Eq 3.48), not the bubble density.
inline Real bubble_pressure(Real tait_b, Real density, Real rest_density, Real temperature_c,
                            Real initial_temperature_c) {
  return tait_b * (density / rest_density) * (bubble_volume_ratio(temperature_c, initial_temperature_c) - 1.0);
}

// Eq 3.17 / 3.52: P = B ((ρ/ρ_ref)^γ − 1); ρ_ref is ρ0 before the rise and the
// density recorded when the rise ended (ρ_f) after it, which keeps the risen volume.
inline Real tait_pressure(Real tait_b, Real density, Real reference_density, Real gamma) {
  const Real ratio = density / reference_density;
  const Real power = gamma == 7.0 ? ratio * ratio * ratio * ratio * ratio * ratio * ratio : std::pow(ratio, gamma);
  return tait_b * (power - 1.0);
}

// Reference density of a risen bubble particle that cooled from the
// temperature at which its rise ended: the trapped gas contracts by the gas
// law (never expands past its risen volume), ρ_ref = ρ_f · max(1, T_set/T).
inline Real contracted_reference_density(Real set_density, Real temperature_c, Real set_temperature_c) {
  return set_density * std::max(1.0, bubble_volume_ratio(set_temperature_c, temperature_c));
}

}  // namespace bakesim
