#pragma once
#include <string>
#include <vector>

namespace bakesim {

struct BenchOptions {
  std::vector<long> particles{50000, 200000};
  std::vector<int> threads;  // empty: 1 and all
  std::vector<std::string> searches{"grid", "kdtree"};
  int steps = 50;
  bool phases = true;
};

// Dam-break SPH benchmark: particle-steps per second for each combination.
int run_bench(const BenchOptions& opt);

// The dam break of scenes/dam-break.json with a spacing chosen for about
// `particles` particles; used by the benchmark and the tests.
std::string dam_break_scene_json(long particles, const std::string& search);

}  // namespace bakesim
