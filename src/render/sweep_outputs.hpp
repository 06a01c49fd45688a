#pragma once
// What `bakesim sweep` writes once its runs have ended, into the sweep directory:
//   sweep.csv       one row per run: the swept values, the run's status and its
//                   bake results (render/run_results.hpp), units in the names
//   sweep.md        the same as a Markdown table (also printed)
//   plots/*.png     every run's core temperature, volume, height and moisture
//                   loss against bake time, one line per run
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/sweep.hpp"
#include "render/run_results.hpp"

namespace bakesim::render {

struct SweepRun {
  SweepPoint point;
  std::string status;                 // "done", "failed (exit 3)", "stopped", ...
  std::optional<RunResults> results;  // read from its run directory when it has a stats.csv
};

struct SweepOutputs {
  std::filesystem::path csv, markdown;
  std::vector<std::filesystem::path> plots;
  std::string table;  // the Markdown table
};

SweepOutputs write_sweep_outputs(const std::filesystem::path& dir, const std::vector<SweepAxis>& axes,
                                 const std::vector<SweepRun>& runs);

}  // namespace bakesim::render
