#pragma once
// Physical constants, in one place (SI units; temperatures at the interface in °C).
#include "core/types.hpp"

namespace bakesim {

inline constexpr Real kZeroCelsius = 273.15;              // K at 0 °C
inline constexpr Real kGasConstant = 8.314462618;         // R, J/(mol K) (CODATA 2018, exact)
inline constexpr Real kStefanBoltzmann = 5.670374419e-8;  // σ, W/(m² K⁴) (CODATA 2018, exact)
inline constexpr Real kWaterDensity = 1000.0;             // ρ_w, kg/m³ (liquid water, as the spec's mixture)

}  // namespace bakesim
