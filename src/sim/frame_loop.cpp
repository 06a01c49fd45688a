#include "sim/frame_loop.hpp"

#include <cstring>

#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"

namespace bakesim {

Real checked_stable_dt(Solver& solver, Real min_dt, long steps) {
  const Real dt = solver.max_stable_dt();
  if (!(dt >= min_dt))
    throw SimulationError(fmt::format(
        "{} step {} (t = {:.6g} s): the stable time step {:.4g} s, limited by {}, is below the floor {:.4g} s",
        solver.name(), steps, solver.time(), dt, solver.active_dt_bound(), min_dt));
  return dt;
}

Real landing_step(Real dt, Real remaining) {
  if (dt >= remaining) return remaining;
  if (dt > 0.5 * remaining) return 0.5 * remaining;
  return dt;
}

RunSummary run_frames(Solver& solver, const FrameLoopConfig& cfg, FrameObserver& observer, ProgressBar& progress,
                      spdlog::logger& log) {
  if (!(cfg.fps > 0)) throw InputError("time.fps", "must be > 0");
  const int frames = std::max(1, static_cast<int>(std::ceil(cfg.end_time * cfg.fps - 1e-9)));
  const std::size_t n = solver.particles().size();
  RunSummary summary;
  summary.particles = n;
  Stopwatch wall;
  FrameInfo info;
  info.frame = cfg.start_frame;
  info.time = solver.time();
  info.steps = cfg.start_steps;
  info.last_dt = cfg.start_last_dt;
  if (cfg.start_frame == 0 && !cfg.start_frame_written) {
    observer.on_frame(info, solver);
    if (cfg.after_frame && !cfg.after_frame(info, solver)) summary.stopped = true;
  }
  const char* bound = "";  // the step's limiting bound, logged when it changes
  for (int f = cfg.start_frame + 1; f <= frames && !summary.stopped; ++f) {
    const Real target = std::min(cfg.end_time, f / cfg.fps);
    while (solver.time() < target - 1e-12) {
      Real dt = checked_stable_dt(solver, cfg.min_dt, info.steps);
      if (std::strcmp(solver.active_dt_bound(), bound) != 0) {
        bound = solver.active_dt_bound();
        log.info("t = {:.6f} s: time step {:.3e} s limited by {}", solver.time(), dt, bound);
      }
      dt = landing_step(dt, target - solver.time());
      solver.step(dt);
      info.last_dt = dt;
      ++info.steps;
      progress.update({f - 1, frames, solver.time(), cfg.end_time, info.steps, cfg.bake_time_scale});
    }
    solver.synchronize();  // the frame reads every field at its time
    info.frame = f;
    info.time = solver.time();
    observer.on_frame(info, solver);  // which frames get particle files is the observer's choice
    log.debug("frame {} t = {:.6f} s steps {} dt {:.3e}", f, info.time, info.steps, info.last_dt);
    // Before the bar is drawn, so what it shows (the core temperature) is this frame's.
    if (cfg.after_frame && !cfg.after_frame(info, solver) && f < frames) summary.stopped = true;
    progress.update({f, frames, solver.time(), cfg.end_time, info.steps, cfg.bake_time_scale}, f == frames);
  }
  progress.finish();
  summary.steps = info.steps - cfg.start_steps;
  summary.frames = frames;
  summary.last_frame = info.frame;
  summary.wall_seconds = wall.seconds();
  summary.particle_steps_per_second =
      summary.wall_seconds > 0 ? double(summary.steps) * double(n) / summary.wall_seconds : 0.0;
  return summary;
}

}  // namespace bakesim
