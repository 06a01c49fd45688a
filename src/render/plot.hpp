#pragma once
// Line plots as PNG images, and `bakesim plot RUN_DIR`: stats.csv turned into
// plots/temperatures.png (probe, core and crust temperatures and the oven air
// against bake time), plots/volume.png (volume of each body relative to its
// first frame), plots/height.png and, for runs that carry water,
// plots/moisture.png (moisture loss %).
#include <filesystem>
#include <string>
#include <vector>

#include "io/image.hpp"
#include "render/text.hpp"

namespace bakesim::render {

struct Series {
  std::string name;
  std::vector<double> x, y;  // NaN values break the line
  bool dashed = false;
};

struct PlotSpec {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  int width = 960, height = 600;
};

Image plot_lines(const PlotSpec& spec, const TextRenderer& text);
// The colour of the k-th series (the PNG plots, the report's SVG plots): a ten-colour palette, repeating.
std::array<std::uint8_t, 3> series_colour(std::size_t k);

// "Nice" tick values covering [lo, hi] (1, 2 or 5 times a power of ten apart).
std::vector<double> nice_ticks(double lo, double hi, int target_count = 6);
// A tick's label with the decimals its step needs.
std::string tick_label(double value, double step);

// A CSV table: header names and columns of numbers (non-numbers become NaN).
struct Table {
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  const std::vector<double>* column(const std::string& name) const;
};
Table read_csv(const std::filesystem::path& file);  // InputError naming the file and line

// Writes the run's plots; returns the files written.
std::vector<std::filesystem::path> plot_run(const std::filesystem::path& run_dir);

}  // namespace bakesim::render
