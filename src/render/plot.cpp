#include "render/plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/errors.hpp"
#include "io/files.hpp"
#include "render/run_results.hpp"

namespace bakesim::render {

namespace fs = std::filesystem;
using Rgb = std::array<std::uint8_t, 3>;

std::vector<double> nice_ticks(double lo, double hi, int target) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
  if (!(hi > lo)) hi = lo + 1;
  // A span too small to step through at this magnitude (a run of a few
  // nanoseconds): widen it, so the steps are representable and the list is never empty.
  const double scale = std::max({std::abs(lo), std::abs(hi), 1e-300});
  if (!(hi - lo > 1e-9 * scale)) {
    const double w = std::max(1e-6 * scale, 1e-12);
    lo -= w;
    hi += w;
  }
  const double raw = (hi - lo) / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  if (ticks.empty()) ticks.push_back(lo);
  return ticks;
}

std::string tick_label(double v, double step) {
  // As many decimals as the step needs: 2.5 needs one (0, 2.5, 5, 7.5, not 0, 2, 5, 8).
  int decimals = std::max(0, int(-std::floor(std::log10(step) + 1e-9)));
  for (; decimals < 6; ++decimals) {
    const double scaled = step * std::pow(10.0, decimals);
    if (std::abs(scaled - std::round(scaled)) < 1e-6 * scaled) break;
  }
  const std::string label = fmt::format("{:.{}f}", v, decimals);
  return label.find_first_not_of("-0.") == std::string::npos ? label.substr(label[0] == '-') : label;  // no "-0"
}

namespace {

// Anti-aliased thick segment: coverage from the distance to the segment.
void segment(Image& img, double x0, double y0, double x1, double y1, double w, Rgb c) {
  const int xa = int(std::floor(std::min(x0, x1) - w)), xb = int(std::ceil(std::max(x0, x1) + w));
  const int ya = int(std::floor(std::min(y0, y1) - w)), yb = int(std::ceil(std::max(y0, y1) + w));
  const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
  for (int y = std::max(ya, 0); y <= std::min(yb, img.height - 1); ++y)
    for (int x = std::max(xa, 0); x <= std::min(xb, img.width - 1); ++x) {
      const double px = x + 0.5 - x0, py = y + 0.5 - y0;
      const double t = len2 > 0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0.0;
      const double d = std::hypot(px - t * dx, py - t * dy);
      const double cover = std::clamp(0.5 * w + 0.5 - d, 0.0, 1.0);
      if (cover > 0) img.blend(x, y, c, float(cover));
    }
}

void rect(Image& img, int x0, int y0, int x1, int y1, Rgb c) {
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) img.set(x, y, c);
}

constexpr Rgb kColours[] = {{31, 119, 180}, {214, 39, 40},   {44, 160, 44},   {255, 127, 14}, {148, 103, 189},
                            {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};

}  // namespace

std::array<std::uint8_t, 3> series_colour(std::size_t k) { return kColours[k % std::size(kColours)]; }

Image plot_lines(const PlotSpec& spec, const TextRenderer& text) {
  Image img(spec.width, spec.height);
  const Rgb black{0, 0, 0}, grey{225, 225, 225}, dark{90, 90, 90};
  const int left = 90, right = spec.width - 30, top = 50, bottom = spec.height - 70;
  double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo, ylo = xlo, yhi = -xlo;
  for (const Series& s : spec.series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        xlo = std::min(xlo, s.x[i]), xhi = std::max(xhi, s.x[i]);
        ylo = std::min(ylo, s.y[i]), yhi = std::max(yhi, s.y[i]);
      }
  if (!std::isfinite(xlo)) xlo = 0, xhi = 1, ylo = 0, yhi = 1;
  if (!(xhi > xlo)) xhi = xlo + 1;
  if (!(yhi > ylo)) ylo -= 0.5 * std::max(1.0, std::abs(ylo)), yhi += 0.5 * std::max(1.0, std::abs(yhi));
  const double pad = 0.05 * (yhi - ylo);
  ylo -= pad, yhi += pad;
  const auto xt = nice_ticks(xlo, xhi), yt = nice_ticks(ylo, yhi);
  xlo = std::min(xlo, xt.front()), xhi = std::max(xhi, xt.back());
  ylo = std::min(ylo, yt.front()), yhi = std::max(yhi, yt.back());
  auto X = [&](double x) { return left + (x - xlo) / (xhi - xlo) * (right - left); };
  auto Y = [&](double y) { return bottom - (y - ylo) / (yhi - ylo) * (bottom - top); };
  const float font = 15;
  for (double t : xt) {
    const int x = int(std::lround(X(t)));
    rect(img, x, top, x, bottom, grey);
    text.draw(img, x, bottom + 22, tick_label(t, xt.size() > 1 ? xt[1] - xt[0] : 1), font, dark, Align::centre);
  }
  for (double t : yt) {
    const int y = int(std::lround(Y(t)));
    rect(img, left, y, right, y, grey);
    text.draw(img, left - 8, y + 5, tick_label(t, yt.size() > 1 ? yt[1] - yt[0] : 1), font, dark, Align::right);
  }
  rect(img, left, bottom, right, bottom, black);
  rect(img, left, top, left, bottom, black);
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const Series& s = spec.series[k];
    const Rgb c = series_colour(k);
    double dash = 0;  // length drawn so far along a dashed line: 9 px on, 7 px off
    for (std::size_t i = 1; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i - 1] + s.y[i - 1] + s.x[i] + s.y[i])) continue;
      const double x0 = X(s.x[i - 1]), y0 = Y(s.y[i - 1]), x1 = X(s.x[i]), y1 = Y(s.y[i]);
      if (!s.dashed) {
        segment(img, x0, y0, x1, y1, 2.2, c);
        continue;
      }
      // A dashed segment is drawn in pieces of at most 1 px, each on or off by where it lies along the line.
      const double length = std::hypot(x1 - x0, y1 - y0);
      const int pieces = std::max(1, int(std::ceil(length)));
      for (int k = 0; k < pieces; ++k) {
        const double a = double(k) / pieces, b = double(k + 1) / pieces;
        if (std::fmod(dash + a * length, 16.0) < 9.0)
          segment(img, x0 + a * (x1 - x0), y0 + a * (y1 - y0), x0 + b * (x1 - x0), y0 + b * (y1 - y0), 2.2, c);
      }
      dash += length;
    }
    if (s.x.size() == 1 && std::isfinite(s.x[0] + s.y[0]))
      segment(img, X(s.x[0]), Y(s.y[0]), X(s.x[0]), Y(s.y[0]), 5, c);
  }
  // Legend, top-left inside the axes.
  int ly = top + 18;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const Rgb c = series_colour(k);
    if (spec.series[k].dashed)
      for (int d = 0; d < 3; ++d) segment(img, left + 14 + 10 * d, ly - 5, left + 20 + 10 * d, ly - 5, 3, c);
    else
      segment(img, left + 14, ly - 5, left + 40, ly - 5, 3, c);
    text.draw(img, left + 48, ly, spec.series[k].name, 14, black);
    ly += 20;
  }
  text.draw(img, (left + right) / 2, 32, spec.title, 20, black, Align::centre);
  text.draw(img, (left + right) / 2, spec.height - 22, spec.x_label, font + 1, black, Align::centre);
  text.draw_vertical(img, 26, (top + bottom) / 2, spec.y_label, font + 1, black);
  return img;
}

const std::vector<double>* Table::column(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return &columns[i];
  return nullptr;
}

Table read_csv(const fs::path& file) {
  std::string text = read_file(file);
  // A run appends a row per frame: a line without its newline is one a killed run did not finish.
  text.resize(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
  std::istringstream in(text);
  Table t;
  std::string line;
  if (!std::getline(in, line)) throw InputError(file.string(), "is empty");
  std::stringstream hs(line);
  std::string cell;
  while (std::getline(hs, cell, ',')) t.names.push_back(cell);
  t.columns.resize(t.names.size());
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ls(line);
    std::size_t k = 0;
    while (std::getline(ls, cell, ',') && k < t.columns.size()) {
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      t.columns[k++].push_back(end != cell.c_str() ? v : std::numeric_limits<double>::quiet_NaN());
    }
    for (; k < t.columns.size(); ++k) t.columns[k].push_back(std::numeric_limits<double>::quiet_NaN());
  }
  return t;
}

std::vector<fs::path> plot_run(const fs::path& run_dir) {
  const Table t = read_csv(run_dir / "stats.csv");
  const std::vector<double>* bake = t.column("bake_time");
  const std::vector<double>* sim = t.column("time");
  if (!bake && !sim) throw InputError((run_dir / "stats.csv").string(), "has no time or bake_time column");
  // Bake time in minutes when the bake clock runs, else simulated seconds.
  std::vector<double> x = bake ? *bake : *sim;
  std::string x_label = "bake time (min)";
  const bool minutes = bake && !x.empty() && x.back() > 120;
  if (minutes) {
    for (double& v : x) v /= 60.0;
  } else {
    x_label = bake ? "bake time (s)" : "time (s)";
  }
  const TextRenderer text;
  const fs::path dir = run_dir / "plots";
  ensure_directory(dir);
  std::vector<fs::path> written;
  auto emit = [&](const std::string& file, PlotSpec spec) {
    if (spec.series.empty()) return;
    spec.x_label = x_label;
    write_file_atomic(dir / file, encode_png(plot_lines(spec, text)));
    written.push_back(dir / file);
  };
  auto starts = [](const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; };
  auto ends = [](const std::string& s, const std::string& p) {
    return s.size() >= p.size() && s.compare(s.size() - p.size(), p.size(), p) == 0;
  };

  PlotSpec temps{"Temperatures", "", "temperature (°C)", {}};
  PlotSpec volume{"Volume (relative to the first frame)", "", "V / V0", {}};
  PlotSpec height{"Height", "", "height (cm)", {}};
  PlotSpec moisture{"Moisture loss", "", "moisture loss (%)", {}};
  for (std::size_t k = 0; k < t.names.size(); ++k) {
    const std::string& n = t.names[k];
    const std::vector<double>& col = t.columns[k];
    if (starts(n, "probe:") && ends(n, ":temperature")) {
      temps.series.push_back({"probe " + n.substr(6, n.size() - 6 - 12), x, col});
    } else if (starts(n, "core_temperature:") || starts(n, "crust_temperature:")) {
      const std::size_t colon = n.find(':');
      temps.series.push_back({n.substr(0, colon - 12) + " " + n.substr(colon + 1), x, col});
    } else if (starts(n, "volume:")) {
      std::vector<double> rel = col;
      const double v0 = col.empty() ? 1 : col.front();
      for (double& v : rel) v = v0 > 0 ? v / v0 : std::numeric_limits<double>::quiet_NaN();
      volume.series.push_back({n.substr(7), x, rel});
    } else if (starts(n, "height:")) {
      std::vector<double> cm = col;
      for (double& v : cm) v *= 100.0;
      height.series.push_back({n.substr(7), x, cm});
    } else if (starts(n, "moisture_loss_percent:")) {
      moisture.series.push_back({n.substr(22), x, col});
    }
  }
  if (!temps.series.empty()) {
    if (const auto* air = t.column("air_temperature")) temps.series.push_back({"oven air", x, *air, true});
    // The doneness line of the report and the sweep (render/run_results.hpp), where the run has a core.
    bool has_core = false;
    for (const auto& n : t.names) has_core = has_core || starts(n, "core_temperature:");
    if (has_core && !x.empty()) temps.series.push_back(doneness_series(x.front(), x.back(), done_core_degc(run_dir)));
  } else if (const auto* mean = t.column("mean_temperature")) {
    temps.series.push_back({"mean", x, *mean});
    if (const auto* mx = t.column("max_temperature")) temps.series.push_back({"max", x, *mx});
    if (const auto* air = t.column("air_temperature")) temps.series.push_back({"oven air", x, *air, true});
  }
  emit("temperatures.png", temps);
  emit("volume.png", volume);
  emit("height.png", height);
  emit("moisture.png", moisture);
  return written;
}

}  // namespace bakesim::render
