#pragma once
// The thin interface the frame loop drives. Each solver owns its state; the
// loop asks for a stable step, steps, and reads particles for output.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "core/timers.hpp"

namespace bakesim {

class Solver {
 public:
  virtual ~Solver() = default;
  virtual std::string name() const = 0;
  // Largest stable time step for the current state (s).
  virtual Real max_stable_dt() = 0;
  // Which bound limited the last max_stable_dt() ("cfl", "viscosity", ...): a
  // name with static storage, so asking every step allocates nothing.
  virtual const char* active_dt_bound() const = 0;
  // Advances the state by dt; throws SimulationError on an invalid state.
  virtual void step(Real dt) = 0;
  // Brings what advances on a slower clock than the steps (SPH heat, water
  // and browning every few steps) to time(): the frame loop calls it before a
  // frame is read or written. A no-op when nothing lags.
  virtual void synchronize() {}
  virtual Real time() const = 0;
  virtual const ParticleSet& particles() const = 0;
  virtual const PhaseTimers& timers() const = 0;
  // Interpolated quantities at a point (NaN where no particle is near); names
  // are resolved from the particle registry (core/quantity.hpp).
  virtual std::vector<Real> sample(const Vec3& x, const std::vector<std::string>& quantities) const = 0;
  // Whether the run transfers heat (per-body bake statistics go to stats.csv).
  virtual bool heats() const { return true; }
  // What this solver will simulate, as lines for `bakesim validate` (its
  // resolution, materials, bodies, colliders, time-step bounds).
  virtual std::string summary() const = 0;
  // What the set-up found doubtful and runs with all the same (a body its
  // particle lattice fills short), a line each, for the command line to print.
  virtual std::vector<std::string> warnings() const { return {}; }
  // Solver-specific per-frame numbers for stats.csv (name, value), the same
  // names on every frame.
  virtual std::vector<std::pair<std::string, Real>> frame_quantities() const { return {}; }
  // The last step's iterative solves (the SPH viscosity and pressure, the
  // MPM heat) for `bakesim bench`: each one's name (static storage; nullptr
  // for an unused entry) and its iterations.
  struct SolveIterations {
    const char* name = nullptr;
    int iterations = 0;
  };
  using StepSolves = std::array<SolveIterations, 3>;
  virtual StepSolves last_solve_iterations() const { return {}; }

  // Checkpoints (src/io/checkpoint.hpp): the particle attributes, all of them,
  // plus the named numbers returned here are everything the next steps depend
  // on. restore_state() runs after the attributes are written back through
  // particles_for_restore() and rebuilds whatever the solver derives from them.
  virtual std::vector<std::pair<std::string, double>> checkpoint_state() const = 0;
  virtual void restore_state(const std::vector<std::pair<std::string, double>>& state) = 0;
  virtual ParticleSet& particles_for_restore() = 0;
  // After restore_state(): why the restored particles cannot be this
  // solver's state (one where its grids cannot hold it, a non-positive mass,
  // ...; the first offender named), or "" when they can be. A crafted
  // checkpoint is refused with it instead of crashing the next step.
  virtual std::string restored_state_problem() const = 0;
};

}  // namespace bakesim
