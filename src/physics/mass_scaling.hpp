#pragma once
// Quasi-static mass scaling (docs/physics.md, "Mass scaling"): the material's
// inertia is `factor` times its mass; its weight, heat capacity, water and
// every law stay its own. Both solvers take the forces' and the weight's
// impulse over impulse_step(Δt) and grow their wave-bound steps by
// wave_slowdown().
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "core/types.hpp"

namespace bakesim {

struct MassScaling {
  Real factor = 1;  // s ≥ 1 (solver.mass_scaling); 1: the true dynamics
  bool active() const { return factor != 1; }
  // Δt/s: a force f changes the velocity of the inertia s m by f Δt/(s m).
  Real impulse_step(Real dt) const { return dt / factor; }
  // √s: pressure and elastic waves in the inertia s ρ travel √s times slower.
  Real wave_slowdown() const { return std::sqrt(factor); }
  // The run summary's line (empty at s = 1); `waves`: which waves the solver's step follows.
  std::string summary_line(const char* waves) const {
    if (!active()) return {};
    return fmt::format("inertia    mass scaling x{:g}: {} {:.3g} times slower, quasi-static (docs/physics.md)\n",
                       factor, waves, wave_slowdown());
  }
};

}  // namespace bakesim
