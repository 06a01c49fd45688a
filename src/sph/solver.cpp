#include "sph/solver.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <tbb/enumerable_thread_specific.h>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "physics/bubbles.hpp"
#include "physics/heat.hpp"
#include "physics/maxwell.hpp"

namespace bakesim::sph {
namespace {

// Fewer neighbours than this (a full support holds about 33 at h = 2s) mark a
// particle as surface whatever its colour gradient.
constexpr std::uint32_t kSparseNeighbours = 6;

bool is_mesh(const Collider& c) { return std::holds_alternative<MeshCollider>(c.geometry); }

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
      visc_lap_(h_),
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
      ncount_(particles_.add_int("neighbours")) {
  const Settings& s = setup_.settings;
  if (setup_.materials.empty()) throw InputError("materials", "no materials defined");
  for (const Material& m : setup_.materials) {
    tait_b_.push_back(m.rest_density * s.speed_of_sound * s.speed_of_sound / s.gamma);
    mass_.push_back(m.rest_density / lattice_sum_);
    conductivity_.push_back(m.conductivity);
  }
  for (std::size_t k = 0; k < setup_.materials.size(); ++k) {
    // Eq 3.43: 4/3 π r³ = m/ρ0, area π r².
    const Real r = std::cbrt(3.0 * mass_[k] / (4.0 * kPi * setup_.materials[k].rest_density));
    exchange_area_.push_back(kPi * r * r);
  }
  for (const Collider& c : setup_.colliders) heated_colliders_ |= c.temperature.has_value();
  adaptive_ = s.adaptive.enabled;
  for (const Material& m : setup_.materials)
    elastic_ |= !is_constant(m.elasticity) || std::get<ConstantCurve>(m.elasticity).value != 0.0;
  for (const Material& m : setup_.materials) follows_peak_ |= m.properties_follow_peak;
  for (const Body& b : setup_.bodies)
    bubble_b_.push_back(b.bubbles.pressure_scale ? *b.bubbles.pressure_scale
                                                 : tait_b_.at(std::clamp<int>(b.material, 0, int(tait_b_.size()) - 1)));
  // Implicit viscosity when the explicit viscous bound would be tighter than
  // the CFL bound at the largest viscosity any material reaches.
  implicit_viscosity_ = s.viscosity_solver == ViscositySolver::implicit;
  if (s.viscosity_solver == ViscositySolver::automatic) {
    const Real hs = 0.5 * h_;
    Real nu = 0;
    for (const Material& m : setup_.materials) nu = std::max(nu, curve_max(m.viscosity) / m.rest_density);
    implicit_viscosity_ = nu > 0 && s.viscous_factor * hs * hs / nu < s.cfl * hs / s.speed_of_sound;
  }
  // Domain walls come first, then analytic colliders; meshes are separate.
  walls_.push_back(Collider{"domain", InsideBoxCollider{setup_.domain}, setup_.domain_friction, setup_.domain_damping,
                            std::nullopt});
  for (const Collider& c : setup_.colliders) (is_mesh(c) ? meshes_ : walls_).push_back(c);

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
  t_browning_ = timers_.add("browning");
  t_properties_ = timers_.add("properties");
  t_smoothing_ = timers_.add("smoothing");
  t_check_ = timers_.add("check");

  seed_particles();
  refresh();
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
  for (std::size_t c = 1; c < walls_.size(); ++c)  // walls_[0] is the domain, checked when seeding
    for (std::size_t i = 0; i < x_.size(); ++i)
      for_each_wall(walls_[c].geometry, x_[i], 0.0, [&](const WallContact& w) {
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
      mu_[k] = evaluate(mat.viscosity, b.temperature);
      eps_[k] = std::clamp(evaluate(mat.xsph, b.temperature), 0.0, 1.0);
      elasticity_[k] = evaluate(mat.elasticity, b.temperature);
      relaxation_[k] = evaluate(mat.relaxation_time, b.temperature);
      stress_diag_[k].setZero();
      stress_off_[k].setZero();
      set_density_[k] = mat.rest_density;
      set_temperature_[k] = b.temperature;
      peak_temperature_[k] = b.temperature;
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
Mat3 SphSolver::velocity_gradient(std::size_t i) const {
  Mat3 grad = Mat3::Zero();
  const std::uint32_t* nb = lists_.begin(i);
  const std::uint32_t count = lists_.count(i);
  const float* pd = pair_dwr_.data() + i * lists_.stride();
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t j = nb[k];
    const Vec3 gw = Real(pd[k]) * (x_[i] - x_[j]);
    grad += (m_[j] / rho_[j]) * (v_[j] - v_[i]) * gw.transpose();
  }
  return grad;
}

// ---- phases ------------------------------------------------------------------

void SphSolver::phase_neighbours() {
  {
    ScopedPhase t(timers_, t_sort_);
    search_.sort_order(x_, order_);
    particles_.permute(order_);
  }
  ScopedPhase t(timers_, t_neigh_);
  if (adaptive_)
    search_.find(x_, smoothing_, lists_);
  else
    search_.find(x_, lists_);
  parallel_for(
      x_.size(), [&](std::size_t i) { ncount_[i] = static_cast<std::int32_t>(lists_.count(i)); }, 4096);
}

// Eq 3.13, plus the mass of a wall half-space at rest density for particles
// near analytic walls (see docs/physics.md, "wall density correction").
void SphSolver::phase_density() {
  ScopedPhase t(timers_, t_density_);
  const bool wall_corr = setup_.settings.wall_density_correction;
  const Real w0 = kernel_.w(0.0);
  const Vec3* x = x_.data();
  const Real* m = m_.data();
  const std::size_t stride = lists_.stride();
  pair_w_.resize(x_.size() * stride);
  pair_dwr_.resize(x_.size() * stride);
  parallel_for(x_.size(), [&](std::size_t i) {
    Real rho = m[i] * w0;
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pr = lists_.distances(i);
    float* pw = pair_w_.data() + i * stride;
    float* pd = pair_dwr_.data() + i * stride;
    if (adaptive_) {
      // Eq 3.56: the pair's kernel has support (h_i + h_j)/2; the self term h_i.
      rho = m[i] * CubicSpline(smoothing_[i]).w(0.0);
      for (std::uint32_t k = 0; k < count; ++k) {
        const Real r = pr[k];
        const CubicSpline pair_kernel(0.5 * (smoothing_[i] + smoothing_[nb[k]]));
        const Real w = pair_kernel.w(r);
        rho += m[nb[k]] * w;
        pw[k] = static_cast<float>(w);
        pd[k] = static_cast<float>(r > 0 ? pair_kernel.dw_dr_over_r(r) : 0.0);
      }
    } else {
      for (std::uint32_t k = 0; k < count; ++k) {
        const Real r = pr[k];
        const Real w = kernel_.w(r);
        rho += m[nb[k]] * w;
        pw[k] = static_cast<float>(w);
        pd[k] = static_cast<float>(r > 0 ? kernel_.dw_dr_over_r(r) : 0.0);
      }
    }
    if (wall_corr) rho += setup_.materials[material_[i]].rest_density * wall_share(x[i], nullptr);
    rho_[i] = rho;
  });
}

// Eq 3.17 (Tait, γ = 7); Eq 3.48–3.51 for rising bubbles; Eq 3.52 once the
// rise has ended (reference density ρ_f keeps the risen volume).
void SphSolver::phase_pressure() {
  ScopedPhase t(timers_, t_pressure_);
  const Real gamma = setup_.settings.gamma;
  const bool clamp = setup_.settings.clamp_negative_pressure;
  const bool elastic = elastic_;
  p_over_rho2_.resize(x_.size());
  volume_.resize(x_.size());
  if (elastic) stress_rho2_.resize(x_.size());
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        const int mat = material_[i];
        const Real rho0 = setup_.materials[mat].rest_density;
        Real p;
        if (rise_state_[i] == 2) {
          Real reference = set_density_[i];
          if (bubble_[i] && setup_.bodies[body_[i]].bubbles.contract_on_cooling)
            reference = contracted_reference_density(reference, temperature_[i], set_temperature_[i]);
          p = tait_pressure(tait_b_[mat], rho_[i], reference, gamma);
        } else if (rise_state_[i] == 1) {
          const Body& b = setup_.bodies[body_[i]];
          p = bubble_pressure(bubble_b_[body_[i]], rho_[i], rho0, temperature_[i], b.temperature);
        } else {
          p = tait_pressure(tait_b_[mat], rho_[i], rho0, gamma);
        }
        if (clamp && p < 0) p = 0;
        p_[i] = p;
        const Real inv_rho2 = 1.0 / (rho_[i] * rho_[i]);
        p_over_rho2_[i] = p * inv_rho2;
        volume_[i] = m_[i] / rho_[i];
        if (elastic) stress_rho2_[i] = stress(i) * inv_rho2;
      },
      1024);
}

// Colour gradient ∇C_i = Σ V_j ∇W_ij (Eq 3.28; points into the fluid) and the
// surface particles (thesis 3.1.8): |∇C| h above a threshold (colour), or the
// local convex hull test (convex_hull, every `surface_every` steps). Surface
// particles get the exchange area A_i = π r_i² with 4/3 π r_i³ = m_i/ρ0 (Eq 3.43).
void SphSolver::phase_surface() {
  ScopedPhase t(timers_, t_surface_);
  const Settings& s = setup_.settings;
  const std::size_t n = x_.size();
  colour_grad_.resize(n);
  parallel_for(n, [&](std::size_t i) {
    Vec3 grad = Vec3::Zero();
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pd = pair_dwr_.data() + i * lists_.stride();
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      grad += (m_[j] / rho_[j] * Real(pd[k])) * (x_[i] - x_[j]);
    }
    colour_grad_[i] = grad;
  });
  if (s.surface_method == SurfaceMethod::colour) {
    const Real threshold = s.surface_colour_threshold;
    // A particle with almost no neighbours (blown off, or at the tip of an
    // expanded bubble) has a vanishing gradient but is surface all the same.
    parallel_for(
        n,
        [&](std::size_t i) {
          surface_[i] =
              colour_grad_[i].norm() * smoothing_[i] >= threshold || lists_.count(i) < kSparseNeighbours ? 1 : 0;
        },
        4096);
  } else if (steps_ % s.surface_every == 0) {
    const Real threshold = s.surface_hull_threshold * s.spacing;
    struct Scratch {
      LocalConvexHull hull;
      std::vector<Vec3> points;
    };
    tbb::enumerable_thread_specific<Scratch> scratch;
    parallel_for(
        n,
        [&](std::size_t i) {
          Scratch& sc = scratch.local();
          sc.points.clear();
          const std::uint32_t* nb = lists_.begin(i);
          for (std::uint32_t k = 0; k < lists_.count(i); ++k) sc.points.push_back(x_[nb[k]]);
          surface_[i] = sc.hull.distance_to_boundary(x_[i], sc.points.data(), sc.points.size()) < threshold ? 1 : 0;
        },
        64);
  }
  parallel_for(
      n, [&](std::size_t i) { area_[i] = surface_[i] ? exchange_area_[material_[i]] : 0.0; }, 4096);
}

// Eq 3.20–3.27: the Maxwell stress follows the velocity gradient of the
// half-step velocities at the new positions.
void SphSolver::phase_stress(Real dt) {
  if (!elastic_) return;
  ScopedPhase t(timers_, t_stress_);
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        if (elasticity_[i] == 0.0 && stress_diag_[i].isZero() && stress_off_[i].isZero()) return;
        set_stress(i, maxwell_stress_step(stress(i), velocity_gradient(i), elasticity_[i], relaxation_[i], dt));
      },
      256);
}

void SphSolver::phase_forces() {
  ScopedPhase t(timers_, t_forces_);
  const Settings& s = setup_.settings;
  const Vec3* x = x_.data();
  const Vec3* v = v_.data();
  const Real* m = m_.data();
  const Real* rho = rho_.data();
  const Real* p = p_.data();
  const Real* mu = mu_.data();
  const Real c = s.speed_of_sound;
  const Real h = h_;
  const Real av_eps_h2 = s.av_epsilon * h * h;
  const bool artificial = s.av_alpha != 0.0 || s.av_beta != 0.0;
  bool any_tension = false;
  for (const Material& mat : setup_.materials) any_tension |= mat.surface_tension != 0.0;
  const Vec3 g = setup_.gravity;
  const bool wall_corr = s.wall_density_correction;

  const Real* p_rho2 = p_over_rho2_.data();
  const Real* vol = volume_.data();
  const bool explicit_visc = !implicit_viscosity_;
  const bool elastic = elastic_;
  const Mat3* s_rho2 = elastic ? stress_rho2_.data() : nullptr;
  const Real visc_c = visc_lap_.coefficient();  // Eq 3.8 (all listed pairs have r < h)
  const Real* hsup = smoothing_.data();
  const bool adaptive = adaptive_;
  // Monaghan (2000) artificial stress: R_i = Q diag(−ε max(σ'_a, 0)/ρ_i²) Qᵀ
  // from the principal stresses σ'_a of the total stress S − p I.
  const bool art_stress = elastic && s.artificial_stress > 0.0;
  const Real art_n = s.artificial_stress_exponent;
  if (art_stress) {
    artificial_stress_.resize(x_.size());
    const Real eps = s.artificial_stress;
    parallel_for(
        x_.size(),
        [&](std::size_t i) {
          const Mat3 sigma = s_rho2[i] - p_rho2[i] * Mat3::Identity();
          Eigen::SelfAdjointEigenSolver<Mat3> eig;
          eig.computeDirect(sigma);
          const Vec3 r = (-eps * eig.eigenvalues().cwiseMax(0.0)).eval();
          artificial_stress_[i] = eig.eigenvectors() * r.asDiagonal() * eig.eigenvectors().transpose();
        },
        1024);
  }
  const Mat3* art = art_stress ? artificial_stress_.data() : nullptr;
  // f = W(r)/W(Δp) with the pair's W from the density phase; with adaptive h
  // the spacing scales with h_ij, and W_hij(Δp h_ij/h) = W_h(Δp) (h/h_ij)³.
  const Real inv_w_dp = 1.0 / kernel_.w(s.spacing);
  const Real inv_h3 = 1.0 / (h * h * h);
  parallel_for(x_.size(), [&](std::size_t i) {
    const Vec3 xi = x[i], vi = v[i];
    const Real hi = hsup[i];
    const Real lap_w0 = adaptive ? CubicSpline(hi).laplacian(0.0) : kernel_.laplacian(0.0);
    const Real rhoi = rho[i], pi_rho2 = p_rho2[i], mui = mu[i];
    Vec3 acc_p = Vec3::Zero(), acc_v = Vec3::Zero(), acc_av = Vec3::Zero(), acc_s = Vec3::Zero();
    const Vec3 normal = colour_grad_[i];
    // The colour sums run over all j including i (Eq 3.28); the self term of
    // the Laplacian is large and negative, without it ∇²C is biased positive
    // and the force would point outwards.
    Real lap_c = vol[i] * lap_w0;
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pr = lists_.distances(i);
    const float* pd = pair_dwr_.data() + i * lists_.stride();
    const float* pw = pair_w_.data() + i * lists_.stride();
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const Real r = pr[k];
      const Vec3 xij = xi - x[j];
      const Vec3 grad = Real(pd[k]) * xij;  // zero for coincident particles
      // Eq 3.56: the pair's support (the global h unless adaptive).
      const Real hij = adaptive ? 0.5 * (hi + hsup[j]) : h;
      // Eq 3.18: symmetric pressure gradient.
      acc_p -= (m[j] * (pi_rho2 + p_rho2[j])) * grad;
      // Eq 3.19: pairwise-averaged viscosity with the viscosity-kernel Laplacian.
      const Vec3 vij = vi - v[j];
      if (explicit_visc) {
        const Real vc = adaptive ? ViscosityLaplacian::coefficient_for(hij) : visc_c;
        acc_v -= (0.5 * (mui + mu[j]) * vol[j] * vc * (hij - r)) * vij;
      }
      // Divergence of the viscoelastic stress (Eq 2.18 in SPH form):
      // Σ m_j (S_i/ρ_i² + S_j/ρ_j²) ∇_i W_ij.
      if (elastic) acc_s += m[j] * ((s_rho2[i] + s_rho2[j]) * grad);
      // Artificial stress: m_j f_ij^n (R_i + R_j) ∇_i W_ij, f = W(r)/W(Δp).
      if (art_stress) {
        const Real f = Real(pw[k]) * inv_w_dp * (adaptive ? hij * hij * hij * inv_h3 : 1.0);
        const Real fn = art_n == 4.0 ? (f * f) * (f * f) : std::pow(f, art_n);
        acc_s += (m[j] * fn) * ((art[i] + art[j]) * grad);
      }
      // Eq 3.35–3.41: artificial viscosity, only for approaching pairs
      // (branch-free: min(v·x, 0) makes Π vanish for receding pairs).
      if (artificial) {
        const Real vx = std::min(vij.dot(xij), 0.0);
        const Real denom = r * r + (adaptive ? s.av_epsilon * hij * hij : av_eps_h2);
        const Real inv = 1.0 / (denom * denom * 0.5 * (rhoi + rho[j]));
        const Real hvx = hij * vx;
        const Real pi_ij = (-s.av_alpha * c * hvx * denom + s.av_beta * hvx * hvx) * inv;
        acc_av -= (m[j] * pi_ij) * grad;
      }
      // Eq 3.29: colour field Laplacian (the gradient, Eq 3.28, comes from the surface phase).
      if (any_tension) lap_c += vol[j] * (adaptive ? CubicSpline(hij).laplacian(r) : kernel_.laplacian(r));
    }
    Vec3 acc = acc_p + acc_v / rhoi + acc_av + acc_s + g;
    if (any_tension) {
      const Real sigma = setup_.materials[material_[i]].surface_tension;
      const Real nn = normal.norm();
      // Eq 3.30, only where |N| is large enough for a stable direction.
      if (sigma != 0.0 && nn * hi > s.surface_threshold) acc += (-sigma / rhoi * lap_c / nn) * normal;
    }
    if (wall_corr && p[i] > 0) {
      // Pressure of the wall half-space mirrored at the particle's pressure.
      const Real rho0 = setup_.materials[material_[i]].rest_density;
      const Real coef = p[i] * (1.0 / (rhoi * rhoi) + 1.0 / (rho0 * rho0)) * rho0;
      Vec3 grad_share;
      if (wall_share(xi, &grad_share) > 0) acc -= coef * grad_share;
    }
    a_[i] = acc;
  });
}

Real SphSolver::wall_share(const Vec3& x, Vec3* gradient) const {
  // Few walls are ever within reach; keep their fractions on the stack.
  constexpr int kMax = 16;
  Real f[kMax];
  Vec3 n[kMax];
  Real df[kMax];
  int count = 0;
  for (const Collider& c : walls_)
    for_each_wall(c.geometry, x, h_, [&](const WallContact& w) {
      if (count < kMax) {
        f[count] = wall_share_.fraction(w.distance);
        df[count] = wall_share_.slope(w.distance);
        n[count] = w.normal;
        ++count;
      }
    });
  if (gradient) gradient->setZero();
  if (count == 0) return 0.0;
  Real keep = 1.0;
  for (int k = 0; k < count; ++k) keep *= 1.0 - f[k];
  if (gradient)
    for (int k = 0; k < count; ++k) {
      Real others = 1.0;
      for (int l = 0; l < count; ++l)
        if (l != k) others *= 1.0 - f[l];
      // d f_k / dx = −slope(d_k) · n_k (d grows along the wall normal).
      *gradient -= others * df[k] * n[k];
    }
  return 1.0 - keep;
}

void SphSolver::phase_kick(Real dt) {
  ScopedPhase t(timers_, t_kick_);
  const Real half = 0.5 * dt;
  parallel_for(
      x_.size(), [&](std::size_t i) { v_[i] += half * a_[i]; }, 4096);
}

void SphSolver::phase_drift(Real dt) {
  ScopedPhase t(timers_, t_drift_);
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        x_prev_[i] = x_[i];
        x_[i] += dt * v_[i];
      },
      4096);
}

// Eq 3.31–3.33: v_new = β_c v_tangent − α_c v_normal with β_c = 1 − friction
// and α_c = 1 − damping. Analytic walls push the particle back to the contact
// distance; meshes revert it to its previous position (thesis 3.1.9).
void SphSolver::phase_collide() {
  ScopedPhase t(timers_, t_collide_);
  const Real rc = contact_distance_;
  auto respond = [](Vec3& v, const Vec3& n, Real friction, Real damping) {
    const Real vn = v.dot(n);
    if (vn >= 0) return;
    const Vec3 normal = vn * n;
    const Vec3 tangent = v - normal;
    v = (1.0 - friction) * tangent - (1.0 - damping) * normal;
  };
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        Vec3& xi = x_[i];
        Vec3& vi = v_[i];
        for (const Collider& c : walls_) {
          for_each_wall(c.geometry, xi, rc, [&](const WallContact& w) {
            xi += (rc - w.distance) * w.normal;
            respond(vi, w.normal, c.friction, c.damping);
          });
        }
        for (const Collider& c : meshes_) {
          const MeshCollider& mesh = std::get<MeshCollider>(c.geometry);
          const SegmentHit hit = mesh_segment_hits(mesh, x_prev_[i], xi, rc);
          if (hit.hits > 0) {
            const Real len = hit.normal_sum.norm();
            const Vec3 n = len > 0 ? Vec3(hit.normal_sum / len) : Vec3::UnitY();
            // Keep the part of the step along the surface when that path is
            // free: a particle sent back to x_{t−1} on every step would never
            // slide down a slope while gravity kept feeding its velocity.
            const Vec3 d = xi - x_prev_[i];
            const Real dn = d.dot(n);
            const Vec3 slid = x_prev_[i] + (dn < 0 ? Vec3(d - dn * n) : d);
            xi = mesh_segment_hits(mesh, x_prev_[i], slid, rc).hits == 0 ? slid : x_prev_[i];
            respond(vi, n, c.friction, c.damping);
          }
        }
      },
      1024);
}

// Eq 3.34 with the pairwise mean of ε (keeps the correction momentum-conserving).
void SphSolver::phase_xsph() {
  ScopedPhase t(timers_, t_xsph_);
  bool any = false;
  for (const Material& m : setup_.materials) any |= !is_constant(m.xsph) || std::get<ConstantCurve>(m.xsph).value > 0;
  if (!any) return;
  const Vec3* v = v_.data();
  parallel_for(x_.size(), [&](std::size_t i) {
    Vec3 corr = Vec3::Zero();
    const Vec3 vi = v[i];
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pw = pair_w_.data() + i * lists_.stride();
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const Real w = pw[k];
      corr += (0.5 * (eps_[i] + eps_[j]) * 2.0 * m_[j] / (rho_[i] + rho_[j]) * w) * (v[j] - vi);
    }
    dv_[i] = corr;
  });
  parallel_for(
      x_.size(), [&](std::size_t i) { v_[i] += dv_[i]; }, 4096);
}

// Eq 3.45–3.46: ρ c_p dT/dt = ∇·(k∇T). The kernel Laplacian of Eq 3.46
// changes sign inside the support (heat could flow from cold to hot for close
// pairs), so the Laplacian is taken in the Cleary–Monaghan form
//   (∇·k∇T)_i = Σ_j V_j (k_i + k_j)(T_i − T_j) x_ij·∇W_ij / (r² + η²),
// which is always diffusive and exchanges heat pairwise (energy is conserved).
// Then Eq 3.42–3.43 at surface particles: m c_p dT/dt = h A (T_ext − T) with
// T_ext the touching collider's temperature, or the oven air's. Heat runs on
// the bake clock: dt_bake = scale · dt.
void SphSolver::phase_heat(Real dt) {
  ScopedPhase t(timers_, t_heat_);
  const Environment& env = setup_.environment;
  const Real dt_bake = dt * env.bake_time_scale;
  const std::size_t n = x_.size();
  if (setup_.settings.heat_conduction) {
    // Nothing flows in an isothermal state (a common case: water at room temperature).
    using Range = std::pair<Real, Real>;
    const Real inf = std::numeric_limits<Real>::infinity();
    const Range range = deterministic_reduce(
        n, Range{inf, -inf},
        [&](std::size_t b, std::size_t e) {
          Range r{inf, -inf};
          for (std::size_t i = b; i < e; ++i) {
            r.first = std::min(r.first, temperature_[i]);
            r.second = std::max(r.second, temperature_[i]);
          }
          return r;
        },
        [](Range a, Range b) {
          return Range{std::min(a.first, b.first), std::max(a.second, b.second)};
        });
    if (range.second > range.first) {
      const Real eta2_fixed = 0.01 * h_ * h_;
      const Real* hsup = smoothing_.data();
      const Real* temp = temperature_.data();
      const Real* vol = volume_.data();
      parallel_for(n, [&](std::size_t i) {
        const Material& mi = setup_.materials[material_[i]];
        const Real ti = temp[i], ki = mi.conductivity;
        const std::uint32_t* nb = lists_.begin(i);
        const std::uint32_t count = lists_.count(i);
        const float* pr = lists_.distances(i);
        const float* pd = pair_dwr_.data() + i * lists_.stride();
        Real sum = 0;
        for (std::uint32_t k = 0; k < count; ++k) {
          const std::uint32_t j = nb[k];
          const Real r = pr[k];
          // x_ij·∇W = r² W'(r)/r
          const Real kj = conductivity_[material_[j]];
          const Real hij = 0.5 * (hsup[i] + hsup[j]);
          const Real eta2 = adaptive_ ? 0.01 * hij * hij : eta2_fixed;
          sum += vol[j] * (ki + kj) * (ti - temp[j]) * (Real(pd[k]) * r * r) / (r * r + eta2);
        }
        dtemp_[i] = setup_.bodies[body_[i]].hold_temperature ? 0.0 : dt_bake * sum / (rho_[i] * mi.specific_heat);
      });
      parallel_for(
          n, [&](std::size_t i) { temperature_[i] += dtemp_[i]; }, 4096);
    }
  }
  // External exchange (Eq 3.42 with the sign and heat capacity restored).
  const Real air = env.air_temperature(bake_time());
  const Real h_air = env.heat_transfer_coefficient;
  const Real touch = setup_.settings.spacing;  // contact: within one spacing of the collider surface
  // Collider temperatures at this bake time, read once (walls, then meshes).
  std::vector<Real> wall_temperature(walls_.size(), 0.0), mesh_temperature(meshes_.size(), 0.0);
  for (std::size_t c = 0; c < walls_.size(); ++c)
    if (walls_[c].temperature) wall_temperature[c] = (*walls_[c].temperature)(bake_time());
  for (std::size_t c = 0; c < meshes_.size(); ++c)
    if (meshes_[c].temperature) mesh_temperature[c] = (*meshes_[c].temperature)(bake_time());
  parallel_for(
      n,
      [&](std::size_t i) {
        dtemp_[i] = 0.0;
        if (!surface_[i] || area_[i] <= 0 || setup_.bodies[body_[i]].hold_temperature) return;
        Real outside = air, coefficient = h_air;
        if (heated_colliders_) {
          bool found = false;
          for (std::size_t ci = 0; ci < walls_.size(); ++ci) {
            const Collider& c = walls_[ci];
            if (!c.temperature || found) continue;
            for_each_wall(c.geometry, x_[i], touch, [&](const WallContact&) { found = true; });
            if (found) {
              outside = wall_temperature[ci];
              coefficient = c.heat_transfer_coefficient;
            }
          }
          const Real len = colour_grad_[i].norm();
          for (std::size_t ci = 0; ci < meshes_.size(); ++ci) {
            const Collider& c = meshes_[ci];
            if (!c.temperature || found || len <= 0) continue;
            const Vec3 out = -colour_grad_[i] / len;
            if (mesh_segment_hits(std::get<MeshCollider>(c.geometry), x_[i], x_[i] + touch * out, 0.0).hits > 0) {
              found = true;
              outside = mesh_temperature[ci];
              coefficient = c.heat_transfer_coefficient;
            }
          }
        }
        const Real capacity = m_[i] * setup_.materials[material_[i]].specific_heat;
        const Real before = temperature_[i];
        temperature_[i] = exchange_temperature(before, outside, coefficient * area_[i], capacity, dt_bake);
        dtemp_[i] = exchanged_energy(before, temperature_[i], capacity);
      },
      1024);
  exchanged_heat_ += deterministic_sum(n, [&](std::size_t i) { return dtemp_[i]; });
}

// Eq 4.1–4.4: viscosity, elasticity, relaxation time and XSPH tuner follow
// each particle's temperature (or the peak it reached, for irreversible
// setting). Each curve is visited once per material; the particle loop sees
// a plain callable. Then the rise state of Eq 3.48–3.52.
void SphSolver::phase_properties() {
  ScopedPhase t(timers_, t_properties_);
  const std::size_t n = x_.size();
  if (follows_peak_)
    parallel_for(
        n, [&](std::size_t i) { peak_temperature_[i] = std::max(peak_temperature_[i], temperature_[i]); }, 4096);
  auto follow = [&](int id, const TemperatureCurve& c, std::vector<Real>& out, Real lo, Real hi) {
    if (is_constant(c)) return;
    const std::vector<Real>& t = setup_.materials[id].properties_follow_peak ? peak_temperature_ : temperature_;
    std::visit(
        [&](const auto& curve) {
          parallel_for(
              n,
              [&](std::size_t i) {
                if (material_[i] == id) out[i] = std::clamp(curve(t[i]), lo, hi);
              },
              4096);
        },
        c);
  };
  const Real inf = std::numeric_limits<Real>::infinity();
  for (std::size_t mi = 0; mi < setup_.materials.size(); ++mi) {
    const Material& mat = setup_.materials[mi];
    const int id = static_cast<int>(mi);
    follow(id, mat.viscosity, mu_, 0.0, inf);
    follow(id, mat.xsph, eps_, 0.0, 1.0);
    follow(id, mat.elasticity, elasticity_, 0.0, inf);
    follow(id, mat.relaxation_time, relaxation_, 1e-9, inf);  // λ > 0 (Eq 3.20 divides by it)
  }
  // Bubbles start rising once heating begins; a bubble stops when it has
  // expanded max_expansion times, and every particle of the body switches to
  // the risen Tait law at end_temperature (ρ_f: its density then, Eq 3.52).
  parallel_for(
      n,
      [&](std::size_t i) {
        const Body& b = setup_.bodies[body_[i]];
        if (b.bubbles.fraction <= 0 || rise_state_[i] == 2) return;
        const Real rho0 = setup_.materials[material_[i]].rest_density;
        const bool rising = rise_state_[i] == 1;
        if (bubble_[i] && !rising && temperature_[i] > b.temperature + 0.5) rise_state_[i] = 1;
        const bool done = temperature_[i] >= b.bubbles.end_temperature ||
                          (bubble_[i] && rise_state_[i] == 1 && rho0 / rho_[i] >= b.bubbles.max_expansion);
        if (done) {
          rise_state_[i] = 2;
          set_density_[i] = std::min(rho_[i], rho0);
          set_temperature_[i] = temperature_[i];
        }
      },
      4096);
}

// Eq 3.54–3.55: h_i = k_g (ρ_i/ρ_ref)^(−ε_g) h0 for the next step, with
// ρ_ref the geometric mean of ρ/ρ0 over all particles (each material against
// its own rest density) or ρ0 itself; clamped to the configured range.
void SphSolver::phase_smoothing() {
  if (!adaptive_) return;
  ScopedPhase t(timers_, t_smoothing_);
  const AdaptiveSmoothing& a = setup_.settings.adaptive;
  const std::size_t n = x_.size();
  Real log_mean = 0;
  if (a.geometric_mean && n > 0) {
    log_mean = deterministic_sum(
                   n, [&](std::size_t i) { return std::log(rho_[i] / setup_.materials[material_[i]].rest_density); }) /
               Real(n);
  }
  const Real lo = a.min_ratio * h_, hi = a.max_ratio * h_;
  parallel_for(
      n,
      [&](std::size_t i) {
        const Real relative = std::log(rho_[i] / setup_.materials[material_[i]].rest_density) - log_mean;
        smoothing_[i] = std::clamp(a.scale * std::exp(-a.sensitivity * relative) * h_, lo, hi);
      },
      4096);
}

void SphSolver::check_finite() {
  ScopedPhase t(timers_, t_check_);
  const std::size_t n = x_.size();
  // Non-finite state, a particle outside the domain, or a density collapsed
  // below 1% of the rest density (a particle that lost all its neighbours
  // while inside the fluid: the pressure has blown the fluid apart).
  auto collapsed = [&](std::size_t i) { return rho_[i] < 0.01 * setup_.materials[material_[i]].rest_density; };
  const std::size_t bad = deterministic_reduce(
      n, n,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i)
          if (!x_[i].allFinite() || !v_[i].allFinite() || !std::isfinite(rho_[i]) || !std::isfinite(p_[i]) ||
              !std::isfinite(temperature_[i]) || !setup_.domain.contains(x_[i]) || collapsed(i))
            return i;
        return n;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  if (bad == n) return;
  const std::string quantity = !x_[bad].allFinite()                ? "non-finite position"
                               : !v_[bad].allFinite()              ? "non-finite velocity"
                               : !std::isfinite(rho_[bad])         ? "non-finite density"
                               : !std::isfinite(p_[bad])           ? "non-finite pressure"
                               : !std::isfinite(temperature_[bad]) ? "non-finite temperature"
                               : !setup_.domain.contains(x_[bad])  ? "position outside the domain"
                                                                   : "collapsed density";
  std::string neighbours;
  const bool listed = bad < lists_.size();
  const std::uint32_t* nb = listed ? lists_.begin(bad) : nullptr;
  const std::uint32_t count = listed ? lists_.count(bad) : 0;
  for (std::uint32_t k = 0; k < std::min<std::uint32_t>(count, 4); ++k) {
    const std::uint32_t j = nb[k];
    neighbours +=
        fmt::format("{}particle {} (x ({:.4g}, {:.4g}, {:.4g}), v ({:.4g}, {:.4g}, {:.4g}), density {:.6g}, T {:.4g})",
                    k ? "; " : "", id_[j], x_[j].x(), x_[j].y(), x_[j].z(), v_[j].x(), v_[j].y(), v_[j].z(), rho_[j],
                    temperature_[j]);
  }
  throw SimulationError(
      fmt::format("SPH step {} (t = {:.6g} s): particle {} of body '{}' has a {}: x ({:.4g}, {:.4g}, {:.4g}), v "
                  "({:.4g}, {:.4g}, {:.4g}), "
                  "density {:.6g} kg/m^3, pressure {:.6g} Pa, T {:.4g} degC, {} neighbours{}{}",
                  steps_, time_, id_[bad], setup_.bodies[body_[bad]].name, quantity, x_[bad].x(), x_[bad].y(),
                  x_[bad].z(), v_[bad].x(), v_[bad].y(), v_[bad].z(), rho_[bad], p_[bad], temperature_[bad], count,
                  count ? ": " : "", neighbours));
}

// ---- driver ------------------------------------------------------------------

std::vector<std::pair<std::string, Real>> SphSolver::time_step_bounds() const {
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
  std::vector<std::pair<std::string, Real>> bounds;
  bounds.emplace_back("max_dt", s.max_dt);
  bounds.emplace_back("cfl", s.cfl * hs / (s.speed_of_sound + std::sqrt(e.v2)));
  // Shear waves of the Maxwell stress travel at sqrt(μ_e/ρ).
  if (e.shear > 0) bounds.emplace_back("elastic", s.cfl * hs / std::sqrt(e.shear));
  if (e.nu > 0 && !implicit_viscosity_) bounds.emplace_back("viscosity", s.viscous_factor * hs * hs / e.nu);
  if (e.a2 > 0) bounds.emplace_back("force", s.force_factor * std::sqrt(hs / std::sqrt(e.a2)));
  if (s.heat_conduction) {
    Real alpha = 0;  // thermal diffusivity k / (ρ c_p), largest over materials
    for (const Material& m : setup_.materials)
      alpha = std::max(alpha, m.conductivity / (m.rest_density * m.specific_heat));
    alpha *= setup_.environment.bake_time_scale;  // heat runs on the bake clock
    if (alpha > 0) bounds.emplace_back("conduction", s.conduction_factor * hs * hs / alpha);
  }
  return bounds;
}

Real SphSolver::max_stable_dt() {
  Real dt = std::numeric_limits<Real>::infinity();
  for (const auto& [name, value] : time_step_bounds())
    if (value < dt) {
      dt = value;
      dt_bound_ = name;
    }
  return dt;
}

// Crust colour (Zanoni et al. 1995, physics/browning.hpp) from each particle's
// temperature, on the bake clock. Every particle browns at its own
// temperature; the crust browns first because it is the hottest.
void SphSolver::phase_browning(Real dt) {
  ScopedPhase t(timers_, t_browning_);
  const BrowningKinetics& kinetics = setup_.environment.browning;
  const Real dt_bake = dt * setup_.environment.bake_time_scale;
  parallel_for(x_.size(),
               [&](std::size_t i) { browning_[i] = kinetics.advance(browning_[i], temperature_[i], dt_bake); });
}

void SphSolver::step(Real dt) {
  if (!(dt > 0) || !std::isfinite(dt))
    throw SimulationError(fmt::format("SPH step {}: invalid time step {}", steps_, dt));
  phase_kick(dt);
  phase_drift(dt);
  phase_collide();
  phase_neighbours();
  phase_density();
  phase_surface();
  phase_stress(dt);
  phase_pressure();
  phase_forces();
  phase_kick(dt);
  phase_xsph();
  phase_viscosity(dt);
  phase_heat(dt);
  phase_browning(dt);
  phase_properties();
  phase_smoothing();
  time_ += dt;
  ++steps_;
  check_finite();
}

// ---- probes ------------------------------------------------------------------

std::vector<std::string> SphSolver::probe_quantities() const {
  return {"temperature", "density", "pressure", "speed", "velocity_x", "velocity_y", "velocity_z"};
}

// Shepard-normalised SPH interpolation: A(x) = Σ V_j A_j W / Σ V_j W.
std::vector<Real> SphSolver::sample(const Vec3& x, const std::vector<std::string>& quantities) const {
  // Resolve names once, outside the neighbour loop.
  enum class Q { temperature, density, pressure, speed, vx, vy, vz };
  std::vector<Q> qs;
  for (const std::string& name : quantities) {
    if (name == "temperature")
      qs.push_back(Q::temperature);
    else if (name == "density")
      qs.push_back(Q::density);
    else if (name == "pressure")
      qs.push_back(Q::pressure);
    else if (name == "speed")
      qs.push_back(Q::speed);
    else if (name == "velocity_x")
      qs.push_back(Q::vx);
    else if (name == "velocity_y")
      qs.push_back(Q::vy);
    else if (name == "velocity_z")
      qs.push_back(Q::vz);
    else
      throw InputError("probes", "unknown probe quantity '" + name + "'");
  }
  std::vector<Real> sum(qs.size(), 0.0);
  Real wsum = 0.0;
  const Real h2 = h_ * h_;
  search_.grid().for_each_within(x, h_, [&](std::uint32_t j) {
    const Real r2 = (x_[j] - x).squaredNorm();
    if (r2 >= h2) return;
    const Real w = m_[j] / rho_[j] * kernel_.w(std::sqrt(r2));
    wsum += w;
    for (std::size_t q = 0; q < qs.size(); ++q) {
      Real val = 0;
      switch (qs[q]) {
        case Q::temperature: val = temperature_[j]; break;
        case Q::density: val = rho_[j]; break;
        case Q::pressure: val = p_[j]; break;
        case Q::speed: val = v_[j].norm(); break;
        case Q::vx: val = v_[j].x(); break;
        case Q::vy: val = v_[j].y(); break;
        case Q::vz: val = v_[j].z(); break;
      }
      sum[q] += w * val;
    }
  });
  for (Real& s : sum) s = wsum > 1e-12 ? s / wsum : std::numeric_limits<Real>::quiet_NaN();
  return sum;
}

}  // namespace bakesim::sph

namespace bakesim::sph {

std::vector<std::pair<std::string, double>> SphSolver::checkpoint_state() const {
  return {{"time", time_}, {"steps", double(steps_)}, {"exchanged_heat", exchanged_heat_}};
}

void SphSolver::restore_state(const std::vector<std::pair<std::string, double>>& state) {
  for (const auto& [name, value] : state) {
    if (name == "time")
      time_ = value;
    else if (name == "steps")
      steps_ = long(value);
    else if (name == "exchanged_heat")
      exchanged_heat_ = value;
  }
  // Neighbour lists, pair kernels and per-step scratch are rebuilt by the next
  // step, which starts by sorting and searching.
}

}  // namespace bakesim::sph
