#pragma once
#include <string>
#include <vector>

#include "sph/setup.hpp"

namespace bakesim {

struct BenchOptions {
  std::vector<long> particles{50000, 200000};
  std::vector<int> threads;    // empty: 1 and all
  std::string solver = "sph";  // sph: dam break; mpm: cubes dropped on the floor
  std::vector<std::string> searches{"grid", "kdtree"};
  std::vector<double> skins{sph::Settings{}.neighbour_skin};   // SPH Verlet skins, fractions of h
  std::vector<std::string> models{"elastic", "viscoplastic"};  // MPM materials
  int steps = 50;
  bool phases = true;
  // A scene file instead (--scene): its whole run (or to end_time) per thread count, no output written.
  std::string scene;
  std::vector<std::string> sets;  // --set KEY.PATH=VALUE overrides
  bool preview = false;
  double end_time = 0;  // simulated seconds; 0: the scene's end
};

// SPH dam break or MPM cube drop: particle-steps per second for each combination;
// with opt.scene, that scene's run to its end, per thread count.
int run_bench(const BenchOptions& opt);

}  // namespace bakesim
