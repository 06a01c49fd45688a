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
// With adaptive smoothing every pair uses h_ij = (h_i + h_j)/2 (Eq 3.56).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/solver.hpp"
#include "geometry/colliders.hpp"
#include "geometry/shapes.hpp"
#include "physics/browning.hpp"
#include "physics/curves.hpp"
#include "sph/kernels.hpp"
#include "sph/neighbours.hpp"
#include "sph/surface_detection.hpp"

namespace bakesim::sph {

struct Material {
  std::string name;
  Real rest_density = 1000.0;                        // kg/m³
  TemperatureCurve viscosity = ConstantCurve{1e-3};  // dynamic viscosity μ(T), Pa·s (Eq 4.1)
  Real surface_tension = 0.0;                        // σ, N/m (colour-field model)
  TemperatureCurve xsph = ConstantCurve{0.0};        // velocity tuner ε(T), clamped to [0, 1] (Eq 4.4)
  Real specific_heat = 4181.0;                       // J/(kg·K)
  Real conductivity = 0.6;                           // W/(m·K)
  // Maxwell viscoelasticity (Eq 3.20): elasticity μ_e(T) in Pa (0: no
  // viscoelastic stress) and relaxation time λ(T) in s (Eq 4.2, 4.3).
  TemperatureCurve elasticity = ConstantCurve{0.0};
  TemperatureCurve relaxation_time = ConstantCurve{1.0};
  // The curves read the highest temperature reached instead of the current
  // one: baked dough stays set when it cools (irreversible setting).
  bool properties_follow_peak = false;
};

enum class BubbleDistribution { uniform, centred, layered, region };

// Which particles of a body are bubbles (thesis 3.3.3), and how they rise.
struct BubbleSpec {
  Real fraction = 0.0;  // share of the body's particles (of the chosen zone)
  BubbleDistribution distribution = BubbleDistribution::uniform;
  std::uint64_t seed = 1;
  int layers = 4;                      // layered: slabs along the vertical, odd ones hold bubbles
  std::optional<Shape> region;         // region: bubbles only inside this shape
  std::optional<Real> pressure_scale;  // B of Eq 3.48 for bubbles, Pa (default: the material's Tait B)
  Real max_expansion = 3.0;            // a bubble stops rising when ρ0/ρ reaches this
  Real end_temperature = 100.0;        // °C: the rise ends (Eq 3.52 takes over) for every particle of the body
  bool contract_on_cooling = false;    // risen bubbles shrink by the gas law as they cool
};

struct Body {
  std::string name;
  std::string source;  // where it was defined, for messages ("bodies[1]")
  int material = 0;
  Shape shape;
  Real temperature = 20.0;  // °C
  Vec3 velocity = Vec3::Zero();
  bool hold_temperature = false;  // a thermostat: conducts, but keeps its temperature
  BubbleSpec bubbles;
};

enum class ViscositySolver { explicit_euler, implicit, automatic };
ViscositySolver parse_viscosity_solver(const std::string& name);
std::string to_string(ViscositySolver v);

// Oven air and the bake clock (docs/physics.md, "bake clock"): heat and gas
// rates run `bake_time_scale` times faster than the mechanics, so a real
// bake of scale × T seconds is simulated in T seconds of mechanics. The air
// temperature schedule is given in bake time.
struct Environment {
  PiecewiseLinear air_temperature = PiecewiseLinear::constant(20.0);  // °C over bake time (s)
  Real heat_transfer_coefficient = 10.0;                              // W/(m² K), air to surface particles
  Real bake_time_scale = 1.0;
  BrowningKinetics browning;  // crust colour from the temperature history
};

// Per-particle smoothing length, Eq 3.54–3.56 (docs/physics.md).
struct AdaptiveSmoothing {
  bool enabled = false;
  bool geometric_mean = true;             // ρ_ref: geometric mean of ρ/ρ0 (Eq 3.55), else ρ0
  Real sensitivity = 0.5;                 // ε_g
  Real scale = 1.0;                       // k_g
  Real min_ratio = 0.8, max_ratio = 1.5;  // h_i / h0 limits
};

struct Settings {
  Real spacing = 0.01;         // initial particle spacing s, m
  Real smoothing_ratio = 2.0;  // support h = ratio · s
  Real speed_of_sound = 20.0;  // c, m/s; Tait B = ρ0 c² / γ
  Real gamma = 7.0;
  NeighbourMethod search = NeighbourMethod::grid;
  bool clamp_negative_pressure = true;
  bool wall_density_correction = true;
  Real av_alpha = 0.0, av_beta = 1.0, av_epsilon = 0.01;  // Eq 3.36–3.37
  // Monaghan's artificial stress: fraction ε of the tensile principal stress
  // (0: off) and the exponent n of (W(r)/W(s))^n.
  Real artificial_stress = 0.0, artificial_stress_exponent = 4.0;
  Real surface_threshold = 0.1;  // |∇C| · h above which surface tension acts (Eq 3.30)
  SurfaceMethod surface_method = SurfaceMethod::colour;
  Real surface_colour_threshold = 0.6;  // |∇C| · h at or above which a particle is on the surface
  Real surface_hull_threshold = 0.5;    // hull boundary closer than this × spacing: on the surface
  int surface_every = 1;                // steps between surface detections
  ViscositySolver viscosity_solver = ViscositySolver::automatic;
  AdaptiveSmoothing adaptive;
  Real implicit_tolerance = 1e-6;  // relative residual of the implicit viscosity solve
  int implicit_max_iterations = 500;
  Real cfl = 0.4;
  bool heat_conduction = true;
  Real conduction_factor = 0.1;
  Real viscous_factor = 0.125;
  Real force_factor = 0.25;
  Real max_dt = 1e-3;
};

struct Setup {
  Settings settings;
  std::vector<Material> materials;
  std::vector<Body> bodies;
  std::vector<Collider> colliders;
  Aabb domain;
  Environment environment;
  Real domain_friction = 0.0;
  Real domain_damping = 1.0;
  Vec3 gravity = Vec3(0, -9.81, 0);
};

class SphSolver final : public Solver {
 public:
  explicit SphSolver(Setup setup);

  std::string name() const override { return "sph"; }
  Real max_stable_dt() override;
  std::string active_dt_bound() const override { return dt_bound_; }
  // Every time-step bound with its value (s): max_dt, cfl, viscosity, force.
  std::vector<std::pair<std::string, Real>> time_step_bounds() const;
  void step(Real dt) override;
  Real time() const override { return time_; }
  const ParticleSet& particles() const override { return particles_; }
  std::vector<std::pair<std::string, double>> checkpoint_state() const override;
  void restore_state(const std::vector<std::pair<std::string, double>>& state) override;
  ParticleSet& particles_for_restore() override { return particles_; }
  const PhaseTimers& timers() const override { return timers_; }
  std::vector<Real> sample(const Vec3& x, const std::vector<std::string>& quantities) const override;
  std::vector<std::string> probe_quantities() const override;

  const Setup& setup() const { return setup_; }
  Real support() const { return h_; }
  Real particle_mass(int material) const;
  const NeighbourLists& neighbours() const { return lists_; }
  long steps() const { return steps_; }
  Real bake_time() const { return time_ * setup_.environment.bake_time_scale; }
  bool implicit_viscosity() const { return implicit_viscosity_; }
  int last_viscosity_iterations() const { return viscosity_iterations_; }
  // Heat that entered through the surface (air and colliders) since the start, J.
  Real exchanged_heat() const { return exchanged_heat_; }
  // Viscoelastic stress of particle i (symmetric, Pa).
  Mat3 stress(std::size_t i) const;
  void set_stress(std::size_t i, const Mat3& s);
  // Velocity gradient L_ab = ∂v_a/∂x_b at particle i (Eq 3.27).
  Mat3 velocity_gradient(std::size_t i) const;
  std::size_t body_particle_count(std::size_t body) const { return body_counts_.at(body); }

  // Recomputes neighbours, density, pressure and accelerations for the current
  // positions (done automatically; public for tests that edit particles).
  void refresh();
  ParticleSet& mutable_particles() { return particles_; }

 private:
  void seed_particles();
  void check_initial_overlaps() const;
  void phase_neighbours();
  void phase_density();
  void phase_surface();
  void phase_stress(Real dt);
  void phase_pressure();
  void phase_forces();
  void phase_kick(Real dt);
  void phase_drift(Real dt);
  void phase_collide();
  void phase_xsph();
  void phase_viscosity(Real dt);
  void phase_heat(Real dt);
  void phase_browning(Real dt);
  void phase_properties();
  void phase_smoothing();
  void assign_bubbles();
  void check_finite();
  // Share of particle i's kernel beyond all analytic walls, 1 − Π(1 − f_k),
  // and its gradient (walls combined as independent events, exact for a
  // Gaussian kernel and close for the spline at box edges and corners).
  Real wall_share(const Vec3& x, Vec3* gradient) const;

  Setup setup_;
  Real h_;
  Real contact_distance_;
  CubicSpline kernel_;
  Real lattice_sum_;  // Σ W over the sampling lattice (mass calibration, wall share)
  ViscosityLaplacian visc_lap_;
  WallKernelShare wall_share_;
  NeighbourSearch search_;
  NeighbourLists lists_;
  std::vector<Collider> walls_;     // analytic colliders incl. the domain box
  std::vector<Collider> meshes_;    // mesh colliders
  std::vector<Real> tait_b_;        // per material
  std::vector<Real> mass_;          // per material
  std::vector<Real> conductivity_;  // per material, read per neighbour pair in the heat phase
  std::vector<Real> bubble_b_;      // per body: B of Eq 3.48
  bool implicit_viscosity_ = false;
  bool elastic_ = false;             // some material has a Maxwell stress (μ_e not identically 0)
  bool heated_colliders_ = false;    // some collider carries a temperature
  bool follows_peak_ = false;        // some material reads its curves at the peak temperature
  bool adaptive_ = false;            // per-particle smoothing length (Eq 3.54–3.56)
  std::vector<Real> exchange_area_;  // per material: π r² of a surface particle (Eq 3.43)
  int viscosity_iterations_ = 0;
  Real exchanged_heat_ = 0.0;

  ParticleSet particles_;
  std::vector<Vec3>& x_;
  std::vector<Vec3>& v_;
  std::vector<Vec3>& a_;
  std::vector<Real>& rho_;
  std::vector<Real>& p_;
  std::vector<Real>& m_;
  std::vector<Real>& temperature_;
  std::vector<Real>& browning_;  // browning index B = ΔE/ΔE∞
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
  std::vector<std::uint32_t> order_;
  // Per-step scratch, valid only within the phases that fill them (not in
  // the registry, so sorting does not move them).
  std::vector<Vec3> x_prev_;             // position before the drift, for mesh collisions
  std::vector<Vec3> dv_;                 // XSPH correction
  std::vector<Real> dtemp_;              // temperature change of the heat phase
  std::vector<Real> p_over_rho2_;        // P/ρ², per particle (pressure phase)
  std::vector<Real> volume_;             // m/ρ, per particle (pressure phase)
  std::vector<Vec3> colour_grad_;        // Σ V_j ∇W_ij (points into the fluid), surface phase
  std::vector<Mat3> stress_rho2_;        // S/ρ², per particle (pressure phase)
  std::vector<Mat3> artificial_stress_;  // R_i of Monaghan (2000), per particle (forces phase)
  std::vector<double> pair_visc_;        // implicit viscosity weights, layout of lists_
  std::vector<Vec3> cg_r_, cg_z_, cg_p_, cg_ap_;
  // Per neighbour pair, in the layout of lists_ (computed by the density
  // phase, valid until positions change): W(r) and W'(r)/r.
  std::vector<float> pair_w_, pair_dwr_;
  std::vector<std::size_t> body_counts_;

  PhaseTimers timers_;
  int t_kick_, t_drift_, t_collide_, t_sort_, t_neigh_, t_density_, t_surface_, t_stress_, t_pressure_, t_forces_,
      t_xsph_, t_viscosity_, t_heat_, t_browning_, t_properties_, t_smoothing_, t_check_;
  Real time_ = 0.0;
  long steps_ = 0;
  std::string dt_bound_ = "cfl";
};

}  // namespace bakesim::sph
