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

}  // namespace

MpmSolver::MpmSolver(Setup setup)
    : setup_(std::move(setup)),
      x_(particles_.add_vector("position", "m")),
      v_(particles_.add_vector("velocity", "m/s")),
      m_(particles_.add_scalar("mass", "kg")),
      volume0_(particles_.add_scalar("initial_volume", "m^3")),
      j_(particles_.add_scalar("J", "")),
      jp_(particles_.add_scalar("plastic_J", "")),
      temperature_(particles_.add_scalar("temperature", "degC")),
      f0_(particles_.add_vector("F_col0", "", false)),
      f1_(particles_.add_vector("F_col1", "", false)),
      f2_(particles_.add_vector("F_col2", "", false)),
      c0_(particles_.add_vector("C_col0", "1/s", false)),
      c1_(particles_.add_vector("C_col1", "1/s", false)),
      c2_(particles_.add_vector("C_col2", "1/s", false)),
      tau_diag_(particles_.add_vector("kirchhoff_normal", "Pa", false)),
      tau_off_(particles_.add_vector("kirchhoff_shear", "Pa", false)),
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
  if (nodes > 400'000'000) throw InputError("solver.mpm.cell_size", "the grid over the domain would have more than 4e8 nodes");
  grid_.assign(nodes, Node{0, {0, 0, 0}});
  bx_ = (nx_ + kBlock - 1) / kBlock;
  by_ = (ny_ + kBlock - 1) / kBlock;
  bz_ = (nz_ + kBlock - 1) / kBlock;
  t_sort_ = timers_.add("sort");
  t_p2g_ = timers_.add("p2g");
  t_grid_ = timers_.add("grid");
  t_g2p_ = timers_.add("g2p");
  t_plastic_ = timers_.add("constitutive");
  t_check_ = timers_.add("check");
  for (const Material& mat : setup_.materials)
    max_wave_speed_ = std::max(max_wave_speed_, std::sqrt((mat.lame.lambda + 2 * mat.lame.mu) / mat.density));
  build_particles();
  phase_sort();
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
      throw InputError("bodies[" + std::to_string(b) + "]", "no material points inside the domain (shape too small for the cell size, or outside)");
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
      temperature_[k] = body.temperature;
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

// Spec 4.7: Δt ≤ CFL Δx / max|v|, Δt ≤ CFL Δx / c with c = sqrt((λ+2μ)/ρ).
Real MpmSolver::max_stable_dt() {
  const Settings& s = setup_.settings;
  const Real vmax2 = deterministic_reduce(
      x_.size(), Real(0),
      [&](std::size_t b, std::size_t e) {
        Real m = 0;
        for (std::size_t i = b; i < e; ++i) m = std::max(m, v_[i].squaredNorm());
        return m;
      },
      [](Real a, Real b) { return std::max(a, b); });
  Real dt = s.max_dt;
  dt_bound_ = "max_dt";
  const Real cfl_dt = vmax2 > 0 ? s.cfl * dx_ / std::sqrt(vmax2) : std::numeric_limits<Real>::infinity();
  if (cfl_dt < dt) dt = cfl_dt, dt_bound_ = "cfl";
  const Real wave_dt = max_wave_speed_ > 0 ? s.cfl * dx_ / max_wave_speed_ : std::numeric_limits<Real>::infinity();
  if (wave_dt < dt) dt = wave_dt, dt_bound_ = "elastic_wave";
  return dt;
}

void MpmSolver::step(Real dt) {
  if (!(dt > 0)) throw SimulationError(fmt::format("mpm step {}: time step {} is not positive", steps_, dt));
  phase_sort();
  phase_p2g(dt);
  phase_grid(dt);
  phase_g2p(dt);
  phase_plasticity(dt);
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
  parallel_for(n, [&](std::size_t i) {
    const Vec3 g = (x_[i] - origin) * inv_dx_;
    int c[3];
    for (int d = 0; d < 3; ++d) c[d] = std::max(0, static_cast<int>(std::floor(g[d] - 0.5))) / kBlock;
    c[0] = std::min(c[0], bx_ - 1);
    c[1] = std::min(c[1], by_ - 1);
    c[2] = std::min(c[2], bz_ - 1);
    block_key_[i] = static_cast<std::uint32_t>((std::size_t(c[0]) * by_ + c[1]) * bz_ + c[2]);
  }, 4096);
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
void MpmSolver::phase_p2g(Real dt) {
  ScopedPhase t(timers_, t_p2g_);
  parallel_for(grid_.size(), [&](std::size_t k) { grid_[k] = Node{0, {0, 0, 0}}; }, 1 << 14);
  const Vec3 origin = setup_.domain.min;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real d_inv = 4.0 * inv_dx_ * inv_dx_;
  for (const auto& blocks : colour_blocks_) {
    parallel_for(blocks.size(), [&](std::size_t bi) {
      const std::uint32_t b = blocks[bi];
      for (std::uint32_t k = block_start_[b]; k < block_start_[b + 1]; ++k) {
        const std::uint32_t p = order_[k];
        const Vec3 g = (x_[p] - origin) * inv_dx_;
        const Axis ax = axis_weights(g.x()), ay = axis_weights(g.y()), az = axis_weights(g.z());
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
        for (int i = 0; i < 3; ++i) {
          const Real ox = i - ax.frac;
          Real ti[3];
          for (int r = 0; r < 3; ++r) ti[r] = mv[r] + a[0][r] * ox;
          for (int j = 0; j < 3; ++j) {
            const Real oy = j - ay.frac, wij = ax.w[i] * ay.w[j];
            Real tj[3];
            for (int r = 0; r < 3; ++r) tj[r] = ti[r] + a[1][r] * oy;
            Node* row = &grid_[std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base];
            for (int kk = 0; kk < 3; ++kk) {
              const Real oz = kk - az.frac, w = wij * az.w[kk];
              Node& node = row[kk];
              node.mass += w * mp;
              for (int r = 0; r < 3; ++r) node.mv[r] += w * (tj[r] + a[2][r] * oz);
            }
          }
        }
      }
    }, 1);
  }
}

// Spec 4.4: v_i = (m v)_i / m_i + Δt g, then the collider conditions.
void MpmSolver::phase_grid(Real dt) {
  ScopedPhase t(timers_, t_grid_);
  const Vec3 origin = setup_.domain.min;
  const Vec3 g = setup_.gravity;
  // The domain walls sit two cells inside the grid so no stencil leaves it.
  const ColliderGeometry walls = InsideBoxCollider{{setup_.domain.min + Vec3::Constant(2 * dx_), setup_.domain.max - Vec3::Constant(2 * dx_)}};
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  // Collider poses at the end of the step, where the nodes' new velocities take the material.
  collider_poses_.resize(setup_.colliders.size());
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci) collider_poses_[ci] = setup_.colliders[ci].motion.at(time_ + dt);
  parallel_for(grid_.size(), [&](std::size_t k) {
    Node& node = grid_[k];
    if (node.mass <= 0) return;
    Vec3 v = Vec3(node.mv[0], node.mv[1], node.mv[2]) / node.mass + dt * g;
    const Vec3 xi = origin + dx_ * Vec3(Real(k / syz), Real((k / nz) % ny_), Real(k % nz));
    for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci) {
      const GridCollider& c = setup_.colliders[ci];
      const RigidPose& pose = collider_poses_[ci];
      const WallContact w = signed_distance(c.collider.geometry, pose.to_rest(xi));
      if (w.distance > 0) continue;
      const Vec3 vc = pose.velocity_at(xi);
      Vec3 rel = v - vc;
      apply_contact(rel, pose.rotation * w.normal, c.contact, c.friction);
      v = rel + vc;
    }
    for_each_wall(walls, xi, 0.0, [&](const WallContact& w) { apply_contact(v, w.normal, Contact::separate, setup_.domain_friction); });
    node.mv[0] = v.x(), node.mv[1] = v.y(), node.mv[2] = v.z();
  }, 4096);
}

// Spec 4.5: v_p = Σ w v_i, C_p = D⁻¹ Σ w v_i (x_i − x_p)ᵀ (D = Δx²/4 for
// quadratic B-splines); C_p is also the MLS velocity gradient, so the trial
// F = (I + Δt C_p) F; x += Δt v_p.
void MpmSolver::phase_g2p(Real dt) {
  ScopedPhase t(timers_, t_g2p_);
  const Vec3 origin = setup_.domain.min;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real d_inv = 4.0 * inv_dx_;  // D⁻¹ (x_i − x_p) with offsets in cells: 4/Δx² · Δx
  parallel_for(x_.size(), [&](std::size_t p) {
    const Vec3 g = (x_[p] - origin) * inv_dx_;
    const Axis ax = axis_weights(g.x()), ay = axis_weights(g.y()), az = axis_weights(g.z());
    Real v[3] = {0, 0, 0};
    Real b[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};  // b[col][row] = Σ w v_row offset_col
    for (int i = 0; i < 3; ++i) {
      Real vi[3] = {0, 0, 0}, bi[2][3] = {{0, 0, 0}, {0, 0, 0}};  // Σ over j, k at this i
      for (int j = 0; j < 3; ++j) {
        const Real oy = j - ay.frac;
        const Node* row = &grid_[std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base];
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
      }
      const Real wx = ax.w[i], ox = i - ax.frac;
      for (int r = 0; r < 3; ++r) {
        v[r] += wx * vi[r];
        b[0][r] += wx * vi[r] * ox;
        b[1][r] += wx * bi[0][r];
        b[2][r] += wx * bi[1][r];
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
  }, 1024);
}

// Spec 3.1–3.2: the return mapping of each material's plastic law on the trial
// F^E, then the Kirchhoff stress for the next P2G. One dispatch per material.
void MpmSolver::phase_plasticity(Real dt) {
  ScopedPhase t(timers_, t_plastic_);
  for (std::size_t mi = 0; mi < setup_.materials.size(); ++mi) {
    const Material& mat = setup_.materials[mi];
    std::visit([&](const auto& elastic) {
      std::visit([&](const auto& plastic) {
        using P = std::decay_t<decltype(plastic)>;
        const std::vector<std::uint32_t>& members = material_members_[mi];
        parallel_for(members.size(), [&](std::size_t k) {
          const std::size_t i = members[k];
          Mat3 f = deformation_gradient(i);
          Svd3 s = svd3(f);
          if constexpr (!std::is_same_v<P, NoPlasticity>) {
            const Vec3 trial = s.sigma;
            s = return_map(plastic, mat.lame, dt, jp_[i], s);
            if (s.sigma != trial) {
              f = compose(s);
              set_deformation_gradient(i, f);
            }
            jp_[i] = j_[i] / s.sigma.prod();
          }
          const Mat3 tau = kirchhoff_stress(elastic, f, s);
          tau_diag_[i] = tau.diagonal();
          tau_off_[i] = Vec3(tau(0, 1), tau(0, 2), tau(1, 2));
        }, 1024);
      }, mat.plastic);
    }, mat.elastic);
  }
}

void MpmSolver::check_state() {
  ScopedPhase t(timers_, t_check_);
  const std::size_t n = x_.size();
  const std::size_t bad = deterministic_reduce(
      n, n,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i)
          if (!x_[i].allFinite() || !v_[i].allFinite() || !(j_[i] > 0) || !setup_.domain.contains(x_[i])) return i;
        return n;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  if (bad == n) return;
  const char* what = !x_[bad].allFinite() ? "position" : !v_[bad].allFinite() ? "velocity" : !(j_[bad] > 0) ? "J (volume ratio)" : "position (left the domain)";
  throw SimulationError(fmt::format("mpm step {} (t = {:.6g} s): particle {} has an invalid {}: x = ({:.4g}, {:.4g}, {:.4g}), v = ({:.4g}, {:.4g}, {:.4g}), J = {:.4g}",
                                    steps_, time_, id_[bad], what, x_[bad].x(), x_[bad].y(), x_[bad].z(), v_[bad].x(), v_[bad].y(), v_[bad].z(), j_[bad]));
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
    if (q == "temperature") out.push_back(temperature_[best]);
    else if (q == "speed") out.push_back(v_[best].norm());
    else if (q == "velocity_x") out.push_back(v_[best].x());
    else if (q == "velocity_y") out.push_back(v_[best].y());
    else if (q == "velocity_z") out.push_back(v_[best].z());
    else if (q == "J") out.push_back(j_[best]);
    else throw InputError("probes", "unknown probe quantity '" + q + "' for the MPM solver");
  }
  return out;
}

std::vector<std::string> MpmSolver::probe_quantities() const {
  return {"temperature", "speed", "velocity_x", "velocity_y", "velocity_z", "J"};
}

}  // namespace bakesim::mpm
