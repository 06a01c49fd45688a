#pragma once
// Weakly compressible SPH (thesis Chapter 3.1, 3.2, 3.4).
// One step, as named (and timed) phases:
//   kick      v += ½dt a                                  (leap-frog, 3.4)
//   drift     x += dt v
//   collide   walls and meshes                            (Eq 3.31–3.33)
//   sort      particles by cell (memory order)
//   neighbours neighbour lists                             (3.1.2)
//   density   ρ = Σ m W (+ wall half-space)               (Eq 3.13)
//   surface   colour gradient, surface particles, areas   (3.1.8, Eq 3.28, 3.43)
//   stress    Maxwell viscoelastic stress update           (Eq 3.20–3.27)
//   pressure  Tait, bubbles, risen Tait                    (Eq 3.17, 3.48–3.52)
//   forces    pressure, stress divergence, viscosity,
//             artificial viscosity, surface tension,
//             gravity                                      (Eq 3.18, 2.18, 3.19, 3.35–3.41, 3.28–3.30)
//   kick      v += ½dt a
//   xsph      velocity correction                          (Eq 3.34)
//   viscosity implicit viscous velocity update (optional)  (Eq 3.19, backward Euler)
//   heat      conduction and exchange with air/colliders   (Eq 3.42–3.46)
//   properties temperature-dependent μ, μ_e, λ, ε; rise
//             state of bubble particles                    (Eq 4.1–4.4, 3.52)
//   smoothing per-particle h for the next step (optional)  (Eq 3.54–3.56)
// With the divergence-free pressure (DFSPH, Bender & Koschier 2017) the step is
//   kick      v += dt a (the forces without pressure)
//   density solve  pressure that brings the predicted density to rest
//   drift, collide, sort, neighbours, density, surface, stress as above
//   pressure  the solves' factors (no pressure force from the density)
//   divergence solve  pressure that makes Dρ/Dt vanish
//   forces    as above without pressure, for the next step
//   xsph, viscosity, heat, ... as above
// With adaptive smoothing every pair uses h_ij = (h_i + h_j)/2 (Eq 3.56).
#include <array>
#include <cassert>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/pcg.hpp"
#include "core/solver.hpp"
#include "geometry/colliders.hpp"
#include "geometry/open_space.hpp"
#include "physics/oven.hpp"
#include "sph/kernels.hpp"
#include "sph/neighbours.hpp"
#include "sph/setup.hpp"

namespace bakesim::sph {

class SphSolver final : public Solver {
 public:
  explicit SphSolver(Setup setup);

  std::string name() const override { return "sph"; }
  Real max_stable_dt() override;
  const char* active_dt_bound() const override { return dt_bound_; }
  // Every time-step bound of the current state with its value (s): max_dt,
  // cfl, elastic, viscosity, force, conduction, vapour_diffusion (a fixed
  // list of at most seven: the frame loop asks every step).
  struct StepBound {
    const char* name;
    Real dt;
    bool heat;  // a bound of the heat phases (conduction, vapour diffusion): their own step with heat_own_step
  };
  struct StepBounds {
    std::array<StepBound, 8> list{};
    std::size_t count = 0;
    void add(const char* name, Real dt, bool heat = false) {
      assert(count < list.size() && "time_step_bounds adds at most seven");
      list[count++] = {name, dt, heat};
    }
    const StepBound* begin() const { return list.data(); }
    const StepBound* end() const { return list.data() + count; }
  };
  StepBounds time_step_bounds() const;
  void step(Real dt) override;
  void synchronize() override;
  // Mechanical steps whose heat, water and browning are still to be taken (heat_own_step).
  int heat_pending_steps() const { return heat_pending_steps_; }
  // The most steps the heat may lag (Settings::heat_own_step).
  static constexpr int kMaxHeatEverySteps = 8;
  Real time() const override { return time_; }
  const ParticleSet& particles() const override { return particles_; }
  std::vector<std::pair<std::string, double>> checkpoint_state() const override;
  // stats.csv's heat_in: the heat in through the surface since the start, J (as MPM's).
  // With moisture also the water's: water_total, water_evaporated, latent_heat_out, water_boiled.
  std::vector<std::pair<std::string, Real>> frame_quantities() const override;
  void restore_state(const std::vector<std::pair<std::string, double>>& state) override;
  std::string restored_state_problem() const override;
  ParticleSet& particles_for_restore() override { return particles_; }
  const PhaseTimers& timers() const override { return timers_; }
  std::vector<Real> sample(const Vec3& x, const std::vector<std::string>& quantities) const override;
  std::string summary() const override;
  std::vector<std::string> warnings() const override { return warnings_; }

  const Setup& setup() const { return setup_; }
  Real support() const { return h_; }
  Real particle_mass(int material) const;
  const NeighbourLists& neighbours() const { return lists_; }
  // Neighbour searches so far (with a Verlet skin, fewer than the steps).
  long neighbour_searches() const { return searches_; }
  long steps() const { return steps_; }
  Real bake_time() const { return setup_.oven.bake_time(time_); }
  bool implicit_viscosity() const { return implicit_viscosity_; }
  bool implicit_elasticity() const { return implicit_elasticity_; }
  int last_viscosity_iterations() const { return viscosity_iterations_; }
  StepSolves last_solve_iterations() const override {
    StepSolves solves{};
    std::size_t k = 0;
    if (implicit_viscosity_) solves[k++] = {"implicit viscosity", viscosity_iterations_};
    if (divergence_free_) {
      solves[k++] = {"density solve", density_iterations_};
      solves[k++] = {"divergence solve", divergence_iterations_};
    }
    return solves;
  }
  bool divergence_free() const { return divergence_free_; }
  // The last step's pressure solves (divergence_free): iterations, and the mean error the density solve stopped at.
  int last_density_iterations() const { return density_iterations_; }
  int last_divergence_iterations() const { return divergence_iterations_; }
  Real last_density_error() const { return density_error_; }
  // Heat that entered through the surface (air and colliders) since the start, J.
  Real exchanged_heat() const { return exchanged_heat_; }
  // Viscoelastic stress of particle i (symmetric, Pa).
  Mat3 stress(std::size_t i) const;
  void set_stress(std::size_t i, const Mat3& s);
  // Velocity gradient L_ab = ∂v_a/∂x_b at particle i (Eq 3.27).
  Mat3 velocity_gradient(std::size_t i) const;
  // The same with the volumes m/ρ of this step given (the pressure phase's volume_), or nullptr.
  Mat3 velocity_gradient(std::size_t i, const Real* volume) const;
  // The same times C_iᵀ where `corrected` (the stress form's gradient, exact
  // for linear fields where a surface cuts the support; correction_ current).
  Mat3 velocity_gradient(std::size_t i, const Real* volume, bool corrected) const {
    const Mat3 l = velocity_gradient(i, volume);
    return corrected ? Mat3(l * correction_[i].transpose()) : l;
  }
  std::size_t body_particle_count(std::size_t body) const { return body_counts_.at(body); }

  // Recomputes neighbours, density, pressure and accelerations for the current
  // positions (done automatically; public for tests that edit particles).
  void refresh();
  ParticleSet& mutable_particles() { return particles_; }

 private:
  void seed_particles();
  void check_initial_overlaps() const;
  void phase_neighbours();
  // Whether some pair may have come within reach since the anchors (Verlet).
  bool moved_past_skin() const;
  void phase_density();
  // The colour gradient every step; the surface flags and exchange areas only
  // when `flags` (a step that takes the heat: nothing else reads them).
  void phase_surface(bool flags = true);
  // Whether this step takes the heat phases (heat_own_step), adding dt to what is pending.
  bool heat_due(Real dt);
  // Heat, water and browning over the pending time (in substeps within the thermal bound).
  void advance_heat();
  void phase_stress(Real dt);
  void phase_stress_increment(Real dt);  // implicit elasticity: w (R + μ_e D') of the solved velocities
  void plastic_return(Real dt);          // elastoviscoplastic materials: the Maxwell stress back towards τ_y
  void update_gradient_correction();
  void
  add_corrected_stress_divergence();  // phase forces, when corrected_maxwell()  // correction_ and pair_volume_gradient_ of the current positions
  // The Maxwell stress with the stress-form viscosity: the corrected velocity
  // gradient for its rate and its divergence as the adjoint of that gradient.
  bool corrected_maxwell() const { return elastic_ && setup_.settings.stress_viscosity; }
  void phase_pressure();
  void phase_forces();
  void compute_wall_drag();
  void phase_kick(Real kick);  // v += kick · a
  // Divergence-free pressure (phases/pressure_solve.cpp).
  void update_pressure_factors();  // 1/D_i and the walls' terms at the current positions
  void phase_density_solve(Real dt);
  void phase_divergence_solve(Real dt);
  // Jacobi iterations on κ: density (predicted density to rest) or divergence (Dρ/Dt to zero).
  // Adds its κ to kappa_total (the density solve's starts as the last step's).
  struct PressureSolve {
    int iterations = 0;
    Real error = 0;  // the mean error it stopped at
  };
  PressureSolve solve_pressure(Real dt, bool density, Real tolerance, std::vector<Real>& kappa_total);
  // Calls fn(j, ∇_i W_ij) for each neighbour j of particle i (this step's lists and kernel slopes).
  template <class Fn>
  void for_each_kernel_gradient(std::size_t i, Fn&& fn) const {
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pd = pair_dwr_.data() + i * lists_.stride();
    for (std::uint32_t k = 0; k < count; ++k) fn(nb[k], Vec3(Real(pd[k]) * pair_offset(i, nb[k])));
  }
  void apply_pressure(Real dt, const std::vector<Real>& kappa);  // v += dt a_i for κ
  static constexpr Real kRelaxation = 0.5;                       // Jacobi's ω (IISPH's, Ihmsen et al. 2014)
  void phase_drift(Real dt);
  void phase_collide();
  void phase_xsph(Real dt);
  void phase_viscosity(Real dt);
  void solve_stress_viscosity(Real dt, const std::vector<Real>& diag);  // phase_viscosity, stress form
  // The walls bodies rest on in this step's viscous solve (support_normal_, …, supported_).
  void find_wall_supports();
  void remove_supported_normal(std::size_t i, Vec3& value) const;  // the free directions of particle i
  template <bool Coupled, class Apply>
  void solve_supported(Apply& apply, const std::vector<Real>& diag, const Vec3& b_norm2, const char* what);
  void start_viscous_guess();         // v ← v* + the last solve's change (viscosity_start_ ← v*)
  void keep_viscous_change();         // viscous_change_ ← v − v*
  Vec3 build_viscosity_rhs(Real dt);  // the implicit viscosity's M v*; returns its |b|² per component
  // The viscosity the implicit solve uses: μ, plus the step's elastic viscosity when elasticity is implicit.
  const std::vector<Real>& viscosity_in_solve() const { return implicit_elasticity_ ? solve_viscosity_ : mu_; }
  // `weights_ready`: this step's corrected-Laplacian weights are computed (set once they are).
  void phase_heat(Real dt, bool& weights_ready);
  void update_laplacian_moments();  // laplacian_moment_ from this step's neighbours
  // The corrected Laplacian's factor for pair (i, j), 2/(a_i + a_j) (heat and water phases).
  void update_diffusion_weights();
  Real laplacian_correction(std::size_t i, std::size_t j) const {
    return 2 / (laplacian_moment_[i] + laplacian_moment_[j]);
  }
  void phase_browning(Real dt);
  // The profile from particle i to the face it turns to the oven (physics/heat.hpp).
  CrustFace crust_face(std::size_t i) const;
  // The area a surface particle turns to a collider over its area V |∇C| / S (heat phase).
  Real contact_area_scale(std::size_t i) const;
  void phase_water(Real dt);
  // The temperature curves only when `temperature_changed`; the rise state and yield-stress viscosity every step.
  void phase_properties(bool temperature_changed = true);
  void apparent_viscosity(int material);
  void phase_smoothing();
  void assign_bubbles();
  void check_finite();
  // Share of particle i's kernel beyond all analytic walls, 1 − Π(1 − f_k),
  // and its gradient (walls combined as independent events, exact for a
  // Gaussian kernel and close for the spline at box edges and corners).
  Real wall_share(const Vec3& x, Vec3* gradient) const;
  // Poses of the moving analytic colliders at `time` (the end of the step).
  void update_wall_poses(Real time);
  // Calls fn(contact, wall velocity) for each face of analytic collider c
  // within `range` of x, in world coordinates: a moving collider is queried
  // in its rest pose. Static colliders skip the transform (and report zero velocity).
  // x_i − x_j, the nearest image's along periodic axes.
  Vec3 pair_offset(std::size_t i, std::size_t j) const { return pair_offset_of(x_[i], x_[j]); }
  Vec3 pair_offset_of(const Vec3& a, const Vec3& b) const {
    const Vec3 d = a - b;
    return periodic_ ? periodicity_.nearest_image(d) : d;
  }
  // Calls fn(distance scaled to the reference support, h0/h_i, wall contact,
  // wall velocity) for each sticky analytic wall within particle i's support:
  // the no-slip walls' ghost sums (WallGhostSum) are tabulated at h0.
  template <class Fn>
  void for_each_no_slip_wall(std::size_t i, Fn&& fn) const {
    const Real scale = h_ / smoothing_[i];
    for (std::size_t c = 0; c < walls_.size(); ++c) {
      if (walls_[c].contact.mode != ContactMode::sticky) continue;
      for_each_wall_of(c, x_[i], smoothing_[i],
                       [&](const WallContact& w, const Vec3& v_wall) { fn(w.distance * scale, scale, w, v_wall); });
    }
  }
  template <class Fn>
  void for_each_wall_of(std::size_t c, const Vec3& x, Real range, Fn&& fn) const {
    const Collider& collider = walls_[c];
    if (!collider.motion.moves()) {
      for_each_wall(collider.geometry, x, range, [&](const WallContact& w) { fn(w, Vec3::Zero().eval()); });
      return;
    }
    const RigidPose& pose = wall_poses_[c];
    for_each_wall(collider.geometry, pose.to_rest(x), range, [&](const WallContact& w) {
      fn(WallContact{w.distance, pose.rotation * w.normal}, pose.velocity_at(x));
    });
  }

  Setup setup_;
  Real h_;
  Real contact_distance_;
  CubicSpline kernel_;
  Real lattice_sum_;             // Σ W over the sampling lattice (mass calibration, wall share)
  ViscosityLaplacian visc_lap_;  // Eq 3.8, calibrated on the lattice (viscosity_lattice_calibration)
  WallGhostSum wall_viscosity_;  // no-slip walls: their share of Eq 3.19 (kernels.hpp)
  WallGhostSum wall_gradient_;   // and of the velocity gradient, Eq 3.27
  WallKernelShare wall_share_;
  NeighbourSearch search_;
  NeighbourLists lists_;
  // Verlet lists (phase neighbours): the pairs within the support plus the
  // skin at the anchors, the positions of the last search.
  NeighbourLists candidates_;
  Real skin_ = 0;                  // m
  bool candidates_valid_ = false;  // false at the start and after a restore
  bool anchors_valid_ = false;     // false at the start: the first step searches
  bool anchors_moved_ = false;     // this step searched: new anchors (the open-space grid follows them)
  long searches_ = 0;
  // walls_[kDomainWall] is the domain's box; the scene's analytic colliders follow it.
  static constexpr std::size_t kDomainWall = 0;

  std::vector<Collider> walls_;        // analytic colliders incl. the domain box
  std::vector<Collider> meshes_;       // mesh colliders
  std::vector<RigidPose> wall_poses_;  // per analytic collider, at the end of the step (moving ones)
  std::vector<Real> tait_b_;           // per material
  std::vector<Real> mass_;             // per material
  std::vector<Real> conductivity_;     // per material, read per neighbour pair in the heat phase
  std::vector<Real> bubble_b_;         // per body: B of Eq 3.48
  bool implicit_viscosity_ = false;
  Real rest_cfl_step_ = 1;            // s: the CFL bound at rest, cfl ħ / c (XSPH's reference step, auto viscosity)
  bool elastic_ = false;              // some material has a Maxwell stress (μ_e not identically 0)
  bool surface_tension_ = false;      // some material has surface tension (reads the colour gradient every step)
  bool implicit_elasticity_ = false;  // its elastic increment is solved with the implicit viscosity
  bool heated_colliders_ = false;     // some collider carries a temperature
  bool follows_peak_ = false;         // some material reads its curves at the peak temperature
  bool adaptive_ = false;             // per-particle smoothing length (Eq 3.54–3.56)
  bool no_slip_walls_ = false;        // some analytic collider is sticky: walls add viscous stress
  Periodicity periodicity_;           // periodic axes of the domain (geometry/periodic.hpp)
  bool periodic_ = false;             // some axis is periodic
  Real colour_share_ = 1;             // V |∇C| / s² on a flat lattice face (kernels.hpp): exchange areas
  ColliderTemperatures wall_temperatures_, mesh_temperatures_;  // at this step's bake time (heat phase)
  int viscosity_iterations_ = 0;
  // Divergence-free pressure (phases/pressure_solve.cpp).
  bool divergence_free_ = false;
  int density_iterations_ = 0, divergence_iterations_ = 0;
  Real density_error_ = 0;
  std::vector<Real> pressure_factor_;     // 1/D_i, D_i = (S_i + b_i G_i)·(S_i + G_i) + m_i Σ m_j |∇W_ij|²
  std::vector<Vec3> wall_mass_gradient_;  // G_i = ρ0 ∇f_i, the walls' Σ_b m_b ∇W_ib (wall half-space)
  std::vector<Real> wall_mirror_;         // b_i = 1 + ρ_i²/ρ0²: the wall's pressure mirrored at the particle's
  std::vector<Real> kappa_;               // κ = p/ρ²: an iteration's error, then its change
  std::vector<Real> divergence_kappa_;    // the divergence solve's κ (from zero each step)
  Real exchanged_heat_ = 0.0;
  // Moisture (physics/water.hpp): on when a material carries water.
  bool moist_ = false;
  struct WaterBudget {
    Real evaporated = 0;  // kg that left (surface and boiled)
    Real boiled = 0;      // kg boiled off at the boiling cap
    Real clamped = 0;     // kg a particle was asked to give beyond what it held (not removed)
    Real latent_out = 0;  // J the water took with it
  } water_budget_;
  std::vector<Real>* water_ = nullptr;                                  // water_mass, kg (moisture only)
  std::vector<Real>* moisture_ = nullptr;                               // X, kg/kg dry
  std::vector<Real>* vapour_density_ = nullptr;                         // ρ_v, kg/m³
  std::vector<std::array<Real, 2>> water_coefficients_, water_change_;  // per step: (vapour, liquid)
  std::vector<std::array<Real, 3>> step_book_;                          // per step: latent J, boiled kg, clamped kg
  std::vector<Real> face_outside_, face_coefficient_;  // heat phase: what a surface particle faces (°C, W/(m² K))
  std::vector<Real> face_share_;  // heat phase: the share of its area facing the oven air (not a collider)
  std::vector<Real> particle_k_;  // heat phase with moisture: k + the closed-cell heat pipe, W/(m K)

  ParticleSet particles_;
  std::vector<Vec3>& x_;
  std::vector<Vec3>& v_;
  std::vector<Vec3>& a_;
  std::vector<Real>& rho_;
  std::vector<Real>& p_;
  std::vector<Real>& m_;
  std::vector<Real>& temperature_;
  std::vector<Real>& browning_;             // browning index B = ΔE/ΔE∞
  std::vector<Real>& surface_temperature_;  // the face's temperature where the particle meets the oven, else θ
  std::vector<Real>& mu_;
  std::vector<Real>& eps_;
  std::vector<Real>& elasticity_;        // μ_e
  std::vector<Real>& relaxation_;        // λ
  std::vector<Vec3>& stress_diag_;       // S_xx, S_yy, S_zz
  std::vector<Vec3>& stress_off_;        // S_xy, S_xz, S_yz
  std::vector<Real>& area_;              // exchange area of surface particles, m²
  std::vector<Real>& smoothing_;         // support radius h_i, m (h0 unless adaptive, Eq 3.54)
  std::vector<Real>& set_density_;       // ρ_f of Eq 3.52
  std::vector<Real>& set_temperature_;   // °C at which the rise ended
  std::vector<Real>& peak_temperature_;  // highest °C reached (irreversible setting)
  std::vector<std::int32_t>& surface_;
  std::vector<std::int32_t>& bubble_;
  std::vector<std::int32_t>& rise_state_;  // 0 before the rise, 1 rising (bubbles), 2 risen (Eq 3.52)
  std::vector<std::int32_t>& material_;
  std::vector<std::int32_t>& body_;
  std::vector<std::int32_t>& id_;
  std::vector<std::int32_t>& ncount_;
  // Positions and supports at the last neighbour search; in the registry (not
  // exported) so that a checkpoint resumes with the same lists and order.
  std::vector<Vec3>& anchor_;
  std::vector<Real>& anchor_support_;
  // (m/ρ)^(1/3) at the last search, the ball each particle fills in the
  // open-space grid built on the anchors then (surface phase); in the registry
  // so that a resumed run rebuilds the same grid.
  std::vector<Real>& fill_radius_;
  // v − v* of the last implicit viscosity solve, its next start (in the
  // registry: it follows sorts and checkpoints).
  std::vector<Vec3>& viscous_change_;
  // Heat phase: this surface particle faces the air at least as much as a
  // heated collider; in the registry, so the next step's pressure phase (vented
  // bubbles) reads it for the same particle after a sort or a restore.
  std::vector<std::int32_t>& air_facing_;
  // Divergence-free pressure: the density solve's κ = p/ρ² of the last
  // step, its next warm start (in the registry: it follows sorts and checkpoints).
  std::vector<Real>& density_kappa_;
  std::vector<std::uint32_t> order_;
  // Per-step scratch, valid only within the phases that fill them (not in
  // the registry, so sorting does not move them).
  std::vector<Vec3> x_prev_;            // position before the drift, for mesh collisions
  std::vector<Vec3> dv_;                // XSPH correction
  std::vector<Real> compounded_eps_;    // XSPH's ε over a step longer than dt_ref
  std::vector<Real> dtemp_;             // temperature change of the heat phase
  std::vector<Real> p_over_rho2_;       // P/ρ², per particle (pressure phase)
  std::vector<Real> volume_;            // m/ρ, per particle (pressure phase)
  std::vector<Vec3> colour_grad_;       // Σ V_j ∇W_ij (points into the fluid), surface phase
  std::vector<Real> laplacian_moment_;  // a_i = −(1/3) Σ V_j x_ij·∇W_ij ∈ [0.25, 1] (heat phase; 1: uncorrected)
  OpenSpaceGrid open_space_;            // the space open to the outside (surface phase)
  bool open_space_built_ = false;       // open_space_ holds the anchors' grid (false after a restore)
  std::vector<Mat3> stress_rho2_;       // S/ρ², per particle (pressure phase)
  std::vector<Mat3> artificial_stress_;  // R_i of Monaghan (2000), per particle (forces phase)
  // No-slip walls, per particle (forces phase, read by the viscosity phase):
  // Σ S(d) over the sticky walls within h, and Σ S(d) v_wall (wall_viscosity_).
  std::vector<Real> wall_drag_;
  std::vector<Vec3> wall_drag_velocity_;
  // Implicit viscosity weights dt·w_ij, layout of lists_; single precision
  // halves the memory traffic of the conjugate-gradient products.
  std::vector<float> pair_visc_;
  // Per pair, this step: x_ij·∇W_ij/(r² + η²) · 2/(a_i + a_j), the corrected
  // Laplacian's weight the heat and water phases share (update_diffusion_weights).
  std::vector<float> pair_diffusion_;
  std::vector<Real> liquid_concentration_;  // water phase: W/V per particle, kg/m³
  // Implicit elasticity (stress phase → viscosity and stress-increment
  // phases): the step's forcing weight w = λ(1 − e^{−dt/λ}), and μ plus the
  // elastic viscosity w μ_e / 2, the viscosity the implicit solve uses.
  std::vector<Real> forcing_weight_, solve_viscosity_;
  std::vector<Vec3> viscosity_rhs_;            // M v* of the implicit viscosity solve
  std::vector<Vec3> viscosity_start_;          // v* (the velocities before the solve)
  PcgScratch<Vec3> viscosity_pcg_;             // its conjugate-gradient vectors
  std::vector<Mat3> correction_;               // stress-form viscosity: C_i = M_i^{−T}
  bool correction_fresh_ = false;              // correction_ is of the current positions
  std::vector<Mat3> stress_times_correction_;  // S_i C_i of the current iterate
  std::vector<Vec3> pair_volume_gradient_;     // stress form: V_j ∇_i W_ij, layout of lists_
  // Per particle: the normal of the wall it rests on (zero where none) and the wall's speed along it.
  std::vector<Vec3> support_normal_;
  std::vector<Real> support_velocity_;
  std::vector<Real> support_push_;    // b·n of a supported particle before the filter (its reaction's reference)
  std::size_t supported_ = 0;         // particles with a support this solve (none in the Laplacian form)
  bool measuring_reactions_ = false;  // the products are unfiltered, and only supported rows computed
  // Per neighbour pair, in the layout of lists_ (computed by the density
  // phase, valid until positions change): W(r) and W'(r)/r.
  std::vector<float> pair_w_, pair_dwr_;
  std::vector<std::size_t> body_counts_;
  std::vector<SamplingFill> body_fill_;  // what each body's lattice holds of its shape
  std::vector<std::string> warnings_;

  PhaseTimers timers_;
  int t_kick_, t_drift_, t_collide_, t_sort_, t_neigh_, t_density_, t_surface_, t_stress_, t_pressure_, t_forces_,
      t_xsph_, t_viscosity_, t_heat_, t_water_ = 0, t_browning_, t_properties_, t_smoothing_, t_check_,
                                      t_density_solve_ = 0, t_divergence_solve_ = 0;
  Real time_ = 0.0;
  long steps_ = 0;
  const char* dt_bound_ = "cfl";
  // heat_own_step: the mechanical time whose heat is still to be taken, over
  // how many steps, and the thermal bound (conduction, vapour diffusion) of the
  // last max_stable_dt (0 until asked: every step).
  Real heat_pending_ = 0;
  int heat_pending_steps_ = 0;
  Real heat_bound_ = 0;
};

}  // namespace bakesim::sph
