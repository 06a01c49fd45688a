#pragma once
// `bakesim sweep SCENE --set KEY=V1,V2,... [--set ...]`: runs the scene once
// per point of the grid, several at a time, each as a `bakesim run` command of
// its own in DIR/runs/NN-LABEL/ (a task on a Dask cluster, or a process here), and writes the comparison table and plots
// (render/sweep_outputs.hpp). Running the same sweep again skips the runs
// that finished and resumes those that were stopped.
#include <string>
#include <vector>

namespace bakesim {

struct SweepArgs {
  std::string scene;
  std::string out;                // default out/NAME-sweep
  std::vector<std::string> sets;  // KEY.PATH=V1,V2,...
  int jobs = 0;                   // runs at a time (default: as many as cores, at most the runs)
  int threads = 0;                // threads per run (default: the cores shared among the jobs)
  double end_time = -1;
  bool quiet = false;
  bool preview = false;  // every run as run --preview
  // Where the runs go: "" (a Dask LocalCluster when python3-distributed and the
  // Python module are installed, else processes here), "local", or a Dask
  // scheduler's address (an error when Dask cannot be reached).
  std::string dask;
  bool processes = false;  // every run a `bakesim run` process here, without Dask
};

// Returns the exit code: 0 when every run finished, 1 when one failed, 128+N when stopped by signal N.
int command_sweep(const SweepArgs& args, const std::string& self_executable);

}  // namespace bakesim
