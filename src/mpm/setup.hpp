#pragma once
// What an MPM run is made of: materials (elastic and plastic laws, the
// mixture's heat, water and gas), bodies, colliders and the solver's
// settings, as the scene loader builds them (io/scene_mpm.cpp).
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "geometry/colliders.hpp"
#include "geometry/shapes.hpp"
#include "geometry/world.hpp"
#include "mpm/constitutive.hpp"
#include "physics/leavening.hpp"
#include "physics/moisture.hpp"
#include "physics/oven.hpp"
#include "physics/setting.hpp"
#include "physics/water.hpp"

namespace bakesim::mpm {

struct Material {
  std::string name;
  Real density = 1000.0;  // kg/m³
  Lame lame{};
  ElasticLaw elastic = Hencky{};
  PlasticLaw plastic = NoPlasticity{};
  // Thermomechanics (spec 2–3).
  Real specific_heat = 2800;   // c_v, J/(kg K)
  Real conductivity = 0.4;     // κ, W/(m K)
  Real thermal_expansion = 0;  // c of σ_s = τ/J − c λ (θ − θ_ref) I, 1/K
  Real initial_porosity = 0;   // n₀ of the gas porosity
  Moisture water;              // the paper's water (saturation, Fick diffusion, water pressure)
  PoreWater moisture;          // water, vapour and latent heat (physics/water.hpp); its liquid is `water`'s
  Leavening gas;
  std::optional<SettingCurves> setting;  // temperature-dependent τ_y, η (Hencky + plasticity only)
  IrreversibleSetting set;               // when τ_y, η start to follow the peak temperature (gelatinization)
};

struct Body : BodyBase {
  Vec3 angular_velocity = Vec3::Zero();  // rad/s about the body's centre of mass
};

enum class HeatMethod { off, explicit_, implicit };

// Material points sampled per cell edge: the initial lattice lays ppc^(1/3)
// points along each axis of a cell, at a spacing of cell_size / that.
inline Real points_per_cell_axis(Real particles_per_cell) { return std::cbrt(particles_per_cell); }

struct Settings {
  HeatMethod heat = HeatMethod::off;
  // Stomakhin et al. 2014 baseline: heat and temperature-dependent plasticity
  // only (no gas, no water, no porosity in the yield surface).
  bool baseline = false;
  Real heat_tolerance = 1e-8;  // implicit heat: relative residual of the conjugate gradients
  int heat_max_iterations = 200;
  Real cell_size = 0.01;       // Δx, m
  int particles_per_cell = 8;  // initial sampling: a lattice of ppc^(1/3) per axis
  Real cfl = 0.4;
  Real max_dt = 1e-3;
  int reorder_every = 16;  // steps between reordering particle memory by grid block
};

struct Setup : World {
  Settings settings;
  std::vector<Material> materials;
  std::vector<Body> bodies;
};

}  // namespace bakesim::mpm
