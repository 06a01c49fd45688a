#pragma once
// The frame loop: steps a Solver with its stable time step up to each frame
// time, hands every frame to an observer (writers, stats, probes), reports
// progress, and logs which time-step bound is active.
#include <functional>
#include <memory>

#include <spdlog/logger.h>

#include "core/progress.hpp"
#include "core/solver.hpp"

namespace bakesim {

struct FrameInfo {
  int frame = 0;     // 0 is the initial state
  Real time = 0;     // simulated time, s
  long steps = 0;    // cumulative
  Real last_dt = 0;  // most recent time step, s
};

class FrameObserver {
 public:
  virtual ~FrameObserver() = default;
  virtual void on_frame(const FrameInfo& info, const Solver& solver) = 0;
};

struct FrameLoopConfig {
  Real end_time = 1.0;
  Real fps = 30.0;
  // Resuming: the frame the solver's restored state belongs to (its frame was
  // already written), with the loop's counters at that frame.
  int start_frame = 0;
  long start_steps = 0;
  Real start_last_dt = 0;
  // The start frame's row is written already (a resume, or a loop going on
  // from where an earlier one stopped): it is not observed again.
  bool start_frame_written = false;
  // Called after every frame (checkpoints, interruption); returning false
  // stops the loop there.
  std::function<bool(const FrameInfo&, const Solver&)> after_frame;
  // A step shorter than this is a failure (the state has gone stiff or bad).
  Real min_dt = 1e-10;
  // > 0: the progress bar counts minutes of bake (bake seconds per simulated second).
  Real bake_time_scale = 0;
};

struct RunSummary {
  long steps = 0;
  int frames = 0;
  double wall_seconds = 0;
  double particle_steps_per_second = 0;
  std::size_t particles = 0;
  int last_frame = 0;
  bool stopped = false;  // after_frame asked to stop before the end
};

// The solver's stable step, or SimulationError when it is below `min_dt` (`steps`: for the message).
Real checked_stable_dt(Solver& solver, Real min_dt, long steps);
// The step to take towards `target`: lands on it exactly without leaving a tiny last step.
Real landing_step(Real dt, Real remaining);

RunSummary run_frames(Solver& solver, const FrameLoopConfig& cfg, FrameObserver& observer, ProgressBar& progress,
                      spdlog::logger& log);

}  // namespace bakesim
