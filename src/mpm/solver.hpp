#pragma once
// Material Point Method (spec mpm-baking.md 4.1, 4.4, 4.5, 4.7): quadratic
// B-spline weights, APIC transfers (Jiang et al. 2015) with the moving-least-
// squares force and velocity gradient of MLS-MPM (Hu et al. 2018; departure
// noted in docs/physics.md), explicit grid update, finite-strain
// elastoplasticity on the particles, colliders on the grid.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/pcg.hpp"
#include "core/solver.hpp"
#include "core/parallel.hpp"
#include "core/timers.hpp"
#include "geometry/colliders.hpp"
#include "geometry/motion.hpp"
#include "geometry/periodic.hpp"
#include "mpm/grid.hpp"
#include "mpm/setup.hpp"
#include "physics/oven.hpp"

namespace bakesim::mpm {

// Running totals of the mixture (bake time, SI units).
struct MixtureBudget {
  Real evaporated = 0;  // kg that left through the boundary
  Real clamped = 0;     // kg the evaporation asked for beyond what a node held (not removed)
  Real heat_in = 0;     // J through the boundary (air and hot colliders)
  Real boiled = 0;      // kg boiled off at the boiling cap (moisture; part of evaporated)
  Real latent_out = 0;  // J the water took with it as it left (h_fg per kg evaporated and boiled)
};

// What is wrong with the setup's periodic axes for MPM (empty: nothing): each
// must span a whole number of cells, at least 4, and heat must not be implicit.
std::string periodic_problem(const Setup& setup);

class MpmSolver final : public Solver {
 public:
  explicit MpmSolver(Setup setup);

  std::string name() const override { return "mpm"; }
  Real max_stable_dt() override;
  const char* active_dt_bound() const override { return dt_bound_; }
  void step(Real dt) override;
  Real time() const override { return time_; }
  const ParticleSet& particles() const override { return particles_; }
  std::vector<std::pair<std::string, double>> checkpoint_state() const override;
  void restore_state(const std::vector<std::pair<std::string, double>>& state) override;
  std::string restored_state_problem() const override;
  ParticleSet& particles_for_restore() override { return particles_; }
  ParticleSet& mutable_particles() { return particles_; }
  const PhaseTimers& timers() const override { return timers_; }
  std::vector<Real> sample(const Vec3& x, const std::vector<std::string>& quantities) const override;
  bool heats() const override { return thermal(); }
  std::string summary() const override;
  std::vector<std::string> warnings() const override { return warnings_; }

  const Setup& setup() const { return setup_; }
  // Deformation gradient F^E of particle i (columns stored as three vectors).
  // 3×3 per-particle matrices are stored as three column attributes; inline,
  // for the transfers and the constitutive loop call them for every particle.
  Mat3 deformation_gradient(std::size_t i) const {
    Mat3 f;
    f.col(0) = f0_[i], f.col(1) = f1_[i], f.col(2) = f2_[i];
    return f;
  }
  void set_deformation_gradient(std::size_t i, const Mat3& f) {
    f0_[i] = f.col(0), f1_[i] = f.col(1), f2_[i] = f.col(2);
  }
  Mat3 affine(std::size_t i) const {
    Mat3 c;
    c.col(0) = c0_[i], c.col(1) = c1_[i], c.col(2) = c2_[i];
    return c;
  }
  void set_affine(std::size_t i, const Mat3& c) { c0_[i] = c.col(0), c1_[i] = c.col(1), c2_[i] = c.col(2); }
  std::size_t steps() const { return steps_; }
  Real total_mass() const;
  // Σ m_i over the grid after the last P2G (equals total_mass() by the
  // B-splines' partition of unity).
  Real grid_mass() const;
  Real cell_size() const { return dx_; }
  bool thermal() const { return setup_.settings.heat != HeatMethod::off; }
  Real bake_time() const { return setup_.oven.bake_time(time_); }
  const MixtureBudget& budget() const { return budget_; }
  Real total_water() const;
  Real total_co2() const;          // mol
  Real total_heat_energy() const;  // Σ m c θ, J (θ in °C)
  std::vector<std::pair<std::string, Real>> frame_quantities() const override;
  StepSolves last_solve_iterations() const override {
    if (implicit_heat_.iterations < 0) return {};
    return {SolveIterations{"implicit heat", implicit_heat_.iterations}};
  }

 private:
  void build_particles();
  void phase_sort();
  void group_by_material();
  void phase_p2g(Real dt);
  void phase_grid(Real dt);
  void phase_g2p(Real dt);
  void phase_plasticity(Real dt);
  void phase_heat_implicit(Real dt);
  void phase_browning(Real dt);
  void check_state();
  template <bool kThermal>
  void p2g(Real dt);
  template <bool kThermal>
  void g2p(Real dt);
  void push_out_of_colliders(std::size_t p);
  void push_inside_domain(std::size_t p);
  void mirror_sticky_planes();
  void add_wall_ghost_stress(Real dt);
  // A sticky plane at a pose, in world coordinates: signed distance n·(x − p)
  // (a plane's own signed distance, without a dispatch through the collider variant).
  struct WorldPlane {
    Vec3 normal, point;
    Real distance(const Vec3& x) const { return normal.dot(x - point); }
  };
  WorldPlane world_plane(std::size_t collider, const RigidPose& pose) const;
  // Periodic axes (domain.periodic): the nodes of the guard layers beyond a
  // periodic face are images of nodes inside (index G + ((g − G) mod N)).
  // After P2G their sums are added to the node they image and copied back
  // (so differences across the face see the whole), the grid update skips
  // them, and its results are copied to them for G2P.
  template <class T, class Add>
  void fold_periodic(std::vector<T>& nodes, Add&& add);
  template <class T>
  void copy_periodic(std::vector<T>& nodes);
  bool is_image_node(std::size_t k) const { return !image_node_.empty() && image_node_[k]; }
  // The node index inside the period that node index g along an axis of n
  // cells per period images (g itself when it lies inside).
  static int node_inside(int g, int n) { return kGuardCells + ((g - kGuardCells) % n + n) % n; }
  std::array<Real, 2> flip_bounds_{};  // coldest, hottest temperature before the step (G2P)

  Setup setup_;
  std::vector<SamplingFill> body_fill_;  // what each body's lattice holds of its shape
  std::vector<std::string> warnings_;
  ParticleSet particles_;
  PhaseTimers timers_;
  std::vector<Vec3>& x_;
  std::vector<Vec3>& v_;
  std::vector<Real>& m_;
  std::vector<Real>& volume0_;
  std::vector<Real>& j_;
  std::vector<Real>& jp_;
  std::vector<Real>& jp_set_;  // J^P when the particle set (gelatinized)
  std::vector<Real>& temperature_;
  std::vector<Real>& peak_temperature_;     // highest °C reached (irreversible setting)
  std::vector<Real>& browning_;             // browning index B = ΔE/ΔE∞
  std::vector<Real>& surface_temperature_;  // the face's temperature where the point meets the air, else θ
  std::vector<Vec3>& f0_;
  std::vector<Vec3>& f1_;
  std::vector<Vec3>& f2_;
  std::vector<Vec3>& c0_;
  std::vector<Vec3>& c1_;
  std::vector<Vec3>& c2_;
  std::vector<Vec3>& tau_diag_;  // Kirchhoff τ for the next P2G: τ_xx, τ_yy, τ_zz
  std::vector<Vec3>& tau_off_;   // τ_xy, τ_xz, τ_yz
  // Thermomechanics: state, then the per-step transfer terms (hidden).
  std::vector<Real>& heat_capacity_;  // m c, J/K
  std::vector<Real>& water_;          // m_w, kg
  std::vector<Real>& saturation_;     // s
  std::vector<Real>& co2_;            // n_g, mol per m³ of initial volume
  std::vector<Real>& gas_pressure_;   // P_g, Pa
  std::vector<std::int32_t>& gelatinized_;
  std::vector<Vec3>& grad_theta_;  // ∇θ from the grid, K/m
  std::vector<Vec3>& grad_s_;      // ∇s from the grid, 1/m
  std::vector<Real>& exchange_;    // Σ S β over the particle's boundary share, W/K
  std::vector<Real>& exchange_t_;  // Σ S β θ_amb, W
  std::vector<Real>& air_area_;    // area facing the air (evaporation), m²
  std::vector<Real>& air_depth_;   // distance to the centroid of that area (the face), m
  std::vector<Real> face_depth_;   // G2P to browning: depth below the face (the fill's level 1/2), m
  std::vector<Real>& heat_src_;    // P2G heat terms: scalar S β (θ_amb − θ), W
  std::vector<Vec3>& heat_vec_;    //   and −V κ ∇θ · 4/Δx, W
  std::vector<Real>& water_src_;   // P2G water terms: −evaporation, kg/s
  std::vector<Vec3>& water_vec_;   //   and V q_w · 4/Δx, kg/s
  // Moisture (physics/water.hpp): the dry-basis moisture and the pore vapour
  // density in equilibrium with it, then the vapour's transfer terms (hidden).
  std::vector<Real>& moisture_;        // X, kg water / kg dry solid
  std::vector<Real>& vapour_density_;  // ρ_v, kg/m³ of pore gas
  std::vector<Vec3>& grad_vapour_;     // ∇ρ_v from the grid, kg/m⁴
  std::vector<Real>& vapour_src_;      // −h_m (ρ_v − ρ_v,air) S_air, kg/s
  std::vector<Vec3>& vapour_vec_;      // V q_v · 4/Δx, kg/s
  std::vector<Real>& cell_k_;          // moisture's change of κ: heat pipe + drying, W/(m K)
  // κ of point p: its material's with moisture's change (heat pipe, drying), W/(m K).
  Real point_conductivity(std::size_t p) const { return setup_.materials[material_[p]].conductivity + cell_k_[p]; }
  std::vector<std::int32_t>& material_;
  std::vector<std::int32_t>& body_;
  std::vector<std::int32_t>& id_;

  // Dense node grid over the domain grown by kGuardCells on every side (nodes at
  // grid_origin_ + k Δx, grid_origin_ = domain.min − kGuardCells Δx): the walls
  // lie on the domain faces and a point a cell outside still has its stencil.
  static constexpr int kGuardCells = 2;
  Vec3 grid_origin_ = Vec3::Zero();
  Real dx_ = 0, inv_dx_ = 0;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<GridNode> grid_;
  // With heat: what P2G sums on each node, and what the grid update leaves for
  // G2P and the implicit solve (grid.hpp).
  std::vector<HeatSums> heat_sums_;
  std::vector<HeatState> heat_state_;
  BlockOrder blocks_;                       // particles by grid block, blocks coloured for race-free P2G
  Periodicity periodicity_;                 // periodic axes of the domain (geometry/periodic.hpp)
  std::array<int, 3> period_cells_{};       // cells per period along each periodic axis (0: not periodic)
  std::vector<std::uint8_t> image_node_;    // per node: an image of a node inside (periodic axes only)
  std::vector<Vec4> mirror_velocity_;       // grid phase scratch: flow velocity and 1, or 0 (mirror_sticky_planes)
  std::vector<std::size_t> sticky_planes_;  // the colliders that are sticky planes (mirror_sticky_planes, ghosts)
  std::vector<WorldPlane> sticky_world_;    // grid phase scratch: those planes at this step's end pose
  std::vector<Real> ghost_distance_;        // P2G scratch: distance to a sticky plane, or 0 (add_wall_ghost_stress)
  // Particle indices of each material, rebuilt when particle memory is
  // reordered: the constitutive phase dispatches once per material group.
  std::vector<std::vector<std::uint32_t>> material_members_;
  std::vector<RigidPose> collider_poses_;  // per collider, refreshed each grid phase
  // Per node, set by the grid phase: a collider surface is within 2 Δx, so the
  // particles nearest this node are checked against the colliders after they move.
  std::vector<std::uint8_t> near_collider_;

  std::size_t t_sort_, t_p2g_, t_grid_, t_g2p_, t_plastic_, t_heat_, t_browning_, t_check_;
  MixtureBudget budget_;
  std::vector<Real> implicit_mass_;  // M_i for the implicit heat solve
  struct ImplicitHeat {
    std::vector<Real> rhs, diag, x;
    PcgScratch<Real> pcg;
    int iterations = -1;  // the last step's; -1 before the first implicit solve
  } implicit_heat_;
  ColliderTemperatures collider_temperatures_;  // per collider at the current bake time
  Real time_ = 0;
  std::size_t steps_ = 0;
  const char* dt_bound_ = "max_dt";
  Real max_wave_speed_ = 0;
  bool moist_ = false;                           // a material carries moisture (physics/water.hpp)
  std::vector<Real> latent_step_, boiled_step_;  // per particle in one G2P: latent heat given up (J), water boiled (kg)
};

template <class T, class Add>
inline void MpmSolver::fold_periodic(std::vector<T>& nodes, Add&& add) {
  const int dims[3] = {nx_, ny_, nz_};
  const std::size_t stride[3] = {std::size_t(ny_) * nz_, std::size_t(nz_), 1};
  for (int axis = 0; axis < 3; ++axis) {
    const int n = period_cells_[std::size_t(axis)];
    if (n == 0) continue;
    // Every node whose index along this axis lies in a guard layer goes to its image inside.
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const int g = int((k / stride[axis]) % std::size_t(dims[axis]));
      const int inside = node_inside(g, n);
      if (inside == g) continue;
      const std::ptrdiff_t shift = std::ptrdiff_t(inside - g) * std::ptrdiff_t(stride[axis]);
      add(nodes[std::size_t(std::ptrdiff_t(k) + shift)], nodes[k]);
      nodes[k] = T{};
    }
  }
}

template <class T>
inline void MpmSolver::copy_periodic(std::vector<T>& nodes) {
  const int dims[3] = {nx_, ny_, nz_};
  const std::size_t stride[3] = {std::size_t(ny_) * nz_, std::size_t(nz_), 1};
  // In the reverse order of the fold: corner images read edges already filled.
  for (int axis = 2; axis >= 0; --axis) {
    const int n = period_cells_[std::size_t(axis)];
    if (n == 0) continue;
    parallel_for(nodes.size(), [&](std::size_t k) {
      const int g = int((k / stride[axis]) % std::size_t(dims[axis]));
      const int inside = node_inside(g, n);
      if (inside == g) return;
      const std::ptrdiff_t shift = std::ptrdiff_t(inside - g) * std::ptrdiff_t(stride[axis]);
      nodes[k] = nodes[std::size_t(std::ptrdiff_t(k) + shift)];
    });
  }
}

}  // namespace bakesim::mpm
