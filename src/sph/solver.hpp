#pragma once
// Weakly compressible SPH (thesis Chapter 3.1, 3.2, 3.4).
// One step, as named (and timed) phases:
//   kick      v += ½dt a                                  (leap-frog, 3.4)
//   drift     x += dt v
//   collide   walls and meshes                            (Eq 3.31–3.33)
//   sort      particles by cell (memory order)
//   neighbours neighbour lists                             (3.1.2)
//   density   ρ = Σ m W (+ wall half-space)               (Eq 3.13)
//   pressure  Tait                                        (Eq 3.17)
//   forces    pressure, viscosity, artificial viscosity,
//             surface tension, gravity                     (Eq 3.18, 3.19, 3.35–3.41, 3.28–3.30)
//   kick      v += ½dt a
//   xsph      velocity correction                          (Eq 3.34)
//   heat      conduction between particles                 (Eq 3.45–3.46)
//   properties temperature-dependent μ and ε               (Eq 4.1, 4.4)
#include <memory>
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/solver.hpp"
#include "geometry/colliders.hpp"
#include "geometry/shapes.hpp"
#include "physics/curves.hpp"
#include "sph/kernels.hpp"
#include "sph/neighbours.hpp"

namespace bakesim::sph {

struct Material {
  std::string name;
  Real rest_density = 1000.0;   // kg/m³
  TemperatureCurve viscosity = ConstantCurve{1e-3};  // dynamic viscosity μ(T), Pa·s (Eq 4.1)
  Real surface_tension = 0.0;                        // σ, N/m (colour-field model)
  TemperatureCurve xsph = ConstantCurve{0.0};        // velocity tuner ε(T), clamped to [0, 1] (Eq 4.4)
  Real specific_heat = 4181.0;  // J/(kg·K)
  Real conductivity = 0.6;      // W/(m·K)
};

struct Body {
  std::string name;
  std::string source;  // where it was defined, for messages ("bodies[1]")
  int material = 0;
  Shape shape;
  Real temperature = 20.0;  // °C
  Vec3 velocity = Vec3::Zero();
  bool hold_temperature = false;  // a thermostat: conducts, but keeps its temperature
};

struct Settings {
  Real spacing = 0.01;           // initial particle spacing s, m
  Real smoothing_ratio = 2.0;    // support h = ratio · s
  Real speed_of_sound = 20.0;    // c, m/s; Tait B = ρ0 c² / γ
  Real gamma = 7.0;
  NeighbourMethod search = NeighbourMethod::grid;
  bool clamp_negative_pressure = true;
  bool wall_density_correction = true;
  Real av_alpha = 0.0, av_beta = 1.0, av_epsilon = 0.01;  // Eq 3.36–3.37
  Real surface_threshold = 0.1;  // |∇C| · h above which surface tension acts (Eq 3.30)
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
  const PhaseTimers& timers() const override { return timers_; }
  std::vector<Real> sample(const Vec3& x, const std::vector<std::string>& quantities) const override;
  std::vector<std::string> probe_quantities() const override;

  const Setup& setup() const { return setup_; }
  Real support() const { return h_; }
  Real particle_mass(int material) const;
  const NeighbourLists& neighbours() const { return lists_; }
  long steps() const { return steps_; }
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
  void phase_pressure();
  void phase_forces();
  void phase_kick(Real dt);
  void phase_drift(Real dt);
  void phase_collide();
  void phase_xsph();
  void phase_heat(Real dt);
  void phase_properties();
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
  std::vector<Collider> walls_;  // analytic colliders incl. the domain box
  std::vector<Collider> meshes_; // mesh colliders
  std::vector<Real> tait_b_;     // per material
  std::vector<Real> mass_;       // per material
  std::vector<Real> conductivity_;  // per material, read per neighbour pair in the heat phase

  ParticleSet particles_;
  std::vector<Vec3>& x_;
  std::vector<Vec3>& v_;
  std::vector<Vec3>& a_;
  std::vector<Real>& rho_;
  std::vector<Real>& p_;
  std::vector<Real>& m_;
  std::vector<Real>& temperature_;
  std::vector<Real>& mu_;
  std::vector<Real>& eps_;
  std::vector<std::int32_t>& material_;
  std::vector<std::int32_t>& body_;
  std::vector<std::int32_t>& id_;
  std::vector<std::int32_t>& ncount_;
  std::vector<std::uint32_t> order_;
  // Per-step scratch, valid only within the phases that fill them (not in
  // the registry, so sorting does not move them).
  std::vector<Vec3> x_prev_;  // position before the drift, for mesh collisions
  std::vector<Vec3> dv_;      // XSPH correction
  std::vector<Real> dtemp_;   // temperature change of the heat phase
  std::vector<Real> p_over_rho2_;  // P/ρ², per particle (pressure phase)
  std::vector<Real> volume_;       // m/ρ, per particle (pressure phase)
  // Per neighbour pair, in the layout of lists_ (computed by the density
  // phase, valid until positions change): W(r) and W'(r)/r.
  std::vector<float> pair_w_, pair_dwr_;
  std::vector<std::size_t> body_counts_;

  PhaseTimers timers_;
  int t_kick_, t_drift_, t_collide_, t_sort_, t_neigh_, t_density_, t_pressure_, t_forces_, t_xsph_, t_heat_, t_properties_, t_check_;
  Real time_ = 0.0;
  long steps_ = 0;
  std::string dt_bound_ = "cfl";
};

}  // namespace bakesim::sph
