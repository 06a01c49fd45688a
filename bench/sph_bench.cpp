// Neighbour search (grid vs kd-tree) and a whole SPH step on a block of water.
// Run: ./build/bench/bakesim_microbench [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <nlohmann/json.hpp>

#include "io/scene.hpp"
#include "sph/solver.hpp"

using namespace bakesim;

namespace {

nlohmann::json block(long particles, const std::string& search) {
  const double side = 0.2, spacing = side / std::cbrt(double(particles));
  return {{"solver", {{"type", "sph"}, {"sph", {{"spacing", spacing}, {"neighbour_search", search}}}}},
          {"time", {{"end", 1.0}}},
          {"domain", {{"min", {0, 0, 0}}, {"max", {side, 2 * side, side}}}},
          {"materials", {{"water", {{"density", 1000.0}, {"xsph", 0.1}}}}},
          {"bodies",
           {{{"name", "block"},
             {"material", "water"},
             {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {side, side, side}}}}}}}};
}

std::unique_ptr<sph::SphSolver> make(long particles, const std::string& search) {
  Scene scene = parse_scene(block(particles, search).dump(), "bench", ".");
  return std::make_unique<sph::SphSolver>(scene.sph);
}

void neighbour_search(benchmark::State& state, sph::NeighbourMethod method) {
  auto solver = make(state.range(0), to_string(method));
  const auto& x = solver->particles().vector("position");
  const Aabb domain = solver->setup().domain;
  sph::NeighbourSearch search(method, domain, solver->support());
  std::vector<std::uint32_t> order;
  search.sort_order(x, order);
  sph::NeighbourLists lists;
  for (auto _ : state) {
    search.find(x, lists);
    benchmark::DoNotOptimize(lists.mean_count());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_NeighboursGrid(benchmark::State& s) { neighbour_search(s, sph::NeighbourMethod::grid); }
void BM_NeighboursKdTree(benchmark::State& s) { neighbour_search(s, sph::NeighbourMethod::kdtree); }

// Items are particle-steps.
void BM_SphStep(benchmark::State& state) {
  auto solver = make(state.range(0), "grid");
  for (auto _ : state) solver->step(solver->max_stable_dt());
  state.SetItemsProcessed(state.iterations() * static_cast<long>(solver->particles().size()));
}

}  // namespace

BENCHMARK(BM_NeighboursGrid)->Arg(50000)->Arg(200000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NeighboursKdTree)->Arg(50000)->Arg(200000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SphStep)->Arg(50000)->Arg(200000)->Unit(benchmark::kMillisecond);
