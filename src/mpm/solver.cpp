#include "mpm/solver.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/quantity.hpp"

namespace bakesim::mpm {

std::string periodic_problem(const Setup& setup) {
  if (!setup.periodicity().any()) return {};
  if (setup.settings.heat == HeatMethod::implicit)
    return "MPM with periodic axes needs explicit heat (or none): set solver.mpm.heat to \"explicit\" or \"off\"";
  const Real dx = setup.settings.cell_size;
  for (int k = 0; k < 3; ++k) {
    if (!setup.periodic[std::size_t(k)]) continue;
    const Real cells = setup.domain.extent()[k] / dx;
    if (std::abs(cells - std::round(cells)) > 1e-6 * std::max(Real(1), cells) || std::lround(cells) < 4)
      return fmt::format(
          "MPM: the domain is {:.6g} cells of {} m along the periodic axis {}; it must be a whole "
          "number of cells, at least 4",
          cells, dx, char('x' + k));
  }
  return {};
}

MpmSolver::MpmSolver(Setup setup)
    : setup_(std::move(setup)),
      x_(particles_.add_vector("position", "m")),
      v_(particles_.add_vector("velocity", "m/s")),
      m_(particles_.add_scalar("mass", "kg")),
      volume0_(particles_.add_scalar("initial_volume", "m^3")),
      j_(particles_.add_scalar("J", "")),
      jp_(particles_.add_scalar("plastic_J", "")),
      jp_set_(particles_.add_scalar("plastic_J_at_set", "", false, 1.0)),
      temperature_(particles_.add_scalar("temperature", "degC")),
      peak_temperature_(particles_.add_scalar("peak_temperature", "degC", false)),
      browning_(particles_.add_scalar("browning", "")),
      surface_temperature_(particles_.add_scalar("surface_temperature", "degC")),
      f0_(particles_.add_vector("F_col0", "", false)),
      f1_(particles_.add_vector("F_col1", "", false)),
      f2_(particles_.add_vector("F_col2", "", false)),
      c0_(particles_.add_vector("C_col0", "1/s", false)),
      c1_(particles_.add_vector("C_col1", "1/s", false)),
      c2_(particles_.add_vector("C_col2", "1/s", false)),
      tau_diag_(particles_.add_vector("kirchhoff_normal", "Pa", false)),
      tau_off_(particles_.add_vector("kirchhoff_shear", "Pa", false)),
      heat_capacity_(particles_.add_scalar("heat_capacity", "J/K", false)),
      water_(particles_.add_scalar("water_mass", "kg")),
      saturation_(particles_.add_scalar("saturation", "")),
      co2_(particles_.add_scalar("co2", "mol/m^3")),
      gas_pressure_(particles_.add_scalar("gas_pressure", "Pa")),
      gelatinized_(particles_.add_int("gelatinized")),
      grad_theta_(particles_.add_vector("temperature_gradient", "K/m", false)),
      grad_s_(particles_.add_vector("saturation_gradient", "1/m", false)),
      exchange_(particles_.add_scalar("exchange", "W/K", false)),
      exchange_t_(particles_.add_scalar("exchange_temperature", "W", false)),
      air_area_(particles_.add_scalar("air_area", "m^2", false)),
      air_depth_(particles_.add_scalar("air_depth", "m", false)),
      heat_src_(particles_.add_scalar("heat_source", "W", false)),
      heat_vec_(particles_.add_vector("heat_flux_term", "W", false)),
      water_src_(particles_.add_scalar("water_source", "kg/s", false)),
      water_vec_(particles_.add_vector("water_flux_term", "kg/s", false)),
      moisture_(particles_.add_scalar("moisture", "kg/kg")),
      vapour_density_(particles_.add_scalar("vapour_density", "kg/m^3")),
      grad_vapour_(particles_.add_vector("vapour_density_gradient", "kg/m^4", false)),
      vapour_src_(particles_.add_scalar("vapour_source", "kg/s", false)),
      vapour_vec_(particles_.add_vector("vapour_flux_term", "kg/s", false)),
      cell_k_(particles_.add_scalar("cell_conductivity", "W/(m K)", false)),
      material_(particles_.add_int("material_id")),
      body_(particles_.add_int("body_id")),
      id_(particles_.add_int("id")) {
  const Settings& s = setup_.settings;
  if (!(s.cell_size > 0)) throw InputError("solver.mpm.cell_size", "must be positive");
  dx_ = s.cell_size;
  inv_dx_ = 1.0 / dx_;
  const Vec3 ext = setup_.domain.extent();
  // Nodes across the domain plus the guard layer on both sides.
  const double extra = 1 + 2 * kGuardCells;
  // In floating point first: the integer product of tiny cells wraps around.
  const double node_estimate = (std::ceil(ext.x() * inv_dx_) + extra) * (std::ceil(ext.y() * inv_dx_) + extra) *
                               (std::ceil(ext.z() * inv_dx_) + extra);
  if (!(node_estimate <= 4e8))
    throw InputError("solver.mpm.cell_size", "the grid over the domain would have more than 4e8 nodes");
  grid_origin_ = setup_.domain.min - Vec3::Constant(kGuardCells * dx_);
  nx_ = static_cast<int>(std::ceil(ext.x() * inv_dx_) + extra);
  ny_ = static_cast<int>(std::ceil(ext.y() * inv_dx_) + extra);
  nz_ = static_cast<int>(std::ceil(ext.z() * inv_dx_) + extra);
  const std::size_t nodes = std::size_t(nx_) * ny_ * nz_;
  if (nodes > 400'000'000)
    throw InputError("solver.mpm.cell_size", "the grid over the domain would have more than 4e8 nodes");
  grid_.assign(nodes, GridNode{0, {0, 0, 0}});
  if (thermal()) {
    heat_sums_.assign(nodes, HeatSums{});
    heat_state_.assign(nodes, HeatState{});
  }
  if (s.heat == HeatMethod::implicit) implicit_mass_.assign(nodes, 0);
  if (!setup_.colliders.empty()) near_collider_.assign(nodes, 0);
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci)
    if (setup_.colliders[ci].contact.mode == ContactMode::sticky &&
        std::holds_alternative<PlaneCollider>(setup_.colliders[ci].geometry))
      sticky_planes_.push_back(ci);
  sticky_world_.resize(sticky_planes_.size());
  blocks_.resize(nx_, ny_, nz_);
  periodicity_ = setup_.periodicity();
  if (periodicity_.any()) {
    if (const std::string problem = periodic_problem(setup_); !problem.empty())
      throw InputError("domain.periodic", problem);
    for (int k = 0; k < 3; ++k)
      if (periodicity_.along(k)) period_cells_[std::size_t(k)] = static_cast<int>(std::lround(ext[k] * inv_dx_));
    image_node_.assign(nodes, 0);
    parallel_for(nodes, [&](std::size_t node) {
      const int g[3] = {int(node / (std::size_t(ny_) * nz_)), int((node / nz_) % ny_), int(node % nz_)};
      for (int k = 0; k < 3; ++k)
        if (period_cells_[std::size_t(k)] > 0 && node_inside(g[k], period_cells_[std::size_t(k)]) != g[k])
          image_node_[node] = 1;
    });
  }
  t_sort_ = timers_.add("sort");
  t_p2g_ = timers_.add("p2g");
  t_grid_ = timers_.add("grid");
  t_g2p_ = timers_.add("g2p");
  t_plastic_ = timers_.add("constitutive");
  t_heat_ = timers_.add("heat_solve");
  t_browning_ = timers_.add("browning");
  t_check_ = timers_.add("check");
  // Water pressure stiffens the mixture: dP_w/dJ ≈ ξ s₀.
  for (const Material& mat : setup_.materials) {
    const Real water = s.baseline ? 0 : mat.water.stiffness * mat.water.saturation;
    max_wave_speed_ = std::max(max_wave_speed_, std::sqrt((mat.lame.lambda + 2 * mat.lame.mu + water) / mat.density));
  }
  for (const Material& mat : setup_.materials) moist_ |= !s.baseline && mat.moisture.active();
  build_particles();
  phase_sort();
}

void MpmSolver::build_particles() {
  const Settings& s = setup_.settings;
  const Real spacing = dx_ / points_per_cell_axis(s.particles_per_cell);
  std::vector<std::vector<Vec3>> points(setup_.bodies.size());
  std::size_t total = 0;
  for (std::size_t b = 0; b < setup_.bodies.size(); ++b) {
    const Body& body = setup_.bodies[b];
    const std::string where = body.source.empty() ? "bodies[" + std::to_string(b) + "]" : body.source;
    points[b] = sample_lattice(body.shape, spacing);
    if (points[b].empty())
      throw InputError(where, fmt::format("body '{}' contains no material points at {} per cell of {} m: make the "
                                          "shape larger or the cell smaller",
                                          body.name, s.particles_per_cell, dx_));
    body_fill_.push_back(sampling_fill(body.shape, points[b], spacing));
    if (std::string w = sampling_warning(where, body.name, "material points", points[b].size(), spacing,
                                         body_fill_.back(), body.shape, {"solver.mpm.cell_size", dx_ / spacing});
        !w.empty())
      warnings_.push_back(std::move(w));
    // Every sampled point is kept: a body that does not fit is an error, never silently cut.
    const auto outside =
        std::count_if(points[b].begin(), points[b].end(), [&](const Vec3& p) { return !setup_.domain.contains(p); });
    if (outside > 0) {
      const Vec3 p =
          *std::find_if(points[b].begin(), points[b].end(), [&](const Vec3& q) { return !setup_.domain.contains(q); });
      throw InputError(where, fmt::format("body '{}' reaches outside the domain: {} of its {} material points lie "
                                          "outside (one at [{:.4g}, {:.4g}, {:.4g}]); grow the domain or move the body",
                                          body.name, outside, points[b].size(), p.x(), p.y(), p.z()));
    }
    total += points[b].size();
  }
  particles_.resize(total);
  const Real vol = spacing * spacing * spacing;
  std::size_t k = 0;
  for (std::size_t b = 0; b < setup_.bodies.size(); ++b) {
    const Body& body = setup_.bodies[b];
    const Material& mat = setup_.materials[body.material];
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : points[b]) centre += p;
    centre /= Real(points[b].size());
    for (const Vec3& p : points[b]) {
      x_[k] = p;
      v_[k] = body.velocity + body.angular_velocity.cross(p - centre);
      volume0_[k] = vol;
      m_[k] = mat.density * vol;
      j_[k] = 1;
      jp_[k] = 1;
      jp_set_[k] = 1;
      temperature_[k] = body.temperature;
      surface_temperature_[k] = body.temperature;
      peak_temperature_[k] = body.temperature;
      heat_capacity_[k] = m_[k] * mat.specific_heat;
      const bool wet = !s.baseline && mat.water.active();
      water_[k] = wet ? mat.water.saturation * mat.water.water_density * vol : 0;
      saturation_[k] = wet ? mat.water.saturation : 0;
      moisture_[k] = wet && mat.moisture.active() ? mat.moisture.moisture : 0;
      set_deformation_gradient(k, Mat3::Identity());
      set_affine(k, Mat3::Zero());
      material_[k] = body.material;
      body_[k] = static_cast<std::int32_t>(b);
      id_[k] = static_cast<std::int32_t>(k);
      ++k;
    }
  }
  // APIC: a rigid rotation is represented exactly by C = [ω]×.
  for (std::size_t i = 0; i < total; ++i) {
    const Vec3 w = setup_.bodies[body_[i]].angular_velocity;
    Mat3 c;
    c << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
    set_affine(i, c);
  }
}

Real MpmSolver::total_mass() const {
  return deterministic_sum(m_.size(), [&](std::size_t i) { return m_[i]; });
}

Real MpmSolver::grid_mass() const {
  return deterministic_sum(grid_.size(), [&](std::size_t k) { return is_image_node(k) ? 0.0 : grid_[k].mass; });
}

// Spec 4.7: Δt ≤ CFL Δx / max|v|, Δt ≤ CFL Δx / c with c = sqrt((λ+2μ+ξ s₀)/(s ρ)) (s the mass scaling);
// with heat, the explicit conduction bound Δt_bake ≤ ρ c Δx² / (6 κ J), the
// boundary exchange Δt_bake ≤ m c / (2 S β), and water diffusion
// Δt_bake ≤ Δx² / (6 D(θ_max)) (bake time Δt_bake = Δt · bake_time_scale).
Real MpmSolver::max_stable_dt() {
  const Settings& s = setup_.settings;
  struct Acc {
    Real vmax2 = 0, jmax = 0, tmax = -1e300, exchange = 0;
  };
  const bool heat = thermal();
  const Acc acc = deterministic_reduce(
      x_.size(), Acc{},
      [&](std::size_t b, std::size_t e) {
        Acc a;
        for (std::size_t i = b; i < e; ++i) {
          a.vmax2 = std::max(a.vmax2, v_[i].squaredNorm());
          if (heat) {
            a.jmax = std::max(a.jmax, j_[i]);
            a.tmax = std::max(a.tmax, temperature_[i]);
            a.exchange = std::max(a.exchange, exchange_[i] / heat_capacity_[i]);
          }
        }
        return a;
      },
      [](Acc a, const Acc& b) {
        a.vmax2 = std::max(a.vmax2, b.vmax2);
        a.jmax = std::max(a.jmax, b.jmax);
        a.tmax = std::max(a.tmax, b.tmax);
        a.exchange = std::max(a.exchange, b.exchange);
        return a;
      });
  Real dt = s.max_dt;
  dt_bound_ = "max_dt";
  auto limit = [&](Real bound, const char* name) {
    if (bound < dt) dt = bound, dt_bound_ = name;
  };
  if (acc.vmax2 > 0) limit(s.cfl * dx_ / std::sqrt(acc.vmax2), "cfl");
  // Mass scaling slows the waves by sqrt(s) (the inertia s ρ).
  if (max_wave_speed_ > 0) limit(s.cfl * dx_ * setup_.mass_scaling.wave_slowdown() / max_wave_speed_, "elastic_wave");
  if (heat) {
    const Real scale = setup_.oven.bake_time_scale;
    for (const Material& mat : setup_.materials) {
      // With moisture the closed-cell heat pipe adds to κ, most near the boiling point.
      const Real kappa = mat.conductivity + (!s.baseline && mat.moisture.active()
                                                 ? mat.moisture.cell_conductivity(
                                                       mat.moisture.boiling_point - 0.01, mat.moisture.moisture,
                                                       mat.moisture.expanded_gas_fraction(std::max(acc.jmax, Real(1))))
                                                 : 0);
      if (s.heat == HeatMethod::explicit_ && kappa > 0)
        limit(mat.density * mat.specific_heat * dx_ * dx_ / (6 * kappa * std::max(acc.jmax, Real(1))) / scale,
              "heat_conduction");
      if (!s.baseline && mat.water.active() && mat.water.diffusivity > 0)
        limit(dx_ * dx_ / (6 * mat.water.diffusion_coefficient(std::max(acc.tmax, Real(100)))) / scale,
              "water_diffusion");
      if (!s.baseline && mat.moisture.active()) {
        // The vapour's coupled heat–water diffusivity, largest at the hottest moist
        // temperature; over the moistures a particle passes through as it dries.
        const Real d =
            mat.moisture.step_diffusivity(acc.tmax, mat.density, mat.specific_heat, std::max(acc.jmax, Real(1)));
        if (d > 0) limit(dx_ * dx_ / (6 * d) / scale, "vapour_diffusion");
      }
    }
    if (s.heat == HeatMethod::explicit_ && acc.exchange > 0) limit(0.5 / acc.exchange / scale, "heat_exchange");
  }
  return dt;
}

void MpmSolver::step(Real dt) {
  if (!(dt > 0)) throw SimulationError(fmt::format("mpm step {}: time step {} is not positive", steps_ + 1, dt));
  phase_sort();
  phase_p2g(dt);
  phase_grid(dt);
  if (setup_.settings.heat == HeatMethod::implicit) phase_heat_implicit(dt);
  phase_g2p(dt);
  phase_plasticity(dt);
  if (thermal()) phase_browning(dt);
  check_state();
  time_ += dt;
  ++steps_;
}

std::vector<Real> MpmSolver::sample(const Vec3& x, const std::vector<std::string>& quantities) const {
  // Nearest-particle value within one cell (MPM particles carry the state).
  std::size_t best = x_.size();
  Real best_d2 = dx_ * dx_;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const Real d2 = (x_[i] - x).squaredNorm();
    if (d2 < best_d2) best_d2 = d2, best = i;
  }
  std::vector<Real> out;
  for (const std::string& q : quantities) {
    const ParticleQuantity value = ParticleQuantity::resolve(particles_, q, "probes");
    out.push_back(best == x_.size() ? std::numeric_limits<Real>::quiet_NaN() : value(best));
  }
  return out;
}

Real MpmSolver::total_water() const {
  return deterministic_sum(x_.size(), [&](std::size_t i) { return water_[i]; });
}

Real MpmSolver::total_co2() const {
  return deterministic_sum(x_.size(), [&](std::size_t i) { return co2_[i] * volume0_[i]; });
}

Real MpmSolver::total_heat_energy() const {
  return deterministic_sum(x_.size(), [&](std::size_t i) { return heat_capacity_[i] * temperature_[i]; });
}

// The mixture's totals (per-body bake statistics come from sim/bake_stats.hpp).
std::vector<std::pair<std::string, Real>> MpmSolver::frame_quantities() const {
  std::vector<std::pair<std::string, Real>> out;
  if (!thermal()) return out;
  out.emplace_back("water_total", total_water());
  out.emplace_back("water_evaporated", budget_.evaporated);
  out.emplace_back("heat_in", budget_.heat_in);
  if (moist_) {
    out.emplace_back("latent_heat_out", budget_.latent_out);
    out.emplace_back("water_boiled", budget_.boiled);
  }
  return out;
}

}  // namespace bakesim::mpm

namespace bakesim::mpm {

std::vector<std::pair<std::string, double>> MpmSolver::checkpoint_state() const {
  return {{"time", time_},
          {"steps", double(steps_)},
          {"evaporated", budget_.evaporated},
          {"clamped", budget_.clamped},
          {"heat_in", budget_.heat_in},
          {"boiled", budget_.boiled},
          {"latent_out", budget_.latent_out}};
}

void MpmSolver::restore_state(const std::vector<std::pair<std::string, double>>& state) {
  for (const auto& [name, value] : state) {
    if (name == "time")
      time_ = value;
    else if (name == "steps")
      steps_ = std::size_t(value);
    else if (name == "evaporated")
      budget_.evaporated = value;
    else if (name == "clamped")
      budget_.clamped = value;
    else if (name == "heat_in")
      budget_.heat_in = value;
    else if (name == "boiled")
      budget_.boiled = value;
    else if (name == "latent_out")
      budget_.latent_out = value;
  }
  // The particles come back in the order they had; the material groups index them.
  group_by_material();
}

}  // namespace bakesim::mpm
