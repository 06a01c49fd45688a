#include "bench.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>

#include "core/timers.hpp"
#include "io/scene.hpp"

namespace bakesim {

std::string dam_break_scene_json(long particles, const std::string& search) {
  // Column a × 2a × depth, depth = a/2 (thin 3D slab of the 2D experiment).
  const double a = 0.146;
  const double depth = 0.5 * a;
  const double volume = a * 2 * a * depth;
  const double spacing = std::cbrt(volume / double(particles));
  return fmt::format(R"({{
  "name": "dam-break-bench",
  "solver": {{"type": "sph", "sph": {{"spacing": {spacing}, "neighbour_search": "{search}"}}}},
  "time": {{"end": 1.0, "fps": 1}},
  "domain": {{"min": [0, 0, 0], "max": [{lx}, {ly}, {depth}]}},
  "materials": {{"water": {{"density": 1000, "viscosity": 0.001, "xsph": 0.1}}}},
  "bodies": [{{"name": "column", "material": "water",
              "shape": {{"type": "box", "min": [0, 0, 0], "max": [{a}, {h}, {depth}]}}}}]
}})",
                     fmt::arg("spacing", spacing), fmt::arg("search", search), fmt::arg("lx", 4 * a),
                     fmt::arg("ly", 3 * a), fmt::arg("depth", depth), fmt::arg("a", a), fmt::arg("h", 2 * a));
}

int run_bench(const BenchOptions& opt) {
  const int hw = static_cast<int>(tbb::info::default_concurrency());
  std::vector<int> threads = opt.threads;
  if (threads.empty()) {
    threads.push_back(1);
    if (hw > 1) threads.push_back(hw);
  }
  fmt::print("bakesim bench: SPH dam break, {} steps per case, machine has {} hardware threads\n", opt.steps, hw);
  fmt::print("{:>10} {:>8} {:>8} {:>14} {:>12}\n", "particles", "search", "threads", "particle-steps/s", "ms/step");
  for (long n : opt.particles)
    for (const std::string& search : opt.searches)
      for (int t : threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(t));
        Scene scene = parse_scene(dam_break_scene_json(n, search), "bench", ".");
        auto solver = make_solver(scene);
        // Warm up so the column has started to move and caches are hot.
        for (int i = 0; i < 5; ++i) solver->step(solver->max_stable_dt());
        const PhaseTimers before = solver->timers();
        Stopwatch clock;
        for (int i = 0; i < opt.steps; ++i) solver->step(solver->max_stable_dt());
        const double secs = clock.seconds();
        const double rate = double(solver->particles().size()) * opt.steps / secs;
        fmt::print("{:>10} {:>8} {:>8} {:>14.0f} {:>12.2f}\n", solver->particles().size(), search, t, rate,
                   1e3 * secs / opt.steps);
        if (opt.phases) fmt::print("{}", solver->timers().since(before).report(opt.steps));
        std::fflush(stdout);
      }
  return 0;
}

}  // namespace bakesim
