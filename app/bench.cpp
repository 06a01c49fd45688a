#include "bench.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "core/errors.hpp"
#include "core/timers.hpp"
#include "io/bench_scenes.hpp"
#include "io/scene.hpp"

namespace bakesim {

namespace {

// A scene's whole run (a bake) per thread count: wall time, steps, particle-steps
// per second, the steps each time-step bound limited, and the time per phase.
int run_scene_bench(const BenchOptions& opt, const std::vector<int>& threads, int hw) {
  std::vector<SceneOverride> overrides;
  for (const std::string& s : opt.sets) overrides.push_back(parse_override(s));
  Scene scene = load_scene(opt.scene, overrides, opt.preview);  // a bad scene is refused before the header
  if (opt.end_time > 0) set_end_time(scene, opt.end_time);
  fmt::print("bakesim bench: {}{}, machine has {} hardware threads\n", opt.scene, opt.preview ? " (preview)" : "", hw);
  for (int t : threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
    auto solver = make_solver(scene);
    std::map<std::string, long> bounds;  // steps limited by each bound
    long steps = 0;
    struct SolveTally {
      long steps = 0, iterations = 0;
      int most = 0;
    };
    std::vector<std::pair<std::string, SolveTally>> solves;  // in the order the solver names them
    Stopwatch clock;
    while (solver->time() < scene.end_time - 1e-12) {
      const Real dt = std::min(solver->max_stable_dt(), scene.end_time - solver->time());
      ++bounds[solver->active_dt_bound()];
      solver->step(dt);
      ++steps;
      for (const Solver::SolveIterations& solve : solver->last_solve_iterations()) {
        if (!solve.name) continue;
        auto it = std::find_if(solves.begin(), solves.end(), [&](const auto& s) { return s.first == solve.name; });
        if (it == solves.end()) it = solves.insert(solves.end(), {solve.name, SolveTally{}});
        ++it->second.steps;
        it->second.iterations += solve.iterations;
        it->second.most = std::max(it->second.most, solve.iterations);
      }
    }
    const double secs = clock.seconds();
    fmt::print(
        "{} particles, {} threads: {:.6g} s simulated in {} steps, {:.2f} s wall ({:.2f} s per simulated "
        "second), {:.0f} particle-steps/s, {:.2f} ms/step\n",
        solver->particles().size(), t, solver->time(), steps, secs, secs / solver->time(),
        double(solver->particles().size()) * steps / secs, 1e3 * secs / steps);
    std::string limits;
    for (const auto& [name, count] : bounds) limits += fmt::format(" {} {:.1f}%", name, 100.0 * count / steps);
    fmt::print("steps limited by:{}\n", limits);
    // Each iterative solve's iterations: what its phase's time is made of.
    for (const auto& [name, tally] : solves)
      fmt::print("{}: {:.1f} iterations a step (mean), {} at most\n", name,
                 double(tally.iterations) / double(tally.steps), tally.most);
    if (opt.phases) fmt::print("{}", solver->timers().report(steps));
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int run_bench(const BenchOptions& opt) {
  const int hw = static_cast<int>(tbb::info::default_concurrency());
  std::vector<int> threads = opt.threads;
  if (threads.empty()) {
    threads.push_back(1);
    if (hw > 1) threads.push_back(hw);
  }
  if (!opt.scene.empty()) return run_scene_bench(opt, threads, hw);
  const bool mpm = opt.solver == "mpm";
  if (!mpm && opt.solver != "sph") throw InputError("bench --solver", "unknown solver '" + opt.solver + "' (sph, mpm)");
  fmt::print("bakesim bench: {}, {} steps per case, machine has {} hardware threads\n",
             mpm ? "MPM cube squashed on the floor" : "SPH dam break", opt.steps, hw);
  fmt::print("{:>10} {:>13} {:>6} {:>8} {:>16} {:>10}\n", "particles", mpm ? "model" : "search", mpm ? "" : "skin",
             "threads", "particle-steps/s", "ms/step");
  const std::vector<double> skins = mpm ? std::vector<double>{0.0} : opt.skins;
  for (long n : opt.particles)
    for (const std::string& variant : mpm ? opt.models : opt.searches)
      for (double skin : skins)
        for (int t : threads) {
          tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
          Scene scene =
              parse_scene(mpm ? mpm_cube_scene_json(n, variant) : dam_break_scene_json(n, variant, skin), "bench", ".");
          auto solver = make_solver(scene);
          // Warm up so the column has started to move and caches are hot.
          for (int i = 0; i < 5; ++i) solver->step(solver->max_stable_dt());
          const PhaseTimers before = solver->timers();
          Stopwatch clock;
          for (int i = 0; i < opt.steps; ++i) solver->step(solver->max_stable_dt());
          const double secs = clock.seconds();
          const double rate = double(solver->particles().size()) * opt.steps / secs;
          fmt::print("{:>10} {:>13} {:>6} {:>8} {:>16.0f} {:>10.2f}\n", solver->particles().size(), variant,
                     mpm ? std::string() : fmt::format("{:g}", skin), t, rate, 1e3 * secs / opt.steps);
          if (opt.phases) fmt::print("{}", solver->timers().since(before).report(opt.steps));
          std::fflush(stdout);
        }
  return 0;
}

}  // namespace bakesim
