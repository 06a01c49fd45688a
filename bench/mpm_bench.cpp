// A whole MPM step on a cube squashed against the floor (elastic and von
// Mises viscoplastic, and the full thermomechanical dough baking on a hot
// floor), with the time per phase reported as counters.
// Run: ./build/bench/bakesim_microbench --benchmark_filter=Mpm
// (threads: TBB's default; limit with taskset or the `bakesim bench --threads`).
#include <benchmark/benchmark.h>

#include "io/bench_scenes.hpp"
#include "io/scene.hpp"
#include "mpm/solver.hpp"

using namespace bakesim;

namespace {

void mpm_step(benchmark::State& state, const char* model) {
  Scene scene = parse_scene(mpm_cube_scene_json(state.range(0), model), "bench", ".");
  mpm::MpmSolver solver(scene.mpm);
  for (int i = 0; i < 3; ++i) solver.step(solver.max_stable_dt());  // warm up
  const PhaseTimers before = solver.timers();
  for (auto _ : state) solver.step(solver.max_stable_dt());
  const PhaseTimers spent = solver.timers().since(before);
  const double steps = double(state.iterations());
  for (std::size_t k = 0; k < spent.names().size(); ++k)
    state.counters[spent.names()[k] + "_ms"] = 1e3 * spent.seconds()[k] / steps;
  state.SetItemsProcessed(state.iterations() * static_cast<long>(solver.particles().size()));
}

void BM_MpmStepElastic(benchmark::State& s) { mpm_step(s, "elastic"); }
void BM_MpmStepViscoplastic(benchmark::State& s) { mpm_step(s, "viscoplastic"); }
void BM_MpmStepFullModel(benchmark::State& s) { mpm_step(s, "full"); }

}  // namespace

BENCHMARK(BM_MpmStepElastic)->Arg(100000)->Arg(500000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MpmStepViscoplastic)->Arg(100000)->Arg(500000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MpmStepFullModel)->Arg(200000)->Arg(600000)->Unit(benchmark::kMillisecond);
