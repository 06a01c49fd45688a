#include "render/sweep_outputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/files.hpp"

namespace bakesim::render {

namespace fs = std::filesystem;

namespace {

std::string cell(double v, int decimals) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, decimals) : ""; }

// A value of a CSV row: quoted when it holds a comma or a quote.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

// One numeric result per body and run, as the table and the plots show it.
struct Measure {
  const char* csv_name;  // "core_degC"
  const char* md_name;   // "core °C"
  int decimals;
  double (*get)(const BodyResults&);
};

const Measure kMeasures[] = {
    {"core_degC", "core °C", 1, [](const BodyResults& b) { return b.core_end; }},
    {"crust_degC", "crust °C", 1, [](const BodyResults& b) { return b.crust_end; }},
    {"minutes_to_done", "core done at (min)", 1, [](const BodyResults& b) { return b.minutes_to_done; }},
    {"volume_ratio", "volume ×", 2, [](const BodyResults& b) { return b.volume_ratio; }},
    {"height_cm", "height cm", 2, [](const BodyResults& b) { return b.height_end * 100; }},
    {"moisture_loss_percent", "moisture loss %", 1, [](const BodyResults& b) { return b.moisture_loss_percent; }},
};

}  // namespace

SweepOutputs write_sweep_outputs(const fs::path& dir, const std::vector<SweepAxis>& axes,
                                 const std::vector<SweepRun>& runs) {
  // The bodies of all runs, in the order first seen (a sweep normally keeps them).
  std::vector<std::string> bodies;
  for (const auto& r : runs)
    if (r.results)
      for (const auto& b : r.results->bodies)
        if (std::find(bodies.begin(), bodies.end(), b.name) == bodies.end()) bodies.push_back(b.name);
  // Measures no run has a number for (no water: no moisture loss) are left out.
  std::vector<const Measure*> measures;
  for (const Measure& m : kMeasures) {
    bool any = false;
    for (const auto& r : runs)
      if (r.results)
        for (const auto& b : r.results->bodies) any = any || std::isfinite(m.get(b));
    if (any) measures.push_back(&m);
  }
  const std::vector<std::string> names = axis_names(axes);
  auto body_of = [](const RunResults& r, const std::string& name) -> const BodyResults* {
    for (const auto& b : r.bodies)
      if (b.name == name) return &b;
    return nullptr;
  };

  bool any_heat = false;
  for (const auto& r : runs) any_heat = any_heat || (r.results && std::isfinite(r.results->heat_in_kilojoules));
  std::string csv = "run";
  std::string md_head = "| run";
  // The Markdown table leaves out the axes with one value (the same in every run).
  for (std::size_t k = 0; k < names.size(); ++k) {
    csv += "," + csv_field(names[k]);
    if (axes[k].values.size() > 1) md_head += " | " + names[k];
  }
  csv += ",status,bake_minutes";
  md_head += " | status | bake min";
  for (const auto& b : bodies)
    for (const Measure* m : measures) {
      csv += "," + csv_field(fmt::format("{}:{}", m->csv_name, b));
      md_head += bodies.size() > 1 ? fmt::format(" | {} {}", b, m->md_name) : fmt::format(" | {}", m->md_name);
    }
  csv += ",heat_in_kJ,wall_seconds,directory\n";
  md_head += std::string(any_heat ? " | heat in kJ" : "") + " | wall s |\n";
  std::string md_rule = "|";
  for (std::size_t k = 0, n = std::count(md_head.begin(), md_head.end(), '|') - 1; k < n; ++k) md_rule += "---|";
  std::string md = md_head + md_rule + "\n";
  for (const auto& r : runs) {
    csv += csv_field(r.point.label);
    md += "| " + r.point.label;
    for (std::size_t k = 0; k < r.point.values.size(); ++k) {
      csv += "," + csv_field(r.point.values[k]);
      if (axes[k].values.size() > 1) md += " | " + r.point.values[k];
    }
    const RunResults* res = r.results ? &*r.results : nullptr;
    csv += "," + csv_field(r.status) + "," + (res ? cell(res->bake_minutes, 2) : "");
    md += " | " + r.status + " | " + (res ? cell(res->bake_minutes, 1) : "");
    for (const auto& b : bodies) {
      const BodyResults* body = res ? body_of(*res, b) : nullptr;
      for (const Measure* m : measures) {
        const std::string v = body ? cell(m->get(*body), m->decimals + 1) : "";
        csv += "," + v;
        md += " | " + (body ? cell(m->get(*body), m->decimals) : "");
        if (body && m->get == kMeasures[2].get && !std::isfinite(m->get(*body)) && body->heated) md += "not reached";
      }
    }
    csv += "," + (res ? cell(res->heat_in_kilojoules, 2) : "") + "," + (res ? cell(res->wall_seconds, 1) : "") + "," +
           csv_field((fs::path("runs") / r.point.directory).string()) + "\n";
    if (any_heat) md += " | " + (res ? cell(res->heat_in_kilojoules, 1) : "");
    md += " | " + (res ? cell(res->wall_seconds, 0) : "") + " |\n";
  }
  // What "done" meant: the core at 95 °C, lower where the air's pressure lowers the boiling point.
  bool off_sea_level = false;
  for (const auto& r : runs) off_sea_level = off_sea_level || (r.results && r.results->done_degc != kDoneCoreDegC);
  if (any_heat)
    md += fmt::format(
        "\nDone: the core at {:g} °C{}.\n", kDoneCoreDegC,
        off_sea_level ? ", or 5 K below where water boils at the run's air pressure where that is lower" : "");
  SweepOutputs out;
  out.csv = dir / "sweep.csv";
  out.markdown = dir / "sweep.md";
  out.table = md;
  write_file_atomic(out.csv, csv);
  write_file_atomic(out.markdown, md);

  // Plots: one line per run (and body), against bake minutes.
  struct PlotKind {
    const char* file;
    const char* title;
    const char* y_label;
    const char* prefix;
    bool relative;
    double scale;
  };
  const PlotKind kinds[] = {
      {"core_temperature.png", "Core temperature", "temperature (°C)", "core_temperature:", false, 1},
      {"crust_temperature.png", "Crust temperature", "temperature (°C)", "crust_temperature:", false, 1},
      {"volume.png", "Volume (relative to the first frame)", "V / V0", "volume:", true, 1},
      {"height.png", "Height", "height (cm)", "height:", false, 100},
      {"moisture.png", "Moisture loss", "moisture loss (%)", "moisture_loss_percent:", false, 1},
  };
  const TextRenderer text;
  const fs::path plots = dir / "plots";
  for (const PlotKind& k : kinds) {
    PlotSpec spec{k.title, "bake time (min)", k.y_label, {}};
    for (const auto& r : runs) {
      if (!r.results) continue;
      const Table& t = r.results->stats;
      const std::vector<double>& x = r.results->minutes;
      for (const auto& b : bodies) {
        const auto* col = t.column(k.prefix + b);
        if (!col || col->empty()) continue;
        std::vector<double> y = *col;
        const double y0 = y.front();
        for (double& v : y) v = k.relative ? (y0 > 0 ? v / y0 : NAN) : v * k.scale;
        spec.series.push_back({bodies.size() > 1 ? r.point.label + " " + b : r.point.label, x, y});
      }
    }
    if (spec.series.empty()) continue;
    if (k.prefix == std::string("core_temperature:")) {
      // The doneness line across the plot's time span.
      double end = 0;
      for (const auto& s : spec.series)
        if (!s.x.empty()) end = std::max(end, s.x.back());
      std::vector<double> levels;  // one line per level the runs are done at (altitudes differ)
      for (const auto& r : runs)
        if (r.results && std::find(levels.begin(), levels.end(), r.results->done_degc) == levels.end())
          levels.push_back(r.results->done_degc);
      for (const double level : levels) spec.series.push_back(doneness_series(0, end, level));
    }
    ensure_directory(plots);
    write_file_atomic(plots / k.file, encode_png(plot_lines(spec, text)));
    out.plots.push_back(plots / k.file);
  }
  return out;
}

}  // namespace bakesim::render
