#pragma once
// Parameter sweeps: `bakesim sweep SCENE --set KEY=V1,V2,... [--set ...]`
// runs the scene once per point of the grid the lists span (their Cartesian
// product; a --set with one value applies to every run). This file expands the
// grid; the command line runs the points (app/sweep.cpp) and render/ tabulates
// and plots their results.
#include <string>
#include <vector>

namespace bakesim {

struct SweepAxis {
  std::string path;                 // "environment.air_temperature"
  std::vector<std::string> values;  // each a JSON value or a plain word, as typed
};

// "KEY.PATH=V1,V2,..." split at the commas outside brackets, braces and
// quotes, so a list or a schedule is one value: bodies[0].shape.center=[0,0.1,0],[0,0.2,0].
// InputError("--set", ...) without "=", with an empty value or more than 1000 values.
SweepAxis parse_sweep_axis(const std::string& text);

struct SweepPoint {
  std::string label;                // "air_temperature=150,rate=5e-07": the axes with more than one value
  std::string directory;            // "01-air_temperature=150_rate=5e-07": safe as one path component
  std::vector<std::string> sets;    // "KEY.PATH=VALUE" for `run --set`, every axis
  std::vector<std::string> values;  // per axis, the value of this point
};

// Every point of the grid, the first axis varying slowest. InputError when the
// grid has more than `max_points` points.
std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, std::size_t max_points = 10000);

// A short name for each axis in labels and tables: its last key ("air_temperature"),
// or the whole path where two axes share a last key.
std::vector<std::string> axis_names(const std::vector<SweepAxis>& axes);

}  // namespace bakesim
