#pragma once
// Heat exchange laws shared by the solvers.
#include <algorithm>
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
// The geometric factor x_ij·∇W_ij / (r² + η²) alone (the SPH heat and water
// phases keep it per pair: both diffuse over the same pairs in one step).
inline Real pair_diffusion_weight(Real dw_dr_over_r, Real r, Real eta2) {
  return (dw_dr_over_r * r * r) / (r * r + eta2);
}
// The pair's term with that factor given (computed once for several phases).
inline Real pair_conduction_weighted(Real volume_j, Real conductivity_i, Real conductivity_j, Real temperature_i,
                                     Real temperature_j, Real weight) {
  return volume_j * (conductivity_i + conductivity_j) * (temperature_i - temperature_j) * weight;
}
inline Real pair_conduction(Real volume_j, Real conductivity_i, Real conductivity_j, Real temperature_i,
                            Real temperature_j, Real dw_dr_over_r, Real r, Real eta2) {
  return pair_conduction_weighted(volume_j, conductivity_i, conductivity_j, temperature_i, temperature_j,
                                  pair_diffusion_weight(dw_dr_over_r, r, eta2));
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

// The temperature of the face a surface particle turns to the oven (or to a
// hot collider), from a quasi-steady profile through the layer the particle
// stands for: from its centre (at its own temperature θ) to its face, a
// distance L. A particle that has lost the fraction f of its water has dried
// from the face in to the depth δ = min(2f, 1) L (the particle's whole
// thickness is 2L; past its centre the front has left this half): that part
// is crust of conductivity k_c, the rest moist dough of k_m. The face takes
// q = h (θ_out − θ_f) and passes it on through R = δ/k_c + (L − δ)/k_m:
//   θ_f = (h θ_out + θ/R) / (h + 1/R).
// Moist dough cannot pass the boiling point θ_b: where the profile would put
// the front above it, the front is pinned at θ_b (an evaporation front) and
// θ_f = (h θ_out + (k_c/δ) θ_b) / (h + k_c/δ). Purlis & Salvadori (2009) model
// the crust the same way, a dried layer over a boiling front; here it is
// resolved inside the particle that holds it (a real crust, 1–3 mm, is thinner
// than most particles). A material without water has f = 1: the half-cell
// profile of its face. k_m = ∞ says the solver already holds the particle at
// its face's temperature where nothing is pinned (MPM's exchange at the grid
// nodes on the face): only a crust then adds to the profile.
// Temperatures in °C, h in W/(m² K), L in m, k in W/(m K).
struct CrustFace {
  Real face_distance = 0;       // L, centre to face, m
  Real dried_fraction = 1;      // f, share of the particle's water gone (1: a material without water)
  Real crust_conductivity = 0;  // k_c, W/(m K)
  Real moist_conductivity = 0;  // k_m, W/(m K); ∞: the particle stands for its face
  bool moist = false;           // holds water, so its wet part stays at or below θ_b
  Real boiling_point = 100;     // θ_b, °C

  Real temperature(Real theta, Real outside, Real coefficient) const {
    if (!(face_distance > 0) || !(coefficient > 0)) return theta;
    const Real crust = std::min(2 * std::clamp(dried_fraction, Real(0), Real(1)), Real(1)) * face_distance;
    const Real moist_resistance = (face_distance - crust) / moist_conductivity;
    const Real resistance = (crust > 0 ? crust / crust_conductivity : 0) + moist_resistance;
    if (!(resistance > 0) || !std::isfinite(resistance)) return theta;
    const Real face = (coefficient * outside + theta / resistance) / (coefficient + 1 / resistance);
    // The front (the crust's inner edge) lies the moist part's share of the drop above θ.
    // A particle hotter than θ_b holds only bound water (physics/water.hpp): its front is its own temperature.
    const Real front = std::max(boiling_point, theta);
    if (!moist || theta + (face - theta) * moist_resistance / resistance <= front) return face;
    if (!(crust > 0)) return front;
    const Real conductance = crust_conductivity / crust;
    return (coefficient * outside + conductance * front) / (coefficient + conductance);
  }
  // The coefficient that gives the particle the face's heat, h (θ_out − θ_f),
  // in Newton's form β (θ_out − θ) (W/(m² K)): the exchange a solver
  // integrates when its particle does not stand for its face (SPH).
  Real coefficient_to_centre(Real theta, Real outside, Real coefficient) const {
    const Real gap = outside - theta;
    if (std::abs(gap) < 1e-9) return coefficient;
    return std::max(coefficient * (outside - temperature(theta, outside, coefficient)) / gap, Real(0));
  }
};

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
