#pragma once
// What an SPH run is made of: materials, bodies (with their bubbles), the
// solver's settings and the colliders, as the scene loader builds them
// (io/scene_sph.cpp) and the solver reads them.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/colliders.hpp"
#include "geometry/shapes.hpp"
#include "geometry/world.hpp"
#include "physics/curves.hpp"
#include "physics/oven.hpp"
#include "physics/setting.hpp"
#include "physics/water.hpp"
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
  // Once set, the curves read the highest temperature reached instead of the
  // current one: baked dough stays set when it cools.
  IrreversibleSetting set;  // when the curves start to follow the peak temperature (physics/setting.hpp)
  PoreWater moisture;       // water, vapour and latent heat (physics/water.hpp); off unless moisture.moisture > 0
  // A yield-stress fluid (physics/rheology.hpp): the consistency K is
  // `viscosity`; μ follows each particle's shear rate. Absent: Newtonian.
  struct YieldFlow {
    TemperatureCurve yield_stress = ConstantCurve{0.0};  // τ_y, Pa (shear)
    Real flow_index = 1.0;                               // n
    Real regularisation = 1e-3;                          // γ̇_r, 1/s (regularised form)
    // Saramito's (2007) elastoviscoplastic fluid: the Maxwell stress of the
    // material's elasticity is elastic below τ_y and returns to τ_y + K γ̇_pⁿ
    // above it (the Perzyna return MPM uses); μ and λ are then not used.
    bool elastoviscoplastic = false;
  };
  std::optional<YieldFlow> yield_flow;
};

// The Maxwell relaxation time of an elastoviscoplastic material, whose stress
// relaxes only by its plastic flow: e^{−Δt/λ} is 1 to the last bit. Finite, as
// every particle quantity must be (checkpoints refuse the others).
inline constexpr Real kNeverRelaxes = 1e30;  // s

// A yield-stress fluid whose viscosity follows its shear rate (the regularised form).
inline bool regularised_yield_flow(const Material& m) { return m.yield_flow && !m.yield_flow->elastoviscoplastic; }
inline bool elastoviscoplastic(const Material& m) { return m.yield_flow && m.yield_flow->elastoviscoplastic; }
// The support, in spacings, below which an elastoviscoplastic body's stresses
// drift apart in plastic flow (docs/validation.md, "Cylinder slump"; the scene loader warns).
inline constexpr Real kElastoviscoplasticSupport = 2.5;

// A mesh collider's surface is sampled as particles of its own; the others are analytic walls.
inline bool analytic_wall(const Collider& c) { return !std::holds_alternative<MeshCollider>(c.geometry); }
// The sticky analytic walls: the no-slip walls of the viscous terms.
inline bool no_slip_wall(const Collider& c) { return analytic_wall(c) && c.contact.mode == ContactMode::sticky; }

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
  bool vent_at_surface = false;        // a rising bubble on the air-facing surface holds no gas pressure
};

struct Body : BodyBase {
  bool hold_temperature = false;  // a thermostat: conducts, but keeps its temperature
  BubbleSpec bubbles;
};

enum class ViscositySolver { explicit_euler, implicit, automatic };
ViscositySolver parse_viscosity_solver(const std::string& name);
std::string to_string(ViscositySolver v);

// Per-particle smoothing length, Eq 3.54–3.56 (docs/physics.md).
struct AdaptiveSmoothing {
  bool enabled = false;
  bool geometric_mean = true;             // ρ_ref: geometric mean of ρ/ρ0 (Eq 3.55), else ρ0
  Real sensitivity = 0.5;                 // ε_g
  Real scale = 1.0;                       // k_g
  Real min_ratio = 0.8, max_ratio = 1.5;  // h_i / h0 limits
};

// weakly_compressible: Tait pressure from the density (Eq 3.17), the step
// bounded by the speed of sound. divergence_free: DFSPH (Bender & Koschier
// 2015, 2017): pressure solved for each step so that the density stays at rest
// and the velocity field divergence-free; the step is bounded by the flow.
enum class PressureSolver { weakly_compressible, divergence_free };

struct Settings {
  Real spacing = 0.01;         // initial particle spacing s, m
  Real smoothing_ratio = 2.0;  // support h = ratio · s
  Real speed_of_sound = 20.0;  // c, m/s; Tait B = ρ0 c² / γ
  Real gamma = 7.0;
  NeighbourMethod search = NeighbourMethod::grid;
  // Verlet skin as a fraction of the support h: candidates within h(1 + skin)
  // are searched only when particles have moved far enough (0: every step).
  Real neighbour_skin = 0.2;
  bool clamp_negative_pressure = true;
  bool wall_density_correction = true;
  Real av_alpha = 0.0, av_beta = 1.0, av_epsilon = 0.01;  // Eq 3.36–3.37
  // Monaghan's artificial stress: fraction ε of the tensile principal stress
  // (0: off) and the exponent n of (W(r)/W(s))^n.
  Real artificial_stress = 0.0, artificial_stress_exponent = 4.0;
  Real surface_threshold = 0.1;  // |∇C| · h above which surface tension acts (Eq 3.30)
  SurfaceMethod surface_method = SurfaceMethod::colour;
  Real surface_colour_threshold = 0.3;  // |∇C| · h at or above which a particle is on the surface
  Real surface_hull_threshold = 0.5;    // hull boundary closer than this × spacing: on the surface
  int surface_every = 1;                // steps between surface detections
  bool surface_open_space = true;       // keep flags only where open space lies along the outward normal
  ViscositySolver viscosity_solver = ViscositySolver::automatic;
  // Stress-form viscosity (implicit only): the force is the divergence of
  // 2μ dev D from corrected kernel gradients, so free surfaces carry the
  // stress of extensional flow (a yield-stress column stands); false: the
  // thesis's Laplacian (Eq 3.19).
  bool stress_viscosity = false;
  // Semi-implicit Maxwell stress: its elastic increment is taken in the
  // implicit viscosity solve (backward Euler), so set dough's shear waves do
  // not bound the step; false: explicit (Eq 3.20–3.27 as the thesis has them).
  bool implicit_elasticity = false;
  AdaptiveSmoothing adaptive;
  PressureSolver pressure_solver = PressureSolver::weakly_compressible;
  Real density_tolerance = 1e-4;  // divergence_free: mean predicted (ρ − ρ0)/ρ0 at which the density solve stops
  Real divergence_tolerance = 1e-3;  // and mean max_dt·(Dρ/Dt)/ρ0 at which the divergence solve stops
  int pressure_max_iterations = 100;
  Real implicit_tolerance = 1e-6;  // relative residual of the implicit viscosity solve
  int implicit_max_iterations = 500;
  Real cfl = 0.4;
  bool heat_conduction = true;
  bool corrected_laplacian = true;  // pair exchange divided by the mean kernel moment (docs/physics.md)
  Real conduction_factor = 0.1;
  // Heat, water and browning advance once every few mechanical steps, over
  // their summed time, while that sum stays within the conduction and
  // vapour-diffusion bounds (at most kMaxHeatEverySteps), or in substeps
  // within them where a step is longer, so those bounds do not bound the
  // mechanical step; false: every step, bounded by them.
  bool heat_own_step = true;
  Real viscous_factor = 0.125;
  Real force_factor = 0.25;
  Real max_dt = 1e-3;
};

struct Setup : World {
  Settings settings;
  std::vector<Material> materials;
  std::vector<Body> bodies;
};

}  // namespace bakesim::sph
