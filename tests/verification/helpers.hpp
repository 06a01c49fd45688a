#pragma once
// Shared helpers for verification tests: build scenes from JSON text and
// step solvers to a given time.
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/scene.hpp"
#include "sph/solver.hpp"

namespace bakesim::test_support {

inline std::unique_ptr<sph::SphSolver> make_sph(const nlohmann::json& doc) {
  Scene scene = parse_scene(doc.dump(), "test-scene.json", ".");
  return std::make_unique<sph::SphSolver>(scene.sph);
}

inline std::unique_ptr<mpm::MpmSolver> make_mpm(const nlohmann::json& doc) {
  Scene scene = parse_scene(doc.dump(), "test-scene.json", ".");
  return std::make_unique<mpm::MpmSolver>(scene.mpm);
}

// Steps with the solver's stable dt, landing exactly on t_end.
template <class OnStep>
inline void advance_to(Solver& s, double t_end, OnStep&& on_step) {
  while (s.time() < t_end - 1e-12) {
    double dt = std::min(s.max_stable_dt(), t_end - s.time());
    s.step(dt);
    on_step();
  }
}
inline void advance_to(Solver& s, double t_end) {
  advance_to(s, t_end, [] {});
}

// Reads a CSV with '#' comment lines and a header; returns rows of numbers.
inline std::vector<std::vector<double>> read_csv(const std::string& path, std::vector<std::string>* header = nullptr) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  bool have_header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (!have_header) {
      have_header = true;
      if (header) *header = cells;
      continue;
    }
    std::vector<double> row;
    for (const auto& c : cells) row.push_back(std::stod(c));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace bakesim::test_support
