#pragma once
#include <string>
#include <vector>

namespace bakesim {

struct BenchOptions {
  std::vector<long> particles{50000, 200000};
  std::vector<int> threads;  // empty: 1 and all
  std::string solver = "sph";  // sph: dam break; mpm: cubes dropped on the floor
  std::vector<std::string> searches{"grid", "kdtree"};
  std::vector<std::string> models{"elastic", "viscoplastic"};  // MPM materials
  int steps = 50;
  bool phases = true;
};

// SPH dam break or MPM cube drop: particle-steps per second for each combination.
int run_bench(const BenchOptions& opt);

// The dam break of scenes/dam-break.json with a spacing chosen for about
// `particles` particles; used by the benchmark and the tests.
std::string dam_break_scene_json(long particles, const std::string& search);

// An MPM cube of about `particles` points (8 per cell) dropped onto a floor:
// model "elastic" (Hencky, E = 100 kPa) or "viscoplastic" (von Mises dough,
// yield 200 Pa, η 10 Pa·s, which slumps), or "cam_clay" (the same with porosity).
std::string mpm_cube_scene_json(long particles, const std::string& model);

}  // namespace bakesim
