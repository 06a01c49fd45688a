#pragma once
// Heat exchange laws shared by the solvers.
#include <cmath>

#include "core/types.hpp"
#include "physics/constants.hpp"

namespace bakesim {

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

// SPH pair conduction (thesis Eq 3.45–3.46 in the Cleary–Monaghan form, which
// is always diffusive and exchanges heat pairwise, so energy is conserved):
//   (∇·k∇T)_i = Σ_j V_j (k_i + k_j)(T_i − T_j) x_ij·∇W_ij / (r² + η²),
// with x_ij·∇W_ij = r² W'(r)/r. Returns the pair's term; their sum over j is
// ρ_i c_p dT_i/dt (W' < 0, so heat flows from the hotter particle to the colder).
inline Real pair_conduction(Real volume_j, Real conductivity_i, Real conductivity_j, Real temperature_i,
                            Real temperature_j, Real dw_dr_over_r, Real r, Real eta2) {
  return volume_j * (conductivity_i + conductivity_j) * (temperature_i - temperature_j) * (dw_dr_over_r * r * r) /
         (r * r + eta2);
}

// Thermal radiation between a surface and the oven's walls around it (a small
// grey body in a large enclosure, Stefan–Boltzmann): q = ε σ (T_w⁴ − T⁴), in
// Newton's form q = h_r (T_w − T) with the radiative coefficient
//   h_r = ε σ (T_w² + T²)(T_w + T)   (kelvin; exact, not a linearisation),
// evaluated at the surface's temperature at the start of a step (W/(m² K)).
// Temperatures in °C; ε of the food's surface.
inline Real radiative_coefficient(Real emissivity, Real surface_celsius, Real wall_celsius) {
  if (!(emissivity > 0)) return 0.0;
  const Real t = surface_celsius + kZeroCelsius, w = wall_celsius + kZeroCelsius;
  return emissivity * kStefanBoltzmann * (w * w + t * t) * (w + t);
}

// Surface heat exchange, the one law both solvers use for the oven air and
// for hot colliders (Newton's law of cooling; thesis Eq 3.42–3.43, spec 4.3's
// boundary term): a surface element exchanges q = Σ_c β_c A_c (θ_c − θ) with
// everything it faces (the air with `environment.heat_transfer_coefficient`,
// a heated collider with its own coefficient). SPH gives each surface particle
// one outside (the collider it touches, else the air) and integrates exactly
// (`relax`); MPM sums the parts of each grid node's boundary area facing the
// air and the colliders and carries the rate to the particles.
struct SurfaceExchange {
  Real conductance = 0;  // Σ β A, W/K
  Real drive = 0;        // Σ β A θ_out, W

  // Adds a part of the surface: area A (m²) facing an outside at θ_out (°C) through β (W/(m² K)).
  void add(Real area, Real beta, Real outside) {
    conductance += area * beta;
    drive += area * beta * outside;
  }
  // Heat flowing in at temperature θ, W (explicit rate).
  Real heat_rate(Real temperature) const { return drive - conductance * temperature; }
  // One outside temperature, integrated exactly over dt (never overshoots).
  static Real relax(Real temperature, Real outside, Real beta, Real area, Real heat_capacity, Real dt) {
    return exchange_temperature(temperature, outside, beta * area, heat_capacity, dt);
  }
};

}  // namespace bakesim
