#include "bench.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>

#include "core/errors.hpp"
#include "core/timers.hpp"
#include "io/bench_scenes.hpp"
#include "io/scene.hpp"

namespace bakesim {

int run_bench(const BenchOptions& opt) {
  const int hw = static_cast<int>(tbb::info::default_concurrency());
  std::vector<int> threads = opt.threads;
  if (threads.empty()) {
    threads.push_back(1);
    if (hw > 1) threads.push_back(hw);
  }
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
