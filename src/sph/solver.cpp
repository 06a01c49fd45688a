#include "sph/solver.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <tbb/enumerable_thread_specific.h>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/quantity.hpp"
#include "physics/bubbles.hpp"
#include "physics/heat.hpp"
#include "physics/maxwell.hpp"
#include "physics/rheology.hpp"

namespace bakesim::sph {
namespace {

// Largest value a temperature curve takes (curves are monotone pieces, so
// their extremes sit at breakpoints or at the ends).
Real curve_max(const TemperatureCurve& c) {
  if (const auto* k = std::get_if<ConstantCurve>(&c)) return k->value;
  if (const auto* p = std::get_if<PiecewiseLinear>(&c)) {
    Real m = 0;
    for (const auto& [t, v] : p->points()) m = std::max(m, v);
    return m;
  }
  const auto& z = std::get<ZhangArctan>(c);
  return 2.0 * z.scale + z.offset;
}

// splitmix64: a stable, platform-independent hash for reproducible bubble
// placement (std::uniform_real_distribution differs between libraries).
double unit_random(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + index + 0x632BE59BD9B4E019ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return double(z >> 11) * (1.0 / 9007199254740992.0);
}

}  // namespace

ViscositySolver parse_viscosity_solver(const std::string& name) {
  if (name == "explicit") return ViscositySolver::explicit_euler;
  if (name == "implicit") return ViscositySolver::implicit;
  if (name == "auto") return ViscositySolver::automatic;
  throw InputError("solver.sph.viscosity_solver", "unknown viscosity solver '" + name + "' (explicit, implicit, auto)");
}

std::string to_string(ViscositySolver v) {
  switch (v) {
    case ViscositySolver::explicit_euler: return "explicit";
    case ViscositySolver::implicit: return "implicit";
    default: return "auto";
  }
}

SphSolver::SphSolver(Setup setup)
    : setup_(std::move(setup)),
      h_(setup_.settings.smoothing_ratio * setup_.settings.spacing),
      contact_distance_(0.5 * setup_.settings.spacing),
      kernel_(h_),
      lattice_sum_(lattice_kernel_sum(kernel_, setup_.settings.spacing)),
      visc_lap_(h_, viscosity_lattice_calibration(kernel_, setup_.settings.spacing, lattice_sum_)),
      wall_viscosity_(h_, setup_.settings.spacing, lattice_sum_, [this](Real r, Real) { return visc_lap_(r); }),
      wall_gradient_(h_, setup_.settings.spacing, lattice_sum_,
                     [this](Real r, Real z) { return -kernel_.dw_dr(r) * z / r; }),
      wall_share_(kernel_, setup_.settings.spacing, lattice_sum_),
      search_(setup_.settings.search, setup_.domain, h_),
      x_(particles_.add_vector("position", "m")),
      v_(particles_.add_vector("velocity", "m/s")),
      a_(particles_.add_vector("acceleration", "m/s^2")),
      rho_(particles_.add_scalar("density", "kg/m^3")),
      p_(particles_.add_scalar("pressure", "Pa")),
      m_(particles_.add_scalar("mass", "kg")),
      temperature_(particles_.add_scalar("temperature", "degC")),
      browning_(particles_.add_scalar("browning", "")),
      surface_temperature_(particles_.add_scalar("surface_temperature", "degC")),
      mu_(particles_.add_scalar("viscosity", "Pa*s")),
      eps_(particles_.add_scalar("xsph_epsilon", "")),
      elasticity_(particles_.add_scalar("elasticity", "Pa")),
      relaxation_(particles_.add_scalar("relaxation_time", "s")),
      stress_diag_(particles_.add_vector("stress_normal", "Pa")),
      stress_off_(particles_.add_vector("stress_shear", "Pa")),
      area_(particles_.add_scalar("surface_area", "m^2")),
      smoothing_(particles_.add_scalar("smoothing_length", "m")),
      set_density_(particles_.add_scalar("set_density", "kg/m^3", false)),
      set_temperature_(particles_.add_scalar("set_temperature", "degC", false)),
      peak_temperature_(particles_.add_scalar("peak_temperature", "degC", false)),
      surface_(particles_.add_int("surface")),
      bubble_(particles_.add_int("bubble")),
      rise_state_(particles_.add_int("rise_state")),
      material_(particles_.add_int("material_id")),
      body_(particles_.add_int("body_id")),
      id_(particles_.add_int("id")),
      ncount_(particles_.add_int("neighbours")),
      anchor_(particles_.add_vector("neighbour_anchor", "m", false)),
      anchor_support_(particles_.add_scalar("neighbour_anchor_support", "m", false)),
      fill_radius_(particles_.add_scalar("open_space_radius", "m", false)),
      viscous_change_(particles_.add_vector("viscous_velocity_change", "m/s", false)),
      air_facing_(particles_.add_int("air_facing", false)),
      density_kappa_(particles_.add_scalar("density_solve_kappa", "m^5/(kg s^2)", false)) {
  const Settings& s = setup_.settings;
  if (setup_.materials.empty()) throw InputError("materials", "no materials defined");
  for (const Material& m : setup_.materials) {
    tait_b_.push_back(m.rest_density * s.speed_of_sound * s.speed_of_sound / s.gamma);
    mass_.push_back(m.rest_density / lattice_sum_);
    conductivity_.push_back(m.conductivity);
  }
  colour_share_ = flat_face_colour_share(kernel_, s.spacing);
  for (const Collider& c : setup_.colliders) heated_colliders_ |= c.temperature.has_value();
  adaptive_ = s.adaptive.enabled;
  for (const Material& m : setup_.materials)
    elastic_ |= !is_constant(m.elasticity) || std::get<ConstantCurve>(m.elasticity).value != 0.0;
  for (const Material& m : setup_.materials) surface_tension_ |= m.surface_tension != 0.0;
  for (const Material& m : setup_.materials) follows_peak_ |= m.set.ever();
  for (const Body& b : setup_.bodies)
    bubble_b_.push_back(b.bubbles.pressure_scale ? *b.bubbles.pressure_scale
                                                 : tait_b_.at(std::clamp<int>(b.material, 0, int(tait_b_.size()) - 1)));
  // Implicit viscosity when the explicit viscous bound would be tighter than
  // the CFL bound at the largest viscosity any material reaches.
  rest_cfl_step_ = s.cfl * 0.5 * h_ / s.speed_of_sound;
  implicit_elasticity_ = s.implicit_elasticity && elastic_;
  implicit_viscosity_ = s.viscosity_solver == ViscositySolver::implicit || s.stress_viscosity || implicit_elasticity_;
  if (s.viscosity_solver == ViscositySolver::automatic) {
    const Real hs = 0.5 * h_;
    Real nu = 0;
    for (const Material& m : setup_.materials) {
      Real mu = elastoviscoplastic(m) ? 0.0 : curve_max(m.viscosity);
      if (regularised_yield_flow(m))  // a yield-stress fluid is most viscous at rest
        mu = HerschelBulkley{curve_max(m.yield_flow->yield_stress), mu, m.yield_flow->flow_index,
                             m.yield_flow->regularisation}
                 .viscosity_at_rest();
      nu = std::max(nu, mu / m.rest_density);
    }
    implicit_viscosity_ =
        s.stress_viscosity || implicit_elasticity_ || (nu > 0 && s.viscous_factor * hs * hs / nu < rest_cfl_step_);
  }
  // Domain walls come first, then analytic colliders; meshes are separate.
  periodicity_ = setup_.periodicity();
  periodic_ = periodicity_.any();
  search_.set_periodicity(periodicity_);
  // The candidate search reaches h_max + skin, which along a periodic axis
  // must stay under half the box (each pair found once).
  skin_ = s.neighbour_skin * h_;
  const Real h_cap = adaptive_ ? s.adaptive.max_ratio * h_ : h_;
  for (int k = 0; k < 3; ++k)
    if (periodicity_.along(k)) skin_ = std::min(skin_, 0.45 * (setup_.domain.extent()[k] - 2.0 * h_cap));
  skin_ = std::max<Real>(skin_, 0);
  walls_.push_back(Collider{"domain", InsideBoxCollider{setup_.domain, setup_.periodic}, setup_.domain_contact,
                            RigidMotion{}, std::nullopt});
  for (const Collider& c : setup_.colliders) (analytic_wall(c) ? walls_ : meshes_).push_back(c);
  for (const Collider& c : walls_) no_slip_walls_ |= no_slip_wall(c);

  t_kick_ = timers_.add("kick");
  t_drift_ = timers_.add("drift");
  t_collide_ = timers_.add("collide");
  t_sort_ = timers_.add("sort");
  t_neigh_ = timers_.add("neighbours");
  t_density_ = timers_.add("density");
  t_surface_ = timers_.add("surface");
  t_stress_ = timers_.add("stress");
  t_pressure_ = timers_.add("pressure");
  t_forces_ = timers_.add("forces");
  t_xsph_ = timers_.add("xsph");
  t_viscosity_ = timers_.add("viscosity");
  t_heat_ = timers_.add("heat");
  divergence_free_ = s.pressure_solver == PressureSolver::divergence_free;
  if (divergence_free_) {
    t_density_solve_ = timers_.add("density_solve");
    t_divergence_solve_ = timers_.add("divergence_solve");
  }
  for (const Material& m : setup_.materials) moist_ |= m.moisture.active();
  if (moist_) {
    t_water_ = timers_.add("water");
    water_ = &particles_.add_scalar("water_mass", "kg");
    moisture_ = &particles_.add_scalar("moisture", "kg/kg");
    vapour_density_ = &particles_.add_scalar("vapour_density", "kg/m^3");
  }
  t_browning_ = timers_.add("browning");
  t_properties_ = timers_.add("properties");
  t_smoothing_ = timers_.add("smoothing");
  t_check_ = timers_.add("check");

  update_wall_poses(time_);
  seed_particles();
  refresh();
  // Yield-stress materials start with the viscosity of their initial shear
  // rate (at rest: τ_y/γ̇_r), not their consistency: a body at rest holds from the first step.
  for (std::size_t mi = 0; mi < setup_.materials.size(); ++mi)
    if (regularised_yield_flow(setup_.materials[mi])) apparent_viscosity(int(mi));
  check_initial_overlaps();
}

// Bodies that overlap put particles on top of each other (an explosion at the
// first step), and bodies inside a solid collider are pushed out violently:
// both are input errors, named here.
void SphSolver::check_initial_overlaps() const {
  const Real min_gap = 0.5 * setup_.settings.spacing;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const float* dist = lists_.distances(i);
    const std::uint32_t* nb = lists_.begin(i);
    for (std::uint32_t k = 0; k < lists_.count(i); ++k)
      if (dist[k] < min_gap && body_[nb[k]] != body_[i]) {
        const Body& a = setup_.bodies[std::min(body_[i], body_[nb[k]])];
        const Body& b = setup_.bodies[std::max(body_[i], body_[nb[k]])];
        throw InputError(b.source, fmt::format("body '{}' overlaps body '{}' near [{:.4g}, {:.4g}, {:.4g}]; bodies "
                                               "must not share space (use a union shape for one body)",
                                               b.name, a.name, x_[i].x(), x_[i].y(), x_[i].z()));
      }
  }
  for (std::size_t c = kDomainWall + 1; c < walls_.size(); ++c)  // the domain is checked when seeding
    for (std::size_t i = 0; i < x_.size(); ++i)
      for_each_wall_of(c, x_[i], 0.0, [&](const WallContact& w, const Vec3&) {
        if (w.distance < 0)
          throw InputError(setup_.bodies[body_[i]].source,
                           fmt::format("body '{}' starts inside collider '{}' (particle at [{:.4g}, {:.4g}, {:.4g}])",
                                       setup_.bodies[body_[i]].name, walls_[c].name, x_[i].x(), x_[i].y(), x_[i].z()));
      });
}

Real SphSolver::particle_mass(int material) const { return mass_.at(material); }

void SphSolver::seed_particles() {
  const Real s = setup_.settings.spacing;
  std::vector<std::vector<Vec3>> points;
  std::size_t total = 0;
  for (const Body& b : setup_.bodies) {
    if (b.material < 0 || b.material >= int(setup_.materials.size()))
      throw InputError(b.source + ".material", "unknown material");
    points.push_back(sample_lattice(b.shape, s));
    if (points.back().empty())
      throw InputError(b.source, fmt::format("body '{}' contains no particles at spacing {} m: make the shape "
                                             "larger or the spacing smaller",
                                             b.name, s));
    body_fill_.push_back(sampling_fill(b.shape, points.back(), s));
    if (std::string w = sampling_warning(b.source, b.name, "particles", points.back().size(), s, body_fill_.back(),
                                         b.shape, {"solver.sph.spacing", 1});
        !w.empty())
      warnings_.push_back(std::move(w));
    for (const Vec3& p : points.back())
      if (!setup_.domain.contains(p))
        throw InputError(
            b.source, fmt::format("body '{}' reaches outside the domain (particle at [{:.4g}, {:.4g}, {:.4g}])", b.name,
                                  p.x(), p.y(), p.z()));
    total += points.back().size();
  }
  if (total > std::size_t(std::numeric_limits<std::int32_t>::max()))
    throw InputError("solver.sph.spacing", "too many particles");
  particles_.resize(total);
  x_prev_.resize(total);
  dv_.resize(total);
  dtemp_.resize(total);
  if (moist_) {
    water_coefficients_.resize(total);
    water_change_.resize(total);
    step_book_.resize(total);
    particle_k_.resize(total);
  }
  face_outside_.assign(total, 0);
  face_share_.assign(total, 0);
  face_coefficient_.assign(total, 0);
  std::size_t k = 0;
  for (std::size_t bi = 0; bi < setup_.bodies.size(); ++bi) {
    const Body& b = setup_.bodies[bi];
    const Material& mat = setup_.materials[b.material];
    body_counts_.push_back(points[bi].size());
    for (const Vec3& p : points[bi]) {
      x_[k] = p;
      x_prev_[k] = p;
      v_[k] = b.velocity;
      m_[k] = mass_[b.material];
      rho_[k] = mat.rest_density;
      temperature_[k] = b.temperature;
      surface_temperature_[k] = b.temperature;
      // An elastoviscoplastic material's consistency acts in its plastic
      // return only, and its stress relaxes only by that flow.
      const bool evp = elastoviscoplastic(mat);
      mu_[k] = evp ? 0.0 : evaluate(mat.viscosity, b.temperature);
      eps_[k] = std::clamp(evaluate(mat.xsph, b.temperature), 0.0, 1.0);
      elasticity_[k] = evaluate(mat.elasticity, b.temperature);
      relaxation_[k] = evp ? kNeverRelaxes : evaluate(mat.relaxation_time, b.temperature);
      stress_diag_[k].setZero();
      stress_off_[k].setZero();
      set_density_[k] = mat.rest_density;
      set_temperature_[k] = b.temperature;
      peak_temperature_[k] = b.temperature;
      if (moist_) {
        // The particle is dry solid and water: m_w = m X₀ / (1 + X₀).
        (*water_)[k] = mat.moisture.initial_water(m_[k]);
        (*moisture_)[k] = mat.moisture.moisture;
      }
      smoothing_[k] = h_;
      material_[k] = b.material;
      body_[k] = static_cast<std::int32_t>(bi);
      id_[k] = static_cast<std::int32_t>(k);
      ++k;
    }
  }
  assign_bubbles();
}

// Tags bubble particles per body (thesis 3.3.3, Fig 4.4): a random share of
// the body, of its centre, of alternate horizontal layers, or of a region.
void SphSolver::assign_bubbles() {
  const Vec3 up = setup_.gravity.norm() > 0 ? Vec3(-setup_.gravity.normalized()) : Vec3::UnitY();
  std::size_t first = 0;
  for (std::size_t bi = 0; bi < setup_.bodies.size(); ++bi) {
    const BubbleSpec& spec = setup_.bodies[bi].bubbles;
    const std::size_t count = body_counts_[bi];
    const std::size_t end = first + count;
    if (spec.fraction > 0) {
      if (spec.distribution == BubbleDistribution::centred) {
        // The share of particles closest to the body's centroid.
        Vec3 centre = Vec3::Zero();
        for (std::size_t i = first; i < end; ++i) centre += x_[i];
        centre /= Real(count);
        std::vector<std::pair<Real, std::size_t>> by_distance;
        for (std::size_t i = first; i < end; ++i) by_distance.emplace_back((x_[i] - centre).squaredNorm(), i);
        std::sort(by_distance.begin(), by_distance.end());
        const auto take = static_cast<std::size_t>(std::llround(spec.fraction * Real(count)));
        for (std::size_t k = 0; k < take && k < count; ++k) bubble_[by_distance[k].second] = 1;
      } else {
        Real lo = std::numeric_limits<Real>::infinity(), hi = -lo;
        for (std::size_t i = first; i < end; ++i) {
          lo = std::min(lo, x_[i].dot(up));
          hi = std::max(hi, x_[i].dot(up));
        }
        for (std::size_t i = first; i < end; ++i) {
          bool zone = true;
          if (spec.distribution == BubbleDistribution::layered) {
            const Real u = hi > lo ? (x_[i].dot(up) - lo) / (hi - lo) : 0.0;
            const int layer = std::min(spec.layers - 1, static_cast<int>(u * spec.layers));
            zone = layer % 2 == 1;
          } else if (spec.distribution == BubbleDistribution::region) {
            zone = spec.region && contains(*spec.region, x_[i]);
          }
          if (zone && unit_random(spec.seed, i - first) < spec.fraction) bubble_[i] = 1;
        }
      }
    }
    first = end;
  }
}

void SphSolver::refresh() {
  correction_fresh_ = false;
  phase_neighbours();
  phase_density();
  phase_surface();
  phase_pressure();
  phase_forces();
}

Mat3 SphSolver::stress(std::size_t i) const {
  const Vec3& d = stress_diag_[i];
  const Vec3& o = stress_off_[i];
  Mat3 s;
  s << d.x(), o.x(), o.y(), o.x(), d.y(), o.z(), o.y(), o.z(), d.z();
  return s;
}

void SphSolver::set_stress(std::size_t i, const Mat3& s) {
  stress_diag_[i] = Vec3(s(0, 0), s(1, 1), s(2, 2));
  stress_off_[i] = Vec3(0.5 * (s(0, 1) + s(1, 0)), 0.5 * (s(0, 2) + s(2, 0)), 0.5 * (s(1, 2) + s(2, 1)));
}

// Eq 3.27: ∂v_a/∂x_b = Σ_j V_j (v_j − v_i)_a (∇_i W_ij)_b.
Mat3 SphSolver::velocity_gradient(std::size_t i) const { return velocity_gradient(i, nullptr); }

Mat3 SphSolver::velocity_gradient(std::size_t i, const Real* volume) const {
  const std::uint32_t* nb = lists_.begin(i);
  const std::uint32_t count = lists_.count(i);
  const float* pd = pair_dwr_.data() + i * lists_.stride();
  const Vec3 xi = x_[i], vi = v_[i];
  // Column by column (column c is Σ V_j (v_j − v_i) ∇W_c): summed into a
  // Mat3, every pair's outer product went through memory and the sums waited
  // on each other (4 ms a step on the roll, 17% of it). Same products, same
  // order: the same sums to the bit.
  Vec3 col0 = Vec3::Zero(), col1 = Vec3::Zero(), col2 = Vec3::Zero();
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t j = nb[k];
    const Vec3 gw = Real(pd[k]) * pair_offset_of(xi, x_[j]);
    const Vec3 dv = (volume ? volume[j] : m_[j] / rho_[j]) * (v_[j] - vi);
    col0 += dv * gw.x();
    col1 += dv * gw.y();
    col2 += dv * gw.z();
  }
  Mat3 grad;
  grad << col0, col1, col2;
  // No-slip walls: their ghosts' share (WallGhostSum), so a particle beside
  // the wall sees the whole shear and not half of it.
  // S_grad scales as 1/h with the support (adaptive smoothing).
  if (no_slip_walls_)
    for_each_no_slip_wall(i, [&](Real d0, Real scale, const WallContact& w, const Vec3& v_wall) {
      grad += (wall_gradient_(d0) * scale) * (v_[i] - v_wall) * w.normal.transpose();
    });
  return grad;
}

// ---- driver ------------------------------------------------------------------

SphSolver::StepBounds SphSolver::time_step_bounds() const {
  const Settings& s = setup_.settings;
  struct Extremes {
    Real v2 = 0, a2 = 0, nu = 0, shear = 0, h = std::numeric_limits<Real>::infinity();
  };
  const Extremes e = deterministic_reduce(
      x_.size(), Extremes{},
      [&](std::size_t b, std::size_t end) {
        Extremes r;
        for (std::size_t i = b; i < end; ++i) {
          r.v2 = std::max(r.v2, v_[i].squaredNorm());
          r.a2 = std::max(r.a2, a_[i].squaredNorm());
          r.nu = std::max(r.nu, mu_[i] / rho_[i]);
          r.shear = std::max(r.shear, elasticity_[i] / rho_[i]);
          r.h = std::min(r.h, smoothing_[i]);
        }
        return r;
      },
      [](Extremes a, Extremes b) {
        return Extremes{std::max(a.v2, b.v2), std::max(a.a2, b.a2), std::max(a.nu, b.nu), std::max(a.shear, b.shear),
                        std::min(a.h, b.h)};
      });
  // Classical smoothing length ħ = h/2 of the smallest support.
  const Real hs = 0.5 * std::min(h_, e.h);
  StepBounds bounds;
  bounds.add("max_dt", s.max_dt);
  // Weakly compressible: sound crosses ħ; divergence-free: the flow does (at rest no bound).
  // Mass scaling s: waves travel sqrt(s) slower, forces accelerate s times less.
  const Real slow = setup_.mass_scaling.wave_slowdown(), scale = setup_.mass_scaling.factor;
  if (!divergence_free_)
    bounds.add("cfl", s.cfl * hs / (s.speed_of_sound / slow + std::sqrt(e.v2)));
  else if (e.v2 > 0)
    bounds.add("cfl", s.cfl * hs / std::sqrt(e.v2));
  // Shear waves of the Maxwell stress travel at sqrt(μ_e/ρ).
  // (Solved implicitly, they bound nothing: backward Euler damps them instead.)
  if (e.shear > 0 && !implicit_elasticity_) bounds.add("elastic", s.cfl * hs * slow / std::sqrt(e.shear));
  if (e.nu > 0 && !implicit_viscosity_) bounds.add("viscosity", s.viscous_factor * hs * hs * scale / e.nu);
  if (e.a2 > 0) bounds.add("force", s.force_factor * std::sqrt(hs * scale / std::sqrt(e.a2)));
  if (s.heat_conduction) {
    Real alpha = 0;  // thermal diffusivity k / (ρ c_p), largest over materials
    for (const Material& m : setup_.materials) {
      // With moisture the closed-cell heat pipe adds to k (largest near the boiling point, most gas at 0.95).
      const Real k_cell = m.moisture.active()
                              ? m.moisture.cell_conductivity(m.moisture.boiling_point - 0.01, m.moisture.moisture, 0.95)
                              : 0;
      alpha = std::max(alpha, (m.conductivity + k_cell) / (m.rest_density * m.specific_heat));
    }
    alpha = setup_.oven.bake_step(alpha);  // heat runs on the bake clock
    if (alpha > 0) bounds.add("conduction", s.conduction_factor * hs * hs / alpha, true);
  }
  if (moist_) {
    // The vapour's coupled heat–water diffusivity at the hottest moist temperature
    // (physics/water.hpp), over the moistures a particle passes as it dries.
    // The hottest particle and the most expanded (its gas fraction grows and its heat capacity per volume falls).
    using Pair = std::pair<Real, Real>;
    const auto [tmax, jmax] = deterministic_reduce(
        x_.size(), Pair{-1e300, 1},
        [&](std::size_t b, std::size_t end) {
          Pair m{-1e300, 1};
          for (std::size_t i = b; i < end; ++i)
            m = {std::max(m.first, temperature_[i]),
                 std::max(m.second, setup_.materials[material_[i]].rest_density / rho_[i])};
          return m;
        },
        [](Pair a, Pair b) {
          return Pair{std::max(a.first, b.first), std::max(a.second, b.second)};
        });
    Real d = 0;
    for (const Material& m : setup_.materials) {
      const PoreWater& pw = m.moisture;
      if (!pw.active()) continue;
      d = std::max(d, pw.step_diffusivity(tmax, m.rest_density, m.specific_heat, jmax));
    }
    d = setup_.oven.bake_step(d);
    if (d > 0) bounds.add("vapour_diffusion", s.conduction_factor * hs * hs / d, true);
  }
  return bounds;
}

Real SphSolver::max_stable_dt() {
  Real dt = std::numeric_limits<Real>::infinity();
  heat_bound_ = std::numeric_limits<Real>::infinity();
  for (const StepBound& b : time_step_bounds()) {
    if (b.heat) heat_bound_ = std::min(heat_bound_, b.dt);
    // On its own step the heat takes substeps within its bounds: they do not bound the mechanics.
    if (b.heat && setup_.settings.heat_own_step) continue;
    if (b.dt < dt) {
      dt = b.dt;
      dt_bound_ = b.name;
    }
  }
  return dt;
}

// The heat, water and browning phases are explicit on the bake clock and
// bounded by their own diffusion limits, which in a dough scene lie several
// CFL steps away from the mechanics' (the roll: vapour diffusion 2.8e-4 s,
// conduction 5.2e-4 s, CFL 1.3e-4 s; the Zhang loaf: conduction 5.0e-5 s, CFL
// 1.6e-4 s). With heat_own_step they advance once every few steps over the
// steps' summed time, as long as another step of this size would carry that
// sum past their bound (and at most kMaxHeatEverySteps steps), or in
// substeps within it when one step is longer; the temperature the mechanics
// read lags by those few steps (docs/physics.md, "Heat on its own step").
bool SphSolver::heat_due(Real dt) {
  heat_pending_ += dt;
  ++heat_pending_steps_;
  if (!setup_.settings.heat_own_step || heat_pending_steps_ >= kMaxHeatEverySteps) return true;
  return !(heat_pending_ + dt <= heat_bound_);
}

void SphSolver::advance_heat() {
  const Real total = heat_pending_;
  // A step longer than the last ones may carry the sum past the bound: split it.
  int parts = 1;
  if (setup_.settings.heat_own_step && heat_bound_ > 0 && total > heat_bound_)
    parts = static_cast<int>(std::ceil(total / heat_bound_ - 1e-9));
  bool weights_ready = false;  // the substeps share this step's positions and so its pair weights
  for (int k = 0; k < parts; ++k) {
    const Real part = total / parts;
    phase_heat(part, weights_ready);
    if (moist_) phase_water(part);
    phase_browning(part);
  }
  heat_pending_ = 0;
  heat_pending_steps_ = 0;
}

void SphSolver::synchronize() {
  if (heat_pending_steps_ == 0) return;
  phase_surface(true);
  advance_heat();
  phase_properties(true);
}

void SphSolver::step(Real dt) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw SimulationError(fmt::format("SPH step {}: invalid time step {}", steps_, dt));
  update_wall_poses(time_ + dt);
  correction_fresh_ = false;  // the particles move
  const bool heat_now = heat_due(dt);
  if (divergence_free_) {
    phase_kick(dt);  // symplectic Euler: the forces without pressure, at x(t)
    phase_density_solve(dt);
  } else {
    phase_kick(0.5 * dt);  // leap-frog
  }
  phase_drift(dt);
  phase_collide();
  phase_neighbours();
  phase_density();
  phase_surface(heat_now);
  phase_stress(dt);
  phase_pressure();
  if (divergence_free_) phase_divergence_solve(dt);
  phase_forces();
  if (!divergence_free_) phase_kick(0.5 * dt);
  phase_xsph(dt);
  phase_viscosity(dt);
  phase_stress_increment(dt);
  if (heat_now) advance_heat();
  phase_properties(heat_now);
  phase_smoothing();
  time_ += dt;
  ++steps_;
  check_finite();
}

// Shepard-normalised SPH interpolation: A(x) = Σ V_j A_j W / Σ V_j W, of any
// quantity the registry has (resolved once, outside the neighbour loop).
std::vector<Real> SphSolver::sample(const Vec3& x, const std::vector<std::string>& quantities) const {
  std::vector<ParticleQuantity> qs;
  for (const std::string& name : quantities) qs.push_back(ParticleQuantity::resolve(particles_, name, "probes"));
  std::vector<Real> sum(qs.size(), 0.0);
  Real wsum = 0.0;
  const Real h2 = h_ * h_;
  const Vec3 at = periodic_ ? periodicity_.wrap(x) : x;
  // The grid holds the anchors: a particle within h now lies within h + skin/2 of them.
  search_.for_each_image(at, h_ + skin_, [&](const Vec3& shift) {
    const Vec3 q = at + shift;
    search_.grid().for_each_within(q, h_ + skin_, [&](std::uint32_t j) {
      const Real r2 = (x_[j] - q).squaredNorm();
      if (r2 >= h2) return;
      const Real w = m_[j] / rho_[j] * kernel_.w(std::sqrt(r2));
      wsum += w;
      for (std::size_t k = 0; k < qs.size(); ++k) sum[k] += w * qs[k](j);
    });
  });
  for (Real& s : sum) s = wsum > 1e-12 ? s / wsum : std::numeric_limits<Real>::quiet_NaN();
  return sum;
}

}  // namespace bakesim::sph

namespace bakesim::sph {

std::vector<std::pair<std::string, double>> SphSolver::checkpoint_state() const {
  return {{"time", time_},
          {"steps", double(steps_)},
          {"exchanged_heat", exchanged_heat_},
          {"water_evaporated", water_budget_.evaporated},
          {"water_boiled", water_budget_.boiled},
          {"water_clamped", water_budget_.clamped},
          {"latent_out", water_budget_.latent_out},
          {"heat_pending", heat_pending_},
          {"heat_pending_steps", double(heat_pending_steps_)}};
}

std::vector<std::pair<std::string, Real>> SphSolver::frame_quantities() const {
  std::vector<std::pair<std::string, Real>> out = {{"heat_in", exchanged_heat_}};
  if (moist_) {
    out.emplace_back("water_total", deterministic_sum(x_.size(), [&](std::size_t i) { return (*water_)[i]; }));
    out.emplace_back("water_evaporated", water_budget_.evaporated);
    out.emplace_back("latent_heat_out", water_budget_.latent_out);
    out.emplace_back("water_boiled", water_budget_.boiled);
  }
  return out;
}

void SphSolver::restore_state(const std::vector<std::pair<std::string, double>>& state) {
  for (const auto& [name, value] : state) {
    if (name == "time")
      time_ = value;
    else if (name == "steps")
      steps_ = long(value);
    else if (name == "exchanged_heat")
      exchanged_heat_ = value;
    else if (name == "water_evaporated")
      water_budget_.evaporated = value;
    else if (name == "water_boiled")
      water_budget_.boiled = value;
    else if (name == "water_clamped")
      water_budget_.clamped = value;
    else if (name == "latent_out")
      water_budget_.latent_out = value;
    else if (name == "heat_pending")
      heat_pending_ = std::isfinite(value) && value > 0 ? value : 0;  // a crafted value: take the heat now
    else if (name == "heat_pending_steps")
      heat_pending_steps_ = value >= 1 && value <= kMaxHeatEverySteps ? int(value) : 0;
  }
  // Neighbour lists, pair kernels and per-step scratch are rebuilt by the next
  // step: its candidates from the restored anchors, as the uninterrupted run
  // had them.
  candidates_valid_ = false;
  anchors_valid_ = true;
  open_space_built_ = false;  // rebuilt from the restored anchors and their radii
}

}  // namespace bakesim::sph
