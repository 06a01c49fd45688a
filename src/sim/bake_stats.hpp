#pragma once
// Per-body bake statistics for both solvers, from the particle registry by
// attribute name (stats.csv columns core_temperature:BODY, ...):
//   core_temperature    the coldest particle (the core when heated from outside), °C
//   crust_temperature   the surface temperature, weighted by each particle's
//                       exchange area ("air_area" MPM, "surface_area" SPH), °C
//   water               Σ water_mass, kg                       (where particles carry water)
//   moisture_loss_percent  the share of the body's initial water gone, %
//   weight_loss_percent    the water gone as a share of the body's initial mass, %
//                          (the bake loss a food engineer weighs)
//   crust_thickness     the crust (the dough dried at or past the boiling point)
//                       as a layer over the exchange area: Σ V f / A over the
//                       particles at θ ≥ θ_b − 0.5 K, f = 1 − X/X₀ the share of
//                       a particle's water gone (X₀ the body's initial
//                       moisture), A the exchange area above, m
//   crust_moisture      the outer layer's moisture, kg water / kg dry solid: the
//                       mean over the particles weighted by mass × their outer
//                       share, min(1, A / V^(2/3)) (exchange area over cross-section)
//   crumb_moisture      the same weighted by mass × (1 − outer share)
//                          (these three where particles carry moisture)
//   co2_mol             Σ co2 · initial_volume, mol             (where particles carry CO2)
// Reductions are deterministic: the same state gives the same numbers on any
// thread count.
#include <string>
#include <vector>

#include "core/particles.hpp"

namespace bakesim {

struct BodyBake {
  Real core_temperature = 0, crust_temperature = 0, water = 0, moisture_loss_percent = 0, weight_loss_percent = 0,
       crust_thickness = 0, crust_moisture = 0, crumb_moisture = 0, co2 = 0;
};

class BakeStatistics {
 public:
  // `initial`: the particles before the first step (their water is the
  // reference for the moisture loss); `bodies`: how many bodies there are;
  // `boiling_point`: where the oven's free water boils, °C (the crust is the
  // dough dried at or past it).
  BakeStatistics(const ParticleSet& initial, std::size_t bodies, Real boiling_point = 100);
  // Each body's own boiling point (its material's moisture.boiling_point), one per body.
  BakeStatistics(const ParticleSet& initial, const std::vector<Real>& boiling_points);
  bool has_water() const { return water_; }
  bool has_moisture() const { return moisture_; }
  bool has_co2() const { return co2_; }
  // Column names for one body, in order.
  std::vector<std::string> columns(const std::string& body) const;
  // Values in the order of columns().
  std::vector<Real> values(const BodyBake& b) const;
  std::vector<BodyBake> compute(const ParticleSet& particles) const;

 private:
  std::size_t bodies_;
  std::vector<Real> crust_from_celsius_;  // per body
  bool water_ = false, moisture_ = false, co2_ = false;
  std::vector<Real> initial_water_, initial_mass_, initial_moisture_;
};

}  // namespace bakesim
