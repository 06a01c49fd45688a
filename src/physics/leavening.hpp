#pragma once
// CO2 from a chemical leavener and its pressure in the pores (spec mpm-baking.md 3.3).
#include <algorithm>
#include <limits>

#include "core/types.hpp"
#include "physics/constants.hpp"

namespace bakesim {

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
  // n after dt of bake time, never beyond the leavener's amount.
  Real generated(Real moles, Real dt, Real temperature, Real density) const {
    return generated_at(moles, dt, profile(Lane4::Constant(temperature))[0], density);
  }
  // The same with the temperature's factor exp(−z²) given, and that factor for
  // four temperatures at once on a SIMD vector (Eigen's exp; the MPM
  // constitutive phase takes four particles at a time, generated one lane).
  Real generated_at(Real moles, Real dt, Real profile, Real density) const {
    return std::min(moles + dt * (rate * density * profile), std::max(moles, amount * density));
  }
  Lane4 profile(const Lane4& temperature) const {
    const Lane4 z = (temperature - peak_temperature) / width;
    return (-z * z).exp();
  }
  // J·P (the Kirchhoff pressure) for n moles per initial volume; the porosity
  // is floored at `kMinPorosity` so a dough without pores cannot reach an
  // infinite pressure.
  static constexpr Real kMinPorosity = 0.02;
  static Real kirchhoff_pressure(Real moles, Real temperature, Real porosity) {
    return moles * kGasConstant * (temperature + kZeroCelsius) / std::max(porosity, kMinPorosity);
  }
};

}  // namespace bakesim
