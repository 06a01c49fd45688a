#pragma once
// What a bake did, read back from a run directory's stats.csv: the numbers
// the run's summary, `bakesim sweep`'s table and `bakesim report` show.
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "render/plot.hpp"

namespace bakesim::render {

// The core temperature at which a bake counts as done at sea level (bread
// crumb sets and is safe at 93-96 °C; the report draws it as the doneness line).
inline constexpr double kDoneCoreDegC = 95.0;
// Where the oven's air pressure lowers the boiling point (altitude), the
// moist crumb stops lower: done is 5 K below where free water boils there
// (88.4 °C at 2,000 m), never above kDoneCoreDegC.
double done_core_degc(double boiling_point);
// The level of a run's resolved scene (its scene.json): sea level unless its
// environment names an altitude or air pressure (io/scene.hpp).
double done_core_degc(const nlohmann::json& scene);
// The same read from a run directory's scene.json (sea level if it cannot be read).
double done_core_degc(const std::filesystem::path& run_dir);

// The doneness line of the plots at `level` °C from `from` to `to` (bake minutes), dashed.
Series doneness_series(double from, double to, double level);

struct BodyResults {
  std::string name;
  bool heated = false;                                // the run has core and crust columns for it
  double core_end = NAN, crust_end = NAN;             // °C
  double minutes_to_done = NAN;                       // bake minutes for the core to reach done_degc; NaN: never
  double volume_ratio = NAN;                          // last frame / first frame
  double height_start = NAN, height_end = NAN;        // m
  double moisture_loss_percent = NAN;                 // NaN: the run carries no water
  double crust_thickness = NAN;                       // m, at the end; NaN: no moisture
  double crust_moisture = NAN, crumb_moisture = NAN;  // kg/kg dry basis, at the end
};

struct RunResults {
  std::filesystem::path dir;
  std::string scene_name;
  int frames = 0;                   // rows of stats.csv
  double time_end = NAN;            // simulated s
  double bake_minutes = NAN;        // bake clock at the last frame
  double air_end = NAN;             // oven air at the last frame, °C
  double heat_in_kilojoules = NAN;  // heat in through the surfaces (stats.csv heat_in), kJ
  double wall_seconds = NAN;
  double done_degc = kDoneCoreDegC;  // the core temperature counted as done (done_core_degc)
  std::vector<BodyResults> bodies;
  std::vector<double> minutes;  // per stats.csv row: minutes of bake (simulated minutes without a bake clock)
  Table stats;                  // stats.csv as read
};

// InputError when there is no readable stats.csv.
RunResults read_run_results(const std::filesystem::path& run_dir);

// The first bake time (s) at which `values` reaches `level`, interpolated between rows; NaN when it never does.
double first_crossing(const std::vector<double>& bake_time, const std::vector<double>& values, double level);

}  // namespace bakesim::render
