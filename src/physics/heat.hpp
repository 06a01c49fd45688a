#pragma once
// Heat exchange laws shared by the solvers.
#include <cmath>

#include "core/types.hpp"

namespace bakesim {

inline constexpr Real kZeroCelsius = 273.15;  // K

// Convective exchange of a lumped particle with an outside temperature
// (thesis Eq 3.42 with the sign and the heat capacity restored):
//   m c_p dT/dt = h A (T_ext − T).
// Integrated exactly over dt, so it never overshoots T_ext whatever the step.
inline Real exchange_temperature(Real temperature, Real outside, Real coefficient_times_area, Real heat_capacity,
                                 Real dt) {
  if (!(coefficient_times_area > 0) || !(heat_capacity > 0)) return temperature;
  const Real rate = coefficient_times_area / heat_capacity;  // 1/s
  return outside + (temperature - outside) * std::exp(-rate * dt);
}

// Energy that entered the particle over that step (J), for bookkeeping.
inline Real exchanged_energy(Real before, Real after, Real heat_capacity) { return heat_capacity * (after - before); }

}  // namespace bakesim
