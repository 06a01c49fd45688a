#include "mpm/solver.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.hpp"
#include "core/parallel.hpp"

namespace bakesim::mpm {

namespace {

// Quadratic B-spline weights along one axis for a particle at grid
// coordinate xi (in cells): nodes base, base+1, base+2 at offsets
// (x_node − x_p)/Δx = k − frac.
struct Axis {
  int base;
  Real frac;
  Real w[3];
};

inline Axis axis_weights(Real xi) {
  Axis a;
  a.base = static_cast<int>(std::floor(xi - 0.5));
  const Real f = xi - a.base;
  a.frac = f;
  a.w[0] = 0.5 * (1.5 - f) * (1.5 - f);
  a.w[1] = 0.75 - (f - 1.0) * (f - 1.0);
  a.w[2] = 0.5 * (f - 0.5) * (f - 0.5);
  return a;
}

void apply_contact(Vec3& v, const Vec3& n, Contact contact, Real mu) {
  const Real vn = v.dot(n);
  if (contact == Contact::sticky) {
    v.setZero();
    return;
  }
  if (contact == Contact::separate && vn >= 0) return;  // leaving the wall
  Vec3 vt = v - vn * n;
  const Real pressure = std::abs(std::min(vn, Real(0)));  // Coulomb: friction ∝ the removed normal speed
  const Real t = vt.norm();
  if (mu > 0 && t > 0) vt *= std::max(Real(0), 1 - mu * pressure / t);
  v = vt;
}

// Calls fn(p, ax, ay, az) for every particle, block colour by block colour:
// same-coloured blocks never share a node, so scatters need no atomics.
template <class Fn>
void for_each_by_colour(const std::vector<std::vector<std::uint32_t>>& colour_blocks,
                        const std::vector<std::uint32_t>& block_start, const std::vector<std::uint32_t>& order,
                        const std::vector<Vec3>& x, const Vec3& origin, Real inv_dx, Fn&& fn) {
  for (const auto& blocks : colour_blocks) {
    parallel_for(
        blocks.size(),
        [&](std::size_t bi) {
          const std::uint32_t b = blocks[bi];
          for (std::uint32_t k = block_start[b]; k < block_start[b + 1]; ++k) {
            const std::uint32_t p = order[k];
            const Vec3 g = (x[p] - origin) * inv_dx;
            fn(p, axis_weights(g.x()), axis_weights(g.y()), axis_weights(g.z()));
          }
        },
        1);
  }
}

}  // namespace

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
      browning_(particles_.add_scalar("browning", "")),
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
      heat_src_(particles_.add_scalar("heat_source", "W", false)),
      heat_vec_(particles_.add_vector("heat_flux_term", "W", false)),
      water_src_(particles_.add_scalar("water_source", "kg/s", false)),
      water_vec_(particles_.add_vector("water_flux_term", "kg/s", false)),
      material_(particles_.add_int("material_id")),
      body_(particles_.add_int("body_id")),
      id_(particles_.add_int("id")) {
  const Settings& s = setup_.settings;
  if (!(s.cell_size > 0)) throw InputError("solver.mpm.cell_size", "must be positive");
  dx_ = s.cell_size;
  inv_dx_ = 1.0 / dx_;
  const Vec3 ext = setup_.domain.extent();
  nx_ = static_cast<int>(std::ceil(ext.x() * inv_dx_)) + 1;
  ny_ = static_cast<int>(std::ceil(ext.y() * inv_dx_)) + 1;
  nz_ = static_cast<int>(std::ceil(ext.z() * inv_dx_)) + 1;
  const std::size_t nodes = std::size_t(nx_) * ny_ * nz_;
  if (nodes > 400'000'000)
    throw InputError("solver.mpm.cell_size", "the grid over the domain would have more than 4e8 nodes");
  grid_.assign(nodes, Node{0, {0, 0, 0}});
  if (thermal()) heat_grid_.assign(nodes, HeatNode{});
  if (s.heat == HeatMethod::implicit) implicit_mass_.assign(nodes, 0);
  if (!setup_.colliders.empty()) near_collider_.assign(nodes, 0);
  bx_ = (nx_ + kBlock - 1) / kBlock;
  by_ = (ny_ + kBlock - 1) / kBlock;
  bz_ = (nz_ + kBlock - 1) / kBlock;
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
  build_particles();
  phase_sort();
  initial_body_water_.assign(setup_.bodies.size(), 0);
  for (std::size_t i = 0; i < x_.size(); ++i) initial_body_water_[body_[i]] += water_[i];
}

void MpmSolver::build_particles() {
  const Settings& s = setup_.settings;
  const Real spacing = dx_ / std::cbrt(Real(s.particles_per_cell));
  const Vec3 lo = setup_.domain.min + Vec3::Constant(2 * dx_), hi = setup_.domain.max - Vec3::Constant(2 * dx_);
  std::vector<std::vector<Vec3>> points(setup_.bodies.size());
  std::size_t total = 0;
  for (std::size_t b = 0; b < setup_.bodies.size(); ++b) {
    for (const Vec3& p : sample_lattice(setup_.bodies[b].shape, spacing))
      if ((p.array() > lo.array()).all() && (p.array() < hi.array()).all()) points[b].push_back(p);
    if (points[b].empty())
      throw InputError("bodies[" + std::to_string(b) + "]",
                       "no material points inside the domain (shape too small for the cell size, or outside)");
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
      heat_capacity_[k] = m_[k] * mat.specific_heat;
      const bool wet = !s.baseline && mat.water.active();
      water_[k] = wet ? mat.water.saturation * mat.water.water_density * vol : 0;
      saturation_[k] = wet ? mat.water.saturation : 0;
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

namespace {
// 3×3 per-particle matrices are stored as three column attributes.
Mat3 from_columns(const Vec3& a, const Vec3& b, const Vec3& c) {
  Mat3 m;
  m << a, b, c;
  return m;
}
void to_columns(const Mat3& m, Vec3& a, Vec3& b, Vec3& c) {
  a = m.col(0);
  b = m.col(1);
  c = m.col(2);
}
}  // namespace

Mat3 MpmSolver::deformation_gradient(std::size_t i) const { return from_columns(f0_[i], f1_[i], f2_[i]); }
void MpmSolver::set_deformation_gradient(std::size_t i, const Mat3& f) { to_columns(f, f0_[i], f1_[i], f2_[i]); }
Mat3 MpmSolver::affine(std::size_t i) const { return from_columns(c0_[i], c1_[i], c2_[i]); }
void MpmSolver::set_affine(std::size_t i, const Mat3& c) { to_columns(c, c0_[i], c1_[i], c2_[i]); }

Real MpmSolver::total_mass() const {
  return deterministic_sum(m_.size(), [&](std::size_t i) { return m_[i]; });
}

Real MpmSolver::grid_mass() const {
  return deterministic_sum(grid_.size(), [&](std::size_t k) { return grid_[k].mass; });
}

// Spec 4.7: Δt ≤ CFL Δx / max|v|, Δt ≤ CFL Δx / c with c = sqrt((λ+2μ+ξ s₀)/ρ);
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
  if (max_wave_speed_ > 0) limit(s.cfl * dx_ / max_wave_speed_, "elastic_wave");
  if (heat) {
    const Real scale = s.bake_time_scale;
    for (const Material& mat : setup_.materials) {
      if (s.heat == HeatMethod::explicit_ && mat.conductivity > 0)
        limit(
            mat.density * mat.specific_heat * dx_ * dx_ / (6 * mat.conductivity * std::max(acc.jmax, Real(1))) / scale,
            "heat_conduction");
      if (!s.baseline && mat.water.active() && mat.water.diffusivity > 0)
        limit(dx_ * dx_ / (6 * mat.water.diffusion_coefficient(std::max(acc.tmax, Real(100)))) / scale,
              "water_diffusion");
    }
    if (s.heat == HeatMethod::explicit_ && acc.exchange > 0) limit(0.5 / acc.exchange / scale, "heat_exchange");
  }
  return dt;
}

// Crust colour (Zanoni et al. 1995, physics/browning.hpp) from each point's
// temperature after this step's heat transfer, on the bake clock.
void MpmSolver::phase_browning(Real dt) {
  ScopedPhase t(timers_, t_browning_);
  const BrowningKinetics& kinetics = setup_.browning;
  const Real dt_bake = dt * setup_.settings.bake_time_scale;
  parallel_for(x_.size(),
               [&](std::size_t i) { browning_[i] = kinetics.advance(browning_[i], temperature_[i], dt_bake); });
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

// Particles grouped by grid block (counting sort of an index array); every
// reorder_every steps the particle memory itself follows, so P2G and G2P walk
// memory in order.
void MpmSolver::phase_sort() {
  ScopedPhase t(timers_, t_sort_);
  const std::size_t n = x_.size();
  const std::size_t blocks = std::size_t(bx_) * by_ * bz_;
  block_key_.resize(n);
  const Vec3 origin = setup_.domain.min;
  parallel_for(
      n,
      [&](std::size_t i) {
        const Vec3 g = (x_[i] - origin) * inv_dx_;
        int c[3];
        for (int d = 0; d < 3; ++d) c[d] = std::max(0, static_cast<int>(std::floor(g[d] - 0.5))) / kBlock;
        c[0] = std::min(c[0], bx_ - 1);
        c[1] = std::min(c[1], by_ - 1);
        c[2] = std::min(c[2], bz_ - 1);
        block_key_[i] = static_cast<std::uint32_t>((std::size_t(c[0]) * by_ + c[1]) * bz_ + c[2]);
      },
      4096);
  block_start_.assign(blocks + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++block_start_[block_key_[i] + 1];
  for (std::size_t b = 0; b < blocks; ++b) block_start_[b + 1] += block_start_[b];
  order_.resize(n);
  block_fill_.assign(block_start_.begin(), block_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order_[block_fill_[block_key_[i]]++] = static_cast<std::uint32_t>(i);
  const int every = std::max(1, setup_.settings.reorder_every);
  if (steps_ % every == 0) {
    particles_.permute(order_);
    for (std::size_t i = 0; i < n; ++i) order_[i] = static_cast<std::uint32_t>(i);
    material_members_.assign(setup_.materials.size(), {});
    for (std::size_t i = 0; i < n; ++i) material_members_[material_[i]].push_back(static_cast<std::uint32_t>(i));
  }
  colour_blocks_.assign(8, {});
  for (std::size_t b = 0; b < blocks; ++b) {
    if (block_start_[b] == block_start_[b + 1]) continue;
    const std::size_t bk = b % bz_, bj = (b / bz_) % by_, bi = b / (std::size_t(bz_) * by_);
    colour_blocks_[(bi & 1) | ((bj & 1) << 1) | ((bk & 1) << 2)].push_back(static_cast<std::uint32_t>(b));
  }
}

// Spec 4.1 and 4.4: m_i = Σ w m_p, (m v)_i = Σ w m_p (v_p + C_p (x_i − x_p))
// (APIC), and the stress force. The force uses the MLS-MPM gradient
// ∇w_ip ≈ w_ip D⁻¹ (x_i − x_p), D⁻¹ = 4/Δx² for quadratic B-splines, so it
// folds into the affine term: (m v)_i += w (m_p v_p + A_p (x_i − x_p)) with
// A_p = m_p C_p − Δt V⁰_p D⁻¹ τ_p (Hu et al. 2018, Eq. 16–17).
// With heat (spec 4.1–4.3): M_i = Σ w m c, E_i = Σ w m c θ, V_i = Σ w V_p,
// W_i = Σ w m_w and the rates Q_i = Σ w S β (θ_amb − θ) − Σ V κ ∇θ_p · ∇w_ip,
// ΔW_i = −Σ w E(θ) s S_air + Σ V q_w · ∇w_ip, with the same MLS gradient
// (∇w_ip = w (4/Δx) o, o the node offset in cells).
template <bool kThermal>
void MpmSolver::p2g(Real dt) {
  parallel_for(
      grid_.size(),
      [&](std::size_t k) {
        grid_[k] = Node{0, {0, 0, 0}};
        if constexpr (kThermal) {
          heat_grid_[k] = HeatNode{};
          if (!implicit_mass_.empty()) implicit_mass_[k] = 0;
        }
      },
      1 << 14);
  const Vec3 origin = setup_.domain.min;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real d_inv = 4.0 * inv_dx_ * inv_dx_;
  for_each_by_colour(colour_blocks_, block_start_, order_, x_, origin, inv_dx_,
                     [&](std::uint32_t p, const Axis& ax, const Axis& ay, const Axis& az) {
                       const Real mp = m_[p];
                       // A Δx, so that A (x_i − x_p) = (A Δx) · offset-in-cells.
                       const Real s = -dt * volume0_[p] * d_inv;
                       const Vec3 td = tau_diag_[p], to = tau_off_[p];
                       Real a[3][3];  // a[col][row]
                       const Vec3 cc[3] = {c0_[p], c1_[p], c2_[p]};
                       for (int col = 0; col < 3; ++col)
                         for (int row = 0; row < 3; ++row) a[col][row] = mp * cc[col][row];
                       a[0][0] += s * td.x(), a[1][1] += s * td.y(), a[2][2] += s * td.z();
                       a[1][0] += s * to.x(), a[0][1] += s * to.x();
                       a[2][0] += s * to.y(), a[0][2] += s * to.y();
                       a[2][1] += s * to.z(), a[1][2] += s * to.z();
                       for (int col = 0; col < 3; ++col)
                         for (int row = 0; row < 3; ++row) a[col][row] *= dx_;
                       const Real mv[3] = {mp * v_[p].x(), mp * v_[p].y(), mp * v_[p].z()};
                       // Thermal channels: scalar parts (h) and offset slopes (hv, per axis).
                       Real h[6] = {0, 0, 0, 0, 0, 0}, hv[3][2] = {{0, 0}, {0, 0}, {0, 0}};
                       if constexpr (kThermal) {
                         h[0] = heat_capacity_[p];
                         h[1] = heat_capacity_[p] * temperature_[p];
                         h[2] = heat_src_[p];
                         h[3] = water_[p];
                         h[4] = j_[p] * volume0_[p];
                         h[5] = water_src_[p];
                         for (int d = 0; d < 3; ++d) hv[d][0] = heat_vec_[p][d], hv[d][1] = water_vec_[p][d];
                       }
                       for (int i = 0; i < 3; ++i) {
                         const Real ox = i - ax.frac;
                         Real ti[3];
                         for (int r = 0; r < 3; ++r) ti[r] = mv[r] + a[0][r] * ox;
                         const Real qi = h[2] + hv[0][0] * ox, wi = h[5] + hv[0][1] * ox;
                         for (int j = 0; j < 3; ++j) {
                           const Real oy = j - ay.frac, wij = ax.w[i] * ay.w[j];
                           Real tj[3];
                           for (int r = 0; r < 3; ++r) tj[r] = ti[r] + a[1][r] * oy;
                           const std::size_t row_index =
                               std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base;
                           Node* row = &grid_[row_index];
                           for (int kk = 0; kk < 3; ++kk) {
                             const Real oz = kk - az.frac, w = wij * az.w[kk];
                             Node& node = row[kk];
                             node.mass += w * mp;
                             for (int r = 0; r < 3; ++r) node.mv[r] += w * (tj[r] + a[2][r] * oz);
                           }
                           if constexpr (kThermal) {
                             const Real qj = qi + hv[1][0] * oy, wj = wi + hv[1][1] * oy;
                             HeatNode* hrow = &heat_grid_[row_index];
                             for (int kk = 0; kk < 3; ++kk) {
                               const Real oz = kk - az.frac, w = wij * az.w[kk];
                               Real* f = hrow[kk].f;
                               f[0] += w * h[0];
                               f[1] += w * h[1];
                               f[2] += w * (qj + hv[2][0] * oz);
                               f[3] += w * h[3];
                               f[4] += w * h[4];
                               f[5] += w * (wj + hv[2][1] * oz);
                             }
                           }
                         }
                       }
                     });
}

void MpmSolver::phase_p2g(Real dt) {
  ScopedPhase t(timers_, t_p2g_);
  if (thermal()) {
    p2g<true>(dt);
    // What the boundary terms put in this step (spec 4.2, 4.3 bookkeeping).
    const Real dtb = dt * setup_.settings.bake_time_scale;
    // (implicit heat books the energy its solve puts in)
    if (setup_.settings.heat == HeatMethod::explicit_)
      budget_.heat_in += dtb * deterministic_sum(x_.size(), [&](std::size_t i) { return heat_src_[i]; });
    budget_.evaporated -= dtb * deterministic_sum(x_.size(), [&](std::size_t i) { return water_src_[i]; });
  } else {
    p2g<false>(dt);
  }
}

// Spec 4.4: v_i = (m v)_i / m_i + Δt g, then the collider conditions.
// With heat (spec 4.2, 4.3, 4.6): θ_i = E_i / M_i advanced by the explicit
// rate, Δθ_i kept for the FLIP transfer; the boundary area of the node
// a_i = Δx³ |∇φ|, φ = V_i / Δx³ by central differences (Σ a_i is the surface
// area for any smooth profile of φ), exchanging with a hot collider within
// 3 Δx of the node through the part of the area vector Δx³ ∇φ that faces
// it, and with the air through the rest; water: the ratio r_i = Δt ΔW_i / W_i,
// never below −1 (water is never negative; what was asked beyond that is
// counted as clamped), and the saturation s_i for the next flux.
void MpmSolver::phase_grid(Real dt) {
  ScopedPhase t(timers_, t_grid_);
  const Vec3 origin = setup_.domain.min;
  const Vec3 g = setup_.gravity;
  // The domain walls sit two cells inside the grid so no stencil leaves it.
  const ColliderGeometry walls =
      InsideBoxCollider{{setup_.domain.min + Vec3::Constant(2 * dx_), setup_.domain.max - Vec3::Constant(2 * dx_)}};
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  // Collider poses at the end of the step, where the nodes' new velocities take the material.
  collider_poses_.resize(setup_.colliders.size());
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci)
    collider_poses_[ci] = setup_.colliders[ci].motion.at(time_ + dt);
  const bool heat = thermal();
  const Settings& st = setup_.settings;
  const Real dtb = dt * st.bake_time_scale, bake_t = (time_ + dt) * st.bake_time_scale;
  const Real air_t = setup_.air_temperature(bake_t), air_beta = setup_.heat_transfer_coefficient;
  std::vector<Real>& collider_t = collider_temperatures_;
  collider_t.assign(setup_.colliders.size(), 0);
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci)
    if (setup_.colliders[ci].collider.temperature)
      collider_t[ci] = (*setup_.colliders[ci].collider.temperature)(bake_t);
  const Real inv_rho_w = 1.0 / Moisture{}.water_density;
  const Real clamped = deterministic_reduce(
      grid_.size(), Real(0),
      [&](std::size_t kb, std::size_t ke) {
        Real clamp_sum = 0;
        for (std::size_t k = kb; k < ke; ++k) {
          Node& node = grid_[k];
          if (node.mass <= 0) continue;
          Vec3 v = Vec3(node.mv[0], node.mv[1], node.mv[2]) / node.mass + dt * g;
          const Vec3 xi = origin + dx_ * Vec3(Real(k / syz), Real((k / nz) % ny_), Real(k % nz));
          // Area vector Δx³ ∇φ (into the material) by central differences of V over 2Δx
          // The part
          // facing each hot collider within 3 Δx exchanges with it, the rest with the air
          // (∇φ reaches 2 Δx into the material; particles rest up to a cell off a wall).
          // Colliders without a temperature insulate the area facing them.
          Real* f = heat ? heat_grid_[k].f : nullptr;
          // (Nodes on the grid's outer layer have no neighbours to difference: no area there.)
          const std::size_t ki = k / syz, kj = (k / nz) % ny_, kk = k % nz;
          const bool inner = ki > 0 && kj > 0 && kk > 0 && ki + 1 < std::size_t(nx_) && kj + 1 < std::size_t(ny_) &&
                             kk + 1 < std::size_t(nz_);
          const bool exchange = heat && inner && f[0] > 0 && f[4] > 0;
          Vec3 area = Vec3::Zero();
          if (exchange)
            area = (0.5 * inv_dx_) * Vec3(heat_grid_[k + syz].f[4] - heat_grid_[k - syz].f[4],
                                          heat_grid_[k + nz].f[4] - heat_grid_[k - nz].f[4],
                                          heat_grid_[k + 1].f[4] - heat_grid_[k - 1].f[4]);
          Real hot_k = 0, hot_kt = 0;  // Σ a_c β_c and Σ a_c β_c θ_c over the hot colliders
          bool near = false;
          for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci) {
            const GridCollider& c = setup_.colliders[ci];
            const RigidPose& pose = collider_poses_[ci];
            const WallContact w = signed_distance(c.collider.geometry, pose.to_rest(xi));
            near = near || w.distance < 2 * dx_;
            if (exchange && w.distance < 3 * dx_) {
              const Vec3 n = pose.rotation * w.normal;
              const Real facing = std::max(Real(0), area.dot(n));
              area -= facing * n;
              if (c.collider.temperature) {
                hot_k += facing * c.collider.heat_transfer_coefficient;
                hot_kt += facing * c.collider.heat_transfer_coefficient * collider_t[ci];
              }
            }
            if (w.distance > 0) continue;
            const Vec3 vc = pose.velocity_at(xi);
            Vec3 rel = v - vc;
            apply_contact(rel, pose.rotation * w.normal, c.contact, c.friction);
            v = rel + vc;
          }
          if (!near_collider_.empty()) near_collider_[k] = near;
          for_each_wall(walls, xi, 0.0, [&](const WallContact& w) {
            apply_contact(v, w.normal, Contact::separate, setup_.domain_friction);
          });
          node.mv[0] = v.x(), node.mv[1] = v.y(), node.mv[2] = v.z();
          if (!heat) continue;
          const Real volume = f[4];
          if (!exchange) {
            for (int q = 0; q < 8; ++q) f[q] = q == 4 ? volume : 0;
            continue;
          }
          const Real air_area = area.norm();
          const Real inv_v = 1.0 / volume;
          if (!implicit_mass_.empty()) implicit_mass_[k] = f[0];
          const Real theta = f[1] / f[0], dtheta = dtb * f[2] / f[0];
          Real ratio = 0, sat = 0;
          if (f[3] > 0) {
            ratio = dtb * f[5] / f[3];
            if (ratio < -1) clamp_sum += (-1 - ratio) * f[3], ratio = -1;
            sat = (1 + ratio) * f[3] * inv_rho_w / volume;
          }
          f[0] = dtheta;
          f[1] = theta + dtheta;
          f[2] = (hot_k + air_area * air_beta) * inv_v;
          f[3] = (hot_kt + air_area * air_beta * air_t) * inv_v;
          f[5] = ratio;
          f[6] = sat;
          f[7] = air_area * inv_v;
        }
        return clamp_sum;
      },
      [](Real a, Real b) { return a + b; });
  if (heat) {
    budget_.clamped += clamped;
    budget_.evaporated -= clamped;
  }
}

// Spec 4.5: v_p = Σ w v_i, C_p = D⁻¹ Σ w v_i (x_i − x_p)ᵀ (D = Δx²/4 for
// quadratic B-splines); C_p is also the MLS velocity gradient, so the trial
// F = (I + Δt C_p) F; x += Δt v_p.
// With heat: θ_p += Σ w Δθ_i (FLIP), ∇θ_p = D⁻¹ Σ w θ_i (x_i − x_p) and
// ∇s_p likewise for the next step's fluxes, m_w ← m_w (1 + Σ w r_i)
// (spec 4.2), and the particle's share of the boundary: S β = V_p Σ w k_i.
template <bool kThermal>
void MpmSolver::g2p(Real dt) {
  const Vec3 origin = setup_.domain.min;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real d_inv = 4.0 * inv_dx_;  // D⁻¹ (x_i − x_p) with offsets in cells: 4/Δx² · Δx
  parallel_for(
      x_.size(),
      [&](std::size_t p) {
        const Vec3 g = (x_[p] - origin) * inv_dx_;
        const Axis ax = axis_weights(g.x()), ay = axis_weights(g.y()), az = axis_weights(g.z());
        Real v[3] = {0, 0, 0};
        Real b[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};  // b[col][row] = Σ w v_row offset_col
        // Thermal gathers: Σ w of {Δθ, k, kθ, r, k_air} and Σ w o of {θ_new, s}.
        Real hs[5] = {0, 0, 0, 0, 0}, hg[3][2] = {{0, 0}, {0, 0}, {0, 0}};
        for (int i = 0; i < 3; ++i) {
          Real vi[3] = {0, 0, 0}, bi[2][3] = {{0, 0, 0}, {0, 0, 0}};  // Σ over j, k at this i
          Real hsi[5] = {0, 0, 0, 0, 0}, hgi[3][2] = {{0, 0}, {0, 0}, {0, 0}};
          for (int j = 0; j < 3; ++j) {
            const Real oy = j - ay.frac;
            const std::size_t row_index = std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base;
            const Node* row = &grid_[row_index];
            Real vj[3] = {0, 0, 0}, bz[3] = {0, 0, 0};
            for (int kk = 0; kk < 3; ++kk) {
              const Real w = az.w[kk], oz = kk - az.frac;
              for (int r = 0; r < 3; ++r) {
                const Real wv = w * row[kk].mv[r];
                vj[r] += wv;
                bz[r] += wv * oz;
              }
            }
            const Real wy = ay.w[j];
            for (int r = 0; r < 3; ++r) {
              vi[r] += wy * vj[r];
              bi[0][r] += wy * vj[r] * oy;
              bi[1][r] += wy * bz[r];
            }
            if constexpr (kThermal) {
              const HeatNode* hrow = &heat_grid_[row_index];
              Real sj[5] = {0, 0, 0, 0, 0}, tj[2] = {0, 0}, tz[2] = {0, 0};
              for (int kk = 0; kk < 3; ++kk) {
                const Real w = az.w[kk], oz = kk - az.frac;
                const Real* f = hrow[kk].f;
                sj[0] += w * f[0], sj[1] += w * f[2], sj[2] += w * f[3], sj[3] += w * f[5], sj[4] += w * f[7];
                tj[0] += w * f[1], tj[1] += w * f[6];
                tz[0] += w * f[1] * oz, tz[1] += w * f[6] * oz;
              }
              for (int q = 0; q < 5; ++q) hsi[q] += wy * sj[q];
              for (int q = 0; q < 2; ++q) {
                hgi[0][q] += wy * tj[q];  // carried to x below
                hgi[1][q] += wy * tj[q] * oy;
                hgi[2][q] += wy * tz[q];
              }
            }
          }
          const Real wx = ax.w[i], ox = i - ax.frac;
          for (int r = 0; r < 3; ++r) {
            v[r] += wx * vi[r];
            b[0][r] += wx * vi[r] * ox;
            b[1][r] += wx * bi[0][r];
            b[2][r] += wx * bi[1][r];
          }
          if constexpr (kThermal) {
            for (int q = 0; q < 5; ++q) hs[q] += wx * hsi[q];
            for (int q = 0; q < 2; ++q) {
              hg[0][q] += wx * hgi[0][q] * ox;
              hg[1][q] += wx * hgi[1][q];
              hg[2][q] += wx * hgi[2][q];
            }
          }
        }
        const Vec3 vp(v[0], v[1], v[2]);
        Mat3 c;
        for (int col = 0; col < 3; ++col)
          for (int r = 0; r < 3; ++r) c(r, col) = d_inv * b[col][r];
        v_[p] = vp;
        c0_[p] = c.col(0), c1_[p] = c.col(1), c2_[p] = c.col(2);
        const Mat3 df = Mat3::Identity() + dt * c;
        set_deformation_gradient(p, df * deformation_gradient(p));
        j_[p] *= df.determinant();
        x_[p] += dt * vp;
        if (!near_collider_.empty()) {
          // The node nearest the particle's old position (it moves less than a cell).
          const std::size_t nearest =
              std::size_t(g.x() + 0.5) * syz + std::size_t(g.y() + 0.5) * nz + std::size_t(g.z() + 0.5);
          if (near_collider_[nearest]) push_out_of_colliders(p);
        }
        if constexpr (kThermal) {
          const Real volume = j_[p] * volume0_[p];
          // FLIP: θ_p += Σ w Δθ_i (spec 4.3), kept within the coldest and hottest
          // temperatures in the scene (particles, air, colliders) before the step:
          // where the material was cut (the lava cake's knife) FLIP increments took
          // particles to 6 °C in a 20–25 °C room.
          temperature_[p] = std::clamp(temperature_[p] + hs[0], flip_bounds_[0], flip_bounds_[1]);
          exchange_[p] = volume * hs[1];
          exchange_t_[p] = volume * hs[2];
          water_[p] *= 1 + hs[3];
          air_area_[p] = volume * hs[4];
          grad_theta_[p] = d_inv * Vec3(hg[0][0], hg[1][0], hg[2][0]);
          grad_s_[p] = d_inv * Vec3(hg[0][1], hg[1][1], hg[2][1]);
        }
      },
      1024);
}

// Grid contact alone lets material seep through a collider only one or two
// cells thick (nodes inside it are sparse; the pancake's receiving pan let
// 5.8% of the batter into or through its floor). A particle that ends a step inside a collider is put
// back on its surface, and its velocity relative to the collider gets the
// same contact condition as the grid nodes (docs/physics.md). Sticky
// colliders are left out: grips hold the material that lies inside them.
void MpmSolver::push_out_of_colliders(std::size_t p) {
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci) {
    const GridCollider& c = setup_.colliders[ci];
    if (c.contact == Contact::sticky) continue;  // grips hold material inside them
    const RigidPose& pose = collider_poses_[ci];
    const WallContact w = signed_distance(c.collider.geometry, pose.to_rest(x_[p]));
    if (w.distance >= 0) continue;
    const Vec3 n = pose.rotation * w.normal;
    x_[p] -= w.distance * n;
    const Vec3 vc = pose.velocity_at(x_[p]);
    Vec3 rel = v_[p] - vc;
    apply_contact(rel, n, c.contact, c.friction);
    v_[p] = rel + vc;
  }
}

void MpmSolver::phase_g2p(Real dt) {
  ScopedPhase t(timers_, t_g2p_);
  if (!thermal()) return g2p<false>(dt);
  // The hottest and coldest temperatures a particle may take this step.
  const Real inf = std::numeric_limits<Real>::infinity();
  Real lo = deterministic_reduce(
      x_.size(), inf,
      [&](std::size_t b, std::size_t e) { return *std::min_element(&temperature_[b], &temperature_[b] + (e - b)); },
      [](Real a, Real c) { return std::min(a, c); });
  Real hi = deterministic_reduce(
      x_.size(), -inf,
      [&](std::size_t b, std::size_t e) { return *std::max_element(&temperature_[b], &temperature_[b] + (e - b)); },
      [](Real a, Real c) { return std::max(a, c); });
  const Real scale = setup_.settings.bake_time_scale;
  for (const Real air : {setup_.air_temperature(time_ * scale), setup_.air_temperature((time_ + dt) * scale)})
    lo = std::min(lo, air), hi = std::max(hi, air);
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci)
    if (setup_.colliders[ci].collider.temperature)
      lo = std::min(lo, collider_temperatures_[ci]), hi = std::max(hi, collider_temperatures_[ci]);
  flip_bounds_ = {lo, hi};
  g2p<true>(dt);
}

// Spec 3.1–3.4: per material group, the gelatinization flag and the
// temperature-dependent τ_y(θ), η(θ); CO2 generation (3.3); the return mapping
// of the plastic law on the trial F^E; the Kirchhoff stress
// τ = τ_E − J (c λ (θ − θ_ref) + P_g + ξ (s − s₀)) I for the next P2G; the
// cooling by thermal expansion −c λ θ_K ∇·v / (ρ c) (spec 2, on the particle);
// and the heat and water terms of the next P2G (spec 4.2, 4.3).
void MpmSolver::phase_plasticity(Real dt) {
  ScopedPhase t(timers_, t_plastic_);
  const Settings& st = setup_.settings;
  const bool heat = thermal(), mixture = heat && !st.baseline;
  const Real dtb = dt * st.bake_time_scale;
  const Real flux_scale = 4.0 * inv_dx_;
  for (std::size_t mi = 0; mi < setup_.materials.size(); ++mi) {
    const Material& mat = setup_.materials[mi];
    const bool gas = mixture && mat.gas.active(), wet = mixture && mat.water.active();
    const Real expansion = mat.thermal_expansion * mat.lame.lambda;
    std::visit(
        [&](const auto& elastic) {
          std::visit(
              [&](const auto& plastic_law) {
                using P = std::decay_t<decltype(plastic_law)>;
                const std::vector<std::uint32_t>& members = material_members_[mi];
                parallel_for(
                    members.size(),
                    [&](std::size_t k) {
                      const std::size_t i = members[k];
                      const Real theta = temperature_[i];
                      Mat3 f = deformation_gradient(i);
                      Svd3 s = svd3(f);
                      if constexpr (!std::is_same_v<P, NoPlasticity>) {
                        P law = plastic_law;
                        if (heat && mat.setting) {
                          if (!gelatinized_[i] && theta >= mat.setting->set_temperature)
                            gelatinized_[i] = 1, jp_set_[i] = jp_[i];
                          const Real te = mat.setting->effective_temperature(theta, gelatinized_[i] != 0);
                          law.yield_stress = mat.setting->yield_stress(te);
                          law.viscosity = mat.setting->viscosity(te);
                        }
                        if constexpr (std::is_same_v<P, CamClay>) {
                          if (heat && st.baseline)
                            law.cohesion_slope = 0;  // baseline: no porosity in the yield surface
                          // τ_y is a Cauchy stress: in Kirchhoff stress the surface grows with the
                          // plastic dilation, so gas (whose Kirchhoff pressure n R θ / n_p barely
                          // falls as pores grow) expands a dough to a finite size.
                          law.yield_stress *= jp_[i];
                          // Brittle set crust (a departure, docs/physics.md): dilation after setting weakens it.
                          if (wet && mat.setting && gelatinized_[i]) {
                            const Real water_lost =
                                1 - water_[i] / (mat.water.saturation * mat.water.water_density * volume0_[i]);
                            law.yield_stress *= mat.setting->softening_factor(jp_[i], jp_set_[i], water_lost);
                          }
                        }
                        const Vec3 trial = s.sigma;
                        s = return_map(law, mat.lame, dt, jp_[i], s);
                        if (s.sigma != trial) {
                          f = compose(s);
                          set_deformation_gradient(i, f);
                        }
                        jp_[i] = j_[i] / s.sigma.prod();
                      }
                      Mat3 tau = kirchhoff_stress(elastic, f, s);
                      if (heat) {
                        const Real j = j_[i], volume = j * volume0_[i];
                        Real kirchhoff_pressure = 0;
                        if (expansion != 0) {
                          const Real theta_ref = setup_.bodies[body_[i]].temperature;
                          kirchhoff_pressure += j * expansion * (theta - theta_ref);
                          // Spec 2: ρ c Dθ/Dt = −c λ θ_K ∇·v (mechanical time; ∇·v = tr C).
                          const Real div_v = c0_[i].x() + c1_[i].y() + c2_[i].z();
                          temperature_[i] -=
                              dt * expansion * (theta + kZeroCelsius) * div_v * volume / heat_capacity_[i];
                        }
                        if (gas) {
                          co2_[i] = mat.gas.generated(co2_[i], dtb, theta, mat.density);
                          const Real jp_gas =
                              Leavening::kirchhoff_pressure(co2_[i], theta, gas_porosity(jp_[i], mat.initial_porosity));
                          gas_pressure_[i] = jp_gas / j;
                          kirchhoff_pressure += jp_gas;
                        }
                        Real sat = 0;
                        if (wet) {
                          sat = water_[i] / (mat.water.water_density * volume);
                          saturation_[i] = sat;
                          kirchhoff_pressure += j * mat.water.pressure(sat);
                          water_src_[i] = -mat.water.evaporation_flux(theta, sat) * air_area_[i];
                          water_vec_[i] = -(volume * mat.water.diffusion_coefficient(theta) * mat.water.water_density *
                                            flux_scale) *
                                          grad_s_[i];
                        }
                        tau.diagonal().array() -= kirchhoff_pressure;
                        heat_src_[i] = exchange_t_[i] - exchange_[i] * temperature_[i];
                        heat_vec_[i] = -(volume * mat.conductivity * flux_scale) * grad_theta_[i];
                      }
                      tau_diag_[i] = tau.diagonal();
                      tau_off_[i] = Vec3(tau(0, 1), tau(0, 2), tau(1, 2));
                    },
                    1024);
              },
              mat.plastic);
        },
        mat.elastic);
  }
}

// Spec 4.3 with γ = 1: (M/Δt + K + R) θ = (M/Δt) θⁿ + b, K the weak-form
// conduction Σ_p V κ ∇w_ip ∇w_jpᵀ, R the boundary exchange Σ_p S β w_ip w_jp
// (both symmetric positive semi-definite, so the matrix is SPD), solved
// matrix-free by Jacobi-preconditioned conjugate gradients over the nodes
// with heat capacity.
void MpmSolver::phase_heat_implicit(Real dt) {
  ScopedPhase t(timers_, t_heat_);
  const Real dtb = dt * setup_.settings.bake_time_scale;
  const std::size_t nodes = heat_grid_.size();
  const Vec3 origin = setup_.domain.min;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real gscale = 4.0 * inv_dx_;
  std::vector<Real>& mass = implicit_mass_;
  // Particle-to-node operator: y_i = Σ_p w (a_p + g_p · o), per colour so no two threads share a node.
  auto scatter = [&](std::vector<Real>& y, auto&& particle_terms) {
    for_each_by_colour(colour_blocks_, block_start_, order_, x_, origin, inv_dx_,
                       [&](std::uint32_t p, const Axis& ax, const Axis& ay, const Axis& az) {
                         Real a;
                         Vec3 gv;
                         Real diag_a, diag_g;
                         particle_terms(p, ax, ay, az, a, gv, diag_a, diag_g);
                         for (int i = 0; i < 3; ++i)
                           for (int j = 0; j < 3; ++j) {
                             const std::size_t row =
                                 std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base;
                             for (int kk = 0; kk < 3; ++kk) {
                               const Vec3 o(i - ax.frac, j - ay.frac, kk - az.frac);
                               const Real w = ax.w[i] * ay.w[j] * az.w[kk];
                               y[row + kk] += w * (a + gv.dot(o)) + w * w * (diag_a + diag_g * o.squaredNorm());
                             }
                           }
                       });
  };
  auto gather = [&](const std::vector<Real>& x, const Axis& ax, const Axis& ay, const Axis& az, Real& value,
                    Vec3& grad) {
    value = 0;
    grad.setZero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const std::size_t row = std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base;
        for (int kk = 0; kk < 3; ++kk) {
          const Real w = ax.w[i] * ay.w[j] * az.w[kk], xv = x[row + kk];
          value += w * xv;
          grad += (w * xv) * Vec3(i - ax.frac, j - ay.frac, kk - az.frac);
        }
      }
    grad *= gscale;
  };
  auto conductance = [&](std::uint32_t p) { return j_[p] * volume0_[p] * setup_.materials[material_[p]].conductivity; };
  // A x restricted to the active nodes.
  auto apply = [&](const std::vector<Real>& x, std::vector<Real>& y) {
    parallel_for(
        nodes, [&](std::size_t k) { y[k] = mass[k] > 0 ? mass[k] / dtb * x[k] : 0; }, 1 << 14);
    scatter(
        y, [&](std::uint32_t p, const Axis& ax, const Axis& ay, const Axis& az, Real& a, Vec3& gv, Real& da, Real& dg) {
          Real value;
          Vec3 grad;
          gather(x, ax, ay, az, value, grad);
          a = exchange_[p] * value;
          gv = conductance(p) * gscale * grad;
          da = dg = 0;
        });
  };
  // Node vectors of the solve, kept between steps (no per-step allocation once sized).
  ImplicitHeat& h = implicit_heat_;
  for (std::vector<Real>* v : {&h.rhs, &h.diag, &h.x, &h.r, &h.z, &h.d, &h.q}) v->assign(nodes, 0);
  std::vector<Real>&rhs = h.rhs, &diag = h.diag, &x = h.x, &r = h.r, &z = h.z, &d = h.d, &q = h.q;
  // Right-hand side and the Jacobi diagonal.
  scatter(rhs, [&](std::uint32_t p, const Axis&, const Axis&, const Axis&, Real& a, Vec3& gv, Real& da, Real& dg) {
    a = exchange_t_[p];
    gv.setZero();
    da = dg = 0;
  });
  scatter(diag, [&](std::uint32_t p, const Axis&, const Axis&, const Axis&, Real& a, Vec3& gv, Real& da, Real& dg) {
    a = 0;
    gv.setZero();
    da = exchange_[p];
    dg = conductance(p) * gscale * gscale;
  });
  parallel_for(
      nodes,
      [&](std::size_t k) {
        if (mass[k] > 0) {
          const Real theta_n = heat_grid_[k].f[1] - heat_grid_[k].f[0];
          rhs[k] += mass[k] / dtb * theta_n;
          diag[k] += mass[k] / dtb;
          x[k] = theta_n;
        } else {
          rhs[k] = 0, diag[k] = 1;
        }
      },
      1 << 14);
  auto dot = [&](const std::vector<Real>& a, const std::vector<Real>& b) {
    return deterministic_sum(nodes, [&](std::size_t k) { return a[k] * b[k]; });
  };
  apply(x, q);
  parallel_for(
      nodes,
      [&](std::size_t k) {
        r[k] = mass[k] > 0 ? rhs[k] - q[k] : 0;
        z[k] = r[k] / diag[k];
        d[k] = z[k];
      },
      1 << 14);
  Real rz = dot(r, z);
  const Real rhs_norm = std::sqrt(dot(rhs, rhs));
  for (int it = 0;
       it < setup_.settings.heat_max_iterations && std::sqrt(dot(r, r)) > setup_.settings.heat_tolerance * rhs_norm;
       ++it) {
    apply(d, q);
    const Real alpha = rz / dot(d, q);
    parallel_for(
        nodes,
        [&](std::size_t k) {
          x[k] += alpha * d[k];
          r[k] -= alpha * q[k];
          z[k] = r[k] / diag[k];
        },
        1 << 14);
    const Real rz_new = dot(r, z);
    const Real beta = rz_new / rz;
    rz = rz_new;
    parallel_for(
        nodes, [&](std::size_t k) { d[k] = z[k] + beta * d[k]; }, 1 << 14);
  }
  const Real energy = deterministic_reduce(
      nodes, Real(0),
      [&](std::size_t b, std::size_t e) {
        Real sum = 0;
        for (std::size_t k = b; k < e; ++k) {
          if (!(mass[k] > 0)) continue;
          Real* f = heat_grid_[k].f;
          const Real theta_n = f[1] - f[0];
          f[0] = x[k] - theta_n;
          f[1] = x[k];
          sum += mass[k] * f[0];
        }
        return sum;
      },
      [](Real a, Real b) { return a + b; });
  budget_.heat_in += energy;
}

void MpmSolver::check_state() {
  ScopedPhase t(timers_, t_check_);
  const std::size_t n = x_.size();
  const std::size_t bad = deterministic_reduce(
      n, n,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i)
          if (!x_[i].allFinite() || !v_[i].allFinite() || !(j_[i] > 0) || !setup_.domain.contains(x_[i]) ||
              !std::isfinite(temperature_[i]) || !(water_[i] >= 0))
            return i;
        return n;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  if (bad == n) return;
  const char* what = !x_[bad].allFinite()                ? "position"
                     : !v_[bad].allFinite()              ? "velocity"
                     : !(j_[bad] > 0)                    ? "J (volume ratio)"
                     : !setup_.domain.contains(x_[bad])  ? "position (left the domain)"
                     : !std::isfinite(temperature_[bad]) ? "temperature"
                                                         : "water mass";
  throw SimulationError(
      fmt::format("mpm step {} (t = {:.6g} s): particle {} has an invalid {}: x = ({:.4g}, {:.4g}, {:.4g}), v = "
                  "({:.4g}, {:.4g}, {:.4g}), J = {:.4g}, "
                  "temperature = {:.4g} degC, water = {:.4g} kg",
                  steps_ + 1, time_, id_[bad], what, x_[bad].x(), x_[bad].y(), x_[bad].z(), v_[bad].x(), v_[bad].y(),
                  v_[bad].z(), j_[bad], temperature_[bad], water_[bad]));
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
    if (best == x_.size()) {
      out.push_back(std::numeric_limits<Real>::quiet_NaN());
      continue;
    }
    if (q == "temperature")
      out.push_back(temperature_[best]);
    else if (q == "speed")
      out.push_back(v_[best].norm());
    else if (q == "velocity_x")
      out.push_back(v_[best].x());
    else if (q == "velocity_y")
      out.push_back(v_[best].y());
    else if (q == "velocity_z")
      out.push_back(v_[best].z());
    else if (q == "J")
      out.push_back(j_[best]);
    else if (q == "saturation")
      out.push_back(saturation_[best]);
    else if (q == "water_mass")
      out.push_back(water_[best]);
    else if (q == "co2")
      out.push_back(co2_[best]);
    else if (q == "gas_pressure")
      out.push_back(gas_pressure_[best]);
    else if (q == "plastic_J")
      out.push_back(jp_[best]);
    else
      throw InputError("probes", "unknown probe quantity '" + q + "' for the MPM solver");
  }
  return out;
}

std::vector<std::string> MpmSolver::probe_quantities() const {
  return {"temperature", "speed",      "velocity_x", "velocity_y", "velocity_z",  "J",
          "plastic_J",   "saturation", "water_mass", "co2",        "gas_pressure"};
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

// Per body: the coldest temperature (the core when heated from outside), the
// air-facing-area-weighted surface ("crust") temperature, water mass and the
// share lost, CO2 produced; and the totals of the budget.
std::vector<std::pair<std::string, Real>> MpmSolver::frame_quantities() const {
  std::vector<std::pair<std::string, Real>> out;
  if (!thermal()) return out;
  struct Acc {
    Real tmin = std::numeric_limits<Real>::infinity(), area = 0, area_t = 0, water = 0, co2 = 0;
  };
  const std::size_t nb = setup_.bodies.size();
  const std::vector<Acc> acc = deterministic_reduce(
      x_.size(), std::vector<Acc>(nb),
      [&](std::size_t b, std::size_t e) {
        std::vector<Acc> a(nb);
        for (std::size_t i = b; i < e; ++i) {
          Acc& s = a[body_[i]];
          s.tmin = std::min(s.tmin, temperature_[i]);
          s.area += air_area_[i];
          s.area_t += air_area_[i] * temperature_[i];
          s.water += water_[i];
          s.co2 += co2_[i] * volume0_[i];
        }
        return a;
      },
      [](std::vector<Acc> a, const std::vector<Acc>& b) {
        for (std::size_t k = 0; k < a.size(); ++k) {
          a[k].tmin = std::min(a[k].tmin, b[k].tmin);
          a[k].area += b[k].area;
          a[k].area_t += b[k].area_t;
          a[k].water += b[k].water;
          a[k].co2 += b[k].co2;
        }
        return a;
      });
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  for (std::size_t b = 0; b < nb; ++b) {
    const std::string& name = setup_.bodies[b].name;
    out.emplace_back("core_temperature:" + name, acc[b].tmin);
    out.emplace_back("crust_temperature:" + name, acc[b].area > 0 ? acc[b].area_t / acc[b].area : nan);
    out.emplace_back("water:" + name, acc[b].water);
    out.emplace_back("moisture_loss_percent:" + name,
                     initial_body_water_[b] > 0 ? 100.0 * (1 - acc[b].water / initial_body_water_[b]) : 0.0);
    out.emplace_back("co2_mol:" + name, acc[b].co2);
  }
  out.emplace_back("water_total", total_water());
  out.emplace_back("water_evaporated", budget_.evaporated);
  out.emplace_back("heat_in", budget_.heat_in);
  return out;
}

}  // namespace bakesim::mpm

namespace bakesim::mpm {

std::vector<std::pair<std::string, double>> MpmSolver::checkpoint_state() const {
  return {{"time", time_},
          {"steps", double(steps_)},
          {"evaporated", budget_.evaporated},
          {"clamped", budget_.clamped},
          {"heat_in", budget_.heat_in}};
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
  }
  // The particles come back in the order they had; the material groups index them.
  material_members_.assign(setup_.materials.size(), {});
  for (std::size_t i = 0; i < x_.size(); ++i) material_members_[material_[i]].push_back(static_cast<std::uint32_t>(i));
}

}  // namespace bakesim::mpm
