#pragma once
// The oven both solvers bake in: the air temperature over bake time, the air's
// heat transfer coefficient, the bake clock, and the browning kinetics; and the
// temperatures of heated colliders at one bake time.
//
// Bake clock (docs/physics.md): heat, water, gas and browning run
// `bake_time_scale` times faster than the mechanics, so a real bake of
// scale × T seconds is simulated in T seconds of mechanics. Schedules (the
// air's, the colliders') are given in bake time.
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include "core/types.hpp"
#include "physics/browning.hpp"
#include "physics/curves.hpp"
#include "physics/heat.hpp"
#include "physics/water.hpp"

namespace bakesim {

// Air pressure (Pa) at an altitude (m above sea level) in the ICAO/ISO 2533
// standard atmosphere's troposphere: p = p₀ (1 − L h / T₀)^(g M / (R L)) with
// p₀ 101,325 Pa, T₀ 288.15 K, lapse rate L 0.0065 K/m (89.9 kPa at 1,000 m,
// 79.5 kPa at 2,000 m). The day's weather moves it by about ±1.5 kPa.
inline Real standard_atmosphere_pressure(Real altitude) {
  constexpr Real kLapse = 0.0065, kSeaLevelKelvin = 288.15, kExponent = 5.25588;  // g M / (R L)
  return kAtmosphere * std::pow(1 - kLapse * altitude / kSeaLevelKelvin, kExponent);
}

struct Oven {
  PiecewiseLinear air_temperature = PiecewiseLinear::constant(20.0);  // °C over bake time (s)
  Real heat_transfer_coefficient = 10.0;                              // β of the air, W/(m² K)
  // ε of the food's surface facing the oven's walls, which are at the air's
  // temperature (0: no radiation). Radiation adds to the air's coefficient
  // (physics/heat.hpp, radiative_coefficient); it moves no water.
  Real emissivity = 0;
  Real bake_time_scale = 1.0;                     // bake seconds per simulated second
  BrowningKinetics browning;                      // crust colour from the temperature history
  Real air_vapour_density = 0;                    // ρ_v of the oven air, kg/m³
  std::optional<Real> mass_transfer_coefficient;  // h_m, m/s (none: Chilton–Colburn from h)
  // The air's pressure, Pa: where free water boils (99.2 °C at 235 m, 95.0 °C
  // at about 1,500 m) and how fast vapour diffuses and leaves.
  Real air_pressure = kAtmosphere;

  Real boiling_point() const { return boiling_point_at(air_pressure); }
  // Bake time at simulated time t, and the bake-time length of a mechanics step.
  Real bake_time(Real time) const { return time * bake_time_scale; }
  Real bake_step(Real dt) const { return dt * bake_time_scale; }
  // Air temperature (°C) at simulated time t.
  Real air_at(Real time) const { return air_temperature(bake_time(time)); }
  // The coefficient between the surface at `surface` °C and the oven at `air` °C:
  // convection and, with an emissivity, radiation from the walls (W/(m² K)).
  Real surface_coefficient(Real surface, Real air) const {
    return heat_transfer_coefficient + radiative_coefficient(emissivity, surface, air);
  }
  // h_m (m/s) of vapour leaving a moist surface at simulated time t (physics/water.hpp).
  Real mass_transfer_at(Real time) const {
    return mass_transfer_coefficient
               ? *mass_transfer_coefficient
               : bakesim::mass_transfer_coefficient(heat_transfer_coefficient, air_at(time), air_pressure);
  }
};

// The temperature of each collider at one bake time, read once per step from
// its schedule (0 for a collider without one) and looked up per particle or
// node. Sized once: reading again does not allocate.
class ColliderTemperatures {
 public:
  // `schedule(i)` returns collider i's optional temperature schedule.
  template <class Schedule>
  void read(std::size_t colliders, Schedule&& schedule, Real bake_time) {
    values_.assign(colliders, 0.0);
    for (std::size_t i = 0; i < colliders; ++i) {
      const std::optional<PiecewiseLinear>& s = schedule(i);
      if (s) values_[i] = (*s)(bake_time);
    }
  }
  Real operator[](std::size_t i) const { return values_[i]; }
  std::size_t size() const { return values_.size(); }

 private:
  std::vector<Real> values_;
};

}  // namespace bakesim
