#pragma once
// `bakesim report RUN_DIR [--compare measured.csv[=COLUMN] ...]`: one
// self-contained HTML page (no file or network it needs beside itself) with
// what the bake did: the key numbers per body (time for the core to reach
// 95 °C, final core and crust temperature, rise, height, moisture and weight
// loss, crust colour, heat in), pictures of the first and last frame and the last frame cut in half, SVG plots
// with units (temperatures with the doneness line, volume, height, moisture
// loss) with measured data overlaid, and the scene's summary.
//
// Measured data are CSV files with '#' comment lines and a header: a time
// column t_s / time_s (seconds) or t_min / time_min (minutes of bake), and
// value columns whose name ends in their unit: _C (°C, on the temperature
// plot), _m (a displacement of the top, on the height plot as the rise),
// moisture_db (dry-basis moisture, shown as the loss of water since the first
// row, %, on the moisture plot). Columns ending in _std_C / _std are error bars
// of the column before them. FILE=COLUMN compares the file's first value column
// with that stats.csv column (e.g. core_temperature:loaf, probe:centre:temperature)
// and reports the RMS and largest difference at the measured times.
#include <filesystem>
#include <string>
#include <vector>

namespace bakesim::render {

struct ReportOptions {
  std::vector<std::string> compare;  // FILE or FILE=STATS_COLUMN
  std::filesystem::path output;      // default RUN_DIR/report.html
  std::string generator = "bakesim";
  bool draw_pictures = true;  // render the first and last frame and the cut view when render/ has no picture of them
};

struct ReportResult {
  std::filesystem::path file;
  std::vector<std::string> notes;  // what could not be included, and why
};

ReportResult write_report(const std::filesystem::path& run_dir, const ReportOptions& options);

}  // namespace bakesim::render
