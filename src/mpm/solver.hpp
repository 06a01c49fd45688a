#pragma once
// Material Point Method (spec mpm-baking.md 4.1, 4.4, 4.5, 4.7): quadratic
// B-spline weights, APIC transfers (Jiang et al. 2015) with the moving-least-
// squares force and velocity gradient of MLS-MPM (Hu et al. 2018; departure
// noted in docs/physics.md), explicit grid update, finite-strain
// elastoplasticity on the particles, colliders on the grid.
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "core/solver.hpp"
#include "core/timers.hpp"
#include "geometry/colliders.hpp"
#include "geometry/motion.hpp"
#include "geometry/shapes.hpp"
#include "mpm/constitutive.hpp"

namespace bakesim::mpm {

struct Material {
  std::string name;
  Real density = 1000.0;  // kg/m³
  Lame lame{};
  ElasticLaw elastic = Hencky{};
  PlasticLaw plastic = NoPlasticity{};
};

struct Body {
  std::string name;
  int material = 0;
  Shape shape;
  Real temperature = 20.0;  // °C (carried; heat arrives with the thermomechanical MPM)
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();  // rad/s about the body's centre of mass
};

enum class Contact { sticky, slip, separate };

// A collider acts on the grid nodes inside it (signed distance ≤ 0) through
// their velocity relative to its own (scripted rigid motion).
struct GridCollider {
  Collider collider;  // geometry in its rest pose; mesh colliders need their signed distance grid
  Contact contact = Contact::separate;
  Real friction = 0.0;  // Coulomb μ
  RigidMotion motion;
};

struct Settings {
  Real cell_size = 0.01;       // Δx, m
  int particles_per_cell = 8;  // initial sampling: a lattice of ppc^(1/3) per axis
  Real cfl = 0.4;
  Real max_dt = 1e-3;
  int reorder_every = 16;      // steps between reordering particle memory by grid block
};

struct Setup {
  Settings settings;
  std::vector<Material> materials;
  std::vector<Body> bodies;
  std::vector<GridCollider> colliders;
  Aabb domain;
  Real domain_friction = 0.0;  // Coulomb μ of the domain walls (separating contact)
  Vec3 gravity = Vec3(0, -9.81, 0);
};

class MpmSolver final : public Solver {
 public:
  explicit MpmSolver(Setup setup);

  std::string name() const override { return "mpm"; }
  Real max_stable_dt() override;
  std::string active_dt_bound() const override { return dt_bound_; }
  void step(Real dt) override;
  Real time() const override { return time_; }
  const ParticleSet& particles() const override { return particles_; }
  ParticleSet& mutable_particles() { return particles_; }
  const PhaseTimers& timers() const override { return timers_; }
  std::vector<Real> sample(const Vec3& x, const std::vector<std::string>& quantities) const override;
  std::vector<std::string> probe_quantities() const override;

  const Setup& setup() const { return setup_; }
  // Deformation gradient F^E of particle i (columns stored as three vectors).
  Mat3 deformation_gradient(std::size_t i) const;
  void set_deformation_gradient(std::size_t i, const Mat3& f);
  Mat3 affine(std::size_t i) const;
  void set_affine(std::size_t i, const Mat3& c);
  std::size_t steps() const { return steps_; }
  Real total_mass() const;
  // Σ m_i over the grid after the last P2G (equals total_mass() by the
  // B-splines' partition of unity).
  Real grid_mass() const;
  Real cell_size() const { return dx_; }

 private:
  void build_particles();
  void phase_sort();
  void phase_p2g(Real dt);
  void phase_grid(Real dt);
  void phase_g2p(Real dt);
  void phase_plasticity(Real dt);
  void check_state();

  Setup setup_;
  ParticleSet particles_;
  PhaseTimers timers_;
  std::vector<Vec3>& x_;
  std::vector<Vec3>& v_;
  std::vector<Real>& m_;
  std::vector<Real>& volume0_;
  std::vector<Real>& j_;
  std::vector<Real>& jp_;
  std::vector<Real>& temperature_;
  std::vector<Vec3>& f0_;
  std::vector<Vec3>& f1_;
  std::vector<Vec3>& f2_;
  std::vector<Vec3>& c0_;
  std::vector<Vec3>& c1_;
  std::vector<Vec3>& c2_;
  std::vector<Vec3>& tau_diag_;  // Kirchhoff τ for the next P2G: τ_xx, τ_yy, τ_zz
  std::vector<Vec3>& tau_off_;   // τ_xy, τ_xz, τ_yz
  std::vector<std::int32_t>& material_;
  std::vector<std::int32_t>& body_;
  std::vector<std::int32_t>& id_;

  // Dense node grid over the domain (nodes at domain.min + k Δx).
  Real dx_ = 0, inv_dx_ = 0;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  // One node: mass and momentum after P2G; velocity replaces the momentum in
  // the grid update. Four doubles, so one node is half a cache line.
  struct Node {
    Real mass;
    Real mv[3];
  };
  std::vector<Node> grid_;
  // Blocks of kBlock³ cells, coloured 2×2×2 so same-coloured blocks never
  // share a node: P2G runs each colour's blocks in parallel without races.
  static constexpr int kBlock = 4;
  int bx_ = 0, by_ = 0, bz_ = 0;
  std::vector<std::uint32_t> order_;        // particle indices sorted by block
  std::vector<std::uint32_t> block_start_;  // per block, into order_ (size blocks + 1)
  std::vector<std::uint32_t> block_key_;
  std::vector<std::vector<std::uint32_t>> colour_blocks_;  // non-empty blocks per colour
  std::vector<std::uint32_t> block_fill_;  // counting-sort cursors, reused
  // Particle indices of each material, rebuilt when particle memory is
  // reordered: the constitutive phase dispatches once per material group.
  std::vector<std::vector<std::uint32_t>> material_members_;
  std::vector<RigidPose> collider_poses_;  // per collider, refreshed each grid phase

  std::size_t t_sort_, t_p2g_, t_grid_, t_g2p_, t_plastic_, t_check_;
  Real time_ = 0;
  std::size_t steps_ = 0;
  std::string dt_bound_ = "max_dt";
  Real max_wave_speed_ = 0;
};

}  // namespace bakesim::mpm
