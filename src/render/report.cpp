#include "render/report.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "core/errors.hpp"
#include "io/files.hpp"
#include "io/run_meshes.hpp"
#include "io/scene.hpp"
#include "physics/oven.hpp"
#include "render/run_pictures.hpp"
#include "render/run_results.hpp"

namespace bakesim::render {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string base64(std::string_view bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t a = std::uint8_t(bytes[i]);
    const std::uint32_t b = i + 1 < bytes.size() ? std::uint8_t(bytes[i + 1]) : 0;
    const std::uint32_t c = i + 2 < bytes.size() ? std::uint8_t(bytes[i + 2]) : 0;
    const std::uint32_t v = (a << 16) | (b << 8) | c;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? table[v & 63] : '=';
  }
  return out;
}

std::string escape(const std::string& s) {
  std::string out;
  for (const unsigned char ch : s) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch < 0x20 && ch != '\n' && ch != '\t' ? ' ' : char(ch);
    }
  }
  return out;
}

std::string number(double v, int decimals) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, decimals) : "–"; }

// ---- measured data ----------------------------------------------------------

enum class Quantity { temperature, rise, moisture_loss, other };

struct MeasuredColumn {
  std::string name;
  Quantity quantity = Quantity::other;
  std::vector<double> values;  // in the plot's unit: °C, cm of rise, % of the water lost
  std::vector<double> spread;  // error bars (same unit), empty when none
  double spread_scale = 1;     // from the file's unit to the plot's, for the error bars
};

struct Measured {
  std::string label;            // the file's name
  std::vector<double> minutes;  // bake time
  std::vector<MeasuredColumn> columns;
  std::string compare_with;  // a stats.csv column, or ""
};

Measured read_measured(const std::string& spec) {
  const std::size_t eq = spec.rfind('=');
  Measured m;
  const fs::path file = eq == std::string::npos ? fs::path(spec) : fs::path(spec.substr(0, eq));
  if (eq != std::string::npos) m.compare_with = spec.substr(eq + 1);
  m.label = file.filename().string();
  const std::string where = "--compare " + file.string();
  const std::string text = read_file(file, std::uintmax_t(64) << 20);
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    std::vector<double> row;
    for (const auto& c : cells) {
      char* end = nullptr;
      const double v = std::strtod(c.c_str(), &end);
      row.push_back(end != c.c_str() && *end == '\0' ? v : kNaN);
    }
    row.resize(header.size(), kNaN);
    rows.push_back(std::move(row));
  }
  if (header.empty() || rows.empty()) throw InputError(where, "has no header and rows of numbers");
  double to_minutes = 0;
  std::size_t time_col = 0;
  for (std::size_t k = 0; k < header.size() && to_minutes == 0; ++k) {
    if (header[k] == "t_min" || header[k] == "time_min") to_minutes = 1, time_col = k;
    if (header[k] == "t_s" || header[k] == "time_s") to_minutes = 1.0 / 60, time_col = k;
  }
  if (to_minutes == 0)
    throw InputError(where, "needs a time column: t_s or time_s (seconds), t_min or time_min (minutes); it has " +
                                fmt::format("{}", fmt::join(header, ", ")));
  for (const auto& r : rows) m.minutes.push_back(r[time_col] * to_minutes);
  for (std::size_t k = 0; k < header.size(); ++k) {
    if (k == time_col) continue;
    const std::string& n = header[k];
    std::vector<double> values;
    for (const auto& r : rows) values.push_back(r[k]);
    if (n.find("_std") != std::string::npos) {  // error bars of the column before it, in its plot unit
      if (!m.columns.empty() && m.columns.back().spread.empty())
        for (const double v : values) m.columns.back().spread.push_back(v * m.columns.back().spread_scale);
      continue;
    }
    MeasuredColumn c{n, Quantity::other, values, {}};
    if (n.ends_with("_C")) {
      c.quantity = Quantity::temperature;
    } else if (n.ends_with("_m")) {
      c.quantity = Quantity::rise;
      c.spread_scale = 100;  // cm
      for (double& v : c.values) v *= c.spread_scale;
    } else if (n.find("moisture_db") != std::string::npos) {
      c.quantity = Quantity::moisture_loss;  // % of the first row's water lost
      const double x0 = c.values.front();
      c.spread_scale = x0 > 0 ? 100 / x0 : kNaN;
      for (double& v : c.values) v = x0 > 0 ? 100 * (1 - v / x0) : kNaN;
    }
    m.columns.push_back(std::move(c));
  }
  if (m.columns.empty()) throw InputError(where, "has no value column beside its time column");
  return m;
}

// The value of (x, y) samples at x, interpolated linearly; NaN outside them.
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  for (std::size_t i = 1; i < x.size() && i < y.size(); ++i)
    if (at >= x[i - 1] && at <= x[i] && x[i] > x[i - 1])
      return y[i - 1] + (at - x[i - 1]) / (x[i] - x[i - 1]) * (y[i] - y[i - 1]);
  if (!x.empty() && at == x.front()) return y.front();
  return kNaN;
}

// ---- SVG plots ----------------------------------------------------------------

struct SvgSeries {
  std::string name;
  std::vector<double> x = {}, y = {}, spread = {};
  bool dashed = false, markers = false;
  std::string colour = {};  // "" picks the next of the plots' palette (series_colour)
};

struct SvgPlot {
  std::string id, title, x_label, y_label;
  std::vector<SvgSeries> series;
};

std::string svg_plot(const SvgPlot& p) {
  const int width = 760, height = 400, left = 70, right = width - 20, top = 40, bottom = height - 55;
  double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
  for (const auto& s : p.series)
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        const double e = i < s.spread.size() && std::isfinite(s.spread[i]) ? s.spread[i] : 0;
        xlo = std::min(xlo, s.x[i]), xhi = std::max(xhi, s.x[i]);
        ylo = std::min(ylo, s.y[i] - e), yhi = std::max(yhi, s.y[i] + e);
      }
  if (!std::isfinite(xlo)) xlo = 0, xhi = 1, ylo = 0, yhi = 1;
  if (!(xhi > xlo)) xhi = xlo + 1;
  if (!(yhi > ylo)) ylo -= 0.5 * std::max(1.0, std::abs(ylo)), yhi += 0.5 * std::max(1.0, std::abs(yhi));
  const auto xt = nice_ticks(xlo, xhi), yt = nice_ticks(ylo - 0.03 * (yhi - ylo), yhi + 0.03 * (yhi - ylo));
  xlo = std::min(xlo, xt.front()), xhi = std::max(xhi, xt.back());
  ylo = std::min(ylo, yt.front()), yhi = std::max(yhi, yt.back());
  auto X = [&](double x) { return left + (x - xlo) / (xhi - xlo) * (right - left); };
  auto Y = [&](double y) { return bottom - (y - ylo) / (yhi - ylo) * (bottom - top); };
  std::string s = fmt::format(
      "<svg id=\"{}\" class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {} {}\" width=\"{}\" "
      "height=\"{}\" role=\"img\" aria-label=\"{}\">\n",
      p.id, width, height, width, height, escape(p.title));
  s += fmt::format("<text x=\"{}\" y=\"24\" class=\"title\" text-anchor=\"middle\">{}</text>\n", (left + right) / 2,
                   escape(p.title));
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1, ystep = yt.size() > 1 ? yt[1] - yt[0] : 1;
  for (double t : xt)
    s += fmt::format(
        "<line class=\"grid\" x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\"/><text x=\"{0:.1f}\" y=\"{3}\" "
        "text-anchor=\"middle\" class=\"tick\">{4}</text>\n",
        X(t), top, bottom, bottom + 18, tick_label(t, xstep));
  for (double t : yt)
    s += fmt::format(
        "<line class=\"grid\" x1=\"{0}\" y1=\"{2:.1f}\" x2=\"{1}\" y2=\"{2:.1f}\"/><text x=\"{3}\" y=\"{4:.1f}\" "
        "text-anchor=\"end\" class=\"tick\">{5}</text>\n",
        left, right, Y(t), left - 6, Y(t) + 4, tick_label(t, ystep));
  s += fmt::format("<line class=\"axis\" x1=\"{0}\" y1=\"{2}\" x2=\"{1}\" y2=\"{2}\"/>", left, right, bottom);
  s += fmt::format("<line class=\"axis\" x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\"/>\n", left, top, bottom);
  s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" class=\"label\">{}</text>\n", (left + right) / 2,
                   height - 14, escape(p.x_label));
  s += fmt::format(
      "<text x=\"16\" y=\"{0}\" text-anchor=\"middle\" class=\"label\" transform=\"rotate(-90 16 {0})\">{1}</text>\n",
      (top + bottom) / 2, escape(p.y_label));
  std::size_t colour_index = 0;
  int legend_y = top + 14;
  for (const auto& series : p.series) {
    const auto rgb = series_colour(colour_index);
    const std::string colour =
        series.colour.empty() ? fmt::format("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]) : series.colour;
    if (series.colour.empty()) ++colour_index;
    std::string g = fmt::format("<g class=\"series\" data-name=\"{}\">", escape(series.name));
    if (series.markers) {
      for (std::size_t i = 0; i < series.x.size() && i < series.y.size(); ++i) {
        if (!std::isfinite(series.x[i]) || !std::isfinite(series.y[i])) continue;
        if (i < series.spread.size() && std::isfinite(series.spread[i]) && series.spread[i] > 0)
          g +=
              fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" stroke=\"{3}\"/>",
                          X(series.x[i]), Y(series.y[i] - series.spread[i]), Y(series.y[i] + series.spread[i]), colour);
        g += fmt::format(
            "<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"/>",
            X(series.x[i]), Y(series.y[i]), colour);
      }
    } else {
      std::string points;
      auto flush = [&] {
        if (!points.empty())
          g += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"2\"{} points=\"{}\"/>", colour,
                           series.dashed ? " stroke-dasharray=\"7 5\"" : "", points);
        points.clear();
      };
      for (std::size_t i = 0; i < series.x.size() && i < series.y.size(); ++i) {
        if (!std::isfinite(series.x[i]) || !std::isfinite(series.y[i])) {
          flush();
          continue;
        }
        points += fmt::format("{:.1f},{:.1f} ", X(series.x[i]), Y(series.y[i]));
      }
      flush();
    }
    g += "</g>\n";
    s += g;
    // Legend, top left inside the axes.
    if (series.markers)
      s += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"3.5\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"/>",
                       left + 24, legend_y - 4, colour);
    else
      s +=
          fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\" stroke-width=\"2.5\"{}/>", left + 12,
                      legend_y - 4, left + 36, legend_y - 4, colour, series.dashed ? " stroke-dasharray=\"7 5\"" : "");
    s += fmt::format("<text x=\"{}\" y=\"{}\" class=\"legend\">{}</text>\n", left + 42, legend_y, escape(series.name));
    legend_y += 17;
  }
  s += "</svg>\n";
  return s;
}

// ---- the page -----------------------------------------------------------------

std::string scene_oven(const json& env) {
  const json& air = env["air_temperature"];
  if (air.is_number()) return fmt::format("{:g} °C", air.get<double>());
  std::string out;
  for (const auto& p : air)
    out += fmt::format("{}{:g} °C at {:g} min", out.empty() ? "" : ", ", p[1].get<double>(), p[0].get<double>() / 60);
  return out;
}

const char* colour_name(double browning) {
  if (browning < 0.15) return "raw / pale";
  if (browning < 0.35) return "pale golden";
  if (browning < 0.55) return "golden brown";
  if (browning < 0.75) return "brown";
  return "dark brown";
}

struct CrustColour {
  double browning = kNaN;  // area-weighted mean over the drawn surface, [0, 1]
  std::string hex;
};

// The surface as the pictures draw it: the mesh of the frame coloured by browning, its mean over the area.
std::optional<CrustColour> crust_colour(const fs::path& ply, const json& scene, std::vector<std::string>& notes) {
  try {
    const ParticleSet ps = read_particle_frame(ply);
    if (!ps.has("browning")) return std::nullopt;
    MeshSettings settings;
    settings.colour = "browning";
    const surface::SurfaceMesh mesh = frame_mesh(ps, run_geometry(scene), settings);
    // Foods with their own raw colours (chocolate, fruit) are shown browned from their mean raw colour.
    const bool own_colours = mesh.raw_colour.size() == mesh.vertices.size();
    double area = 0, weighted = 0;
    Vec3 raw_sum = Vec3::Zero();
    for (const auto& t : mesh.triangles) {
      const Vec3 a = mesh.vertices[t[0]].cast<Real>(), b = mesh.vertices[t[1]].cast<Real>(),
                 c = mesh.vertices[t[2]].cast<Real>();
      const double A = 0.5 * (b - a).cross(c - a).norm();
      area += A;
      weighted += A * (mesh.uv[t[0]] + mesh.uv[t[1]] + mesh.uv[t[2]]) / 3.0;
      if (own_colours)
        for (const auto k : t)
          raw_sum += A / 3.0 * Vec3(mesh.raw_colour[k].L, mesh.raw_colour[k].a, mesh.raw_colour[k].b);
    }
    if (!(area > 0)) return std::nullopt;
    CrustColour cc;
    cc.browning = surface::value_of_colour_coordinate(weighted / area);
    const Vec3 raw = raw_sum / area;
    const auto rgb = own_colours ? surface::baking_colour({raw.x(), raw.y(), raw.z()}, cc.browning)
                                 : surface::palette_colour(surface::Palette::baking, cc.browning);
    cc.hex = fmt::format("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]);
    return cc;
  } catch (const std::exception& e) {
    notes.push_back(std::string("no crust colour: ") + e.what());
    return std::nullopt;
  }
}

const char* kStyle = R"(
body { font-family: "DejaVu Sans", Helvetica, Arial, sans-serif; margin: 2em auto; max-width: 1100px; color: #222; padding: 0 1em; }
h1 { margin-bottom: 0.2em; } h2 { margin-top: 1.6em; border-bottom: 1px solid #ddd; }
p.description { color: #555; max-width: 60em; }
table { border-collapse: collapse; margin: 0.5em 0; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.7em; text-align: left; }
th { background: #f4f1ec; } td.number { text-align: right; font-variant-numeric: tabular-nums; }
.swatch { display: inline-block; width: 1.2em; height: 1.2em; vertical-align: middle; border: 1px solid #888; margin-right: 0.4em; }
figure { display: inline-block; margin: 0.5em 1em 0.5em 0; vertical-align: top; }
figure img { max-width: 520px; border: 1px solid #ddd; }
figcaption { color: #555; font-size: 0.9em; }
svg.plot { background: #fff; border: 1px solid #ddd; }
svg .grid { stroke: #e6e6e6; } svg .axis { stroke: #222; }
svg text { font-family: "DejaVu Sans", Helvetica, Arial, sans-serif; fill: #222; }
svg .tick { font-size: 11px; fill: #555; } svg .label { font-size: 13px; } svg .title { font-size: 15px; } svg .legend { font-size: 12px; }
.notes { color: #8a5300; } footer { margin-top: 2em; color: #777; font-size: 0.85em; }
)";

}  // namespace

namespace {

ReportResult write_report_of(const fs::path& run_dir, const ReportOptions& o) {
  ReportResult result;
  auto& notes = result.notes;
  const RunResults r = read_run_results(run_dir);
  const json scene = read_run_scene(run_dir / "scene.json");
  std::vector<Measured> measured;
  for (const auto& spec : o.compare) measured.push_back(read_measured(spec));
  const Table& t = r.stats;
  const std::vector<double>& minutes = r.minutes;

  // Pictures of the first and the last frame: drawn now when render/ has none of them.
  std::map<int, fs::path> frames;
  try {
    frames = open_run(run_dir).frames;
  } catch (const InputError& e) {
    notes.push_back(std::string("no frames: ") + e.what());
  }
  std::vector<std::pair<int, fs::path>> pictures;
  std::optional<std::pair<int, fs::path>> cut_picture;
  if (!frames.empty()) {
    const std::vector<int> wanted = frames.size() > 1 ? std::vector<int>{frames.begin()->first, frames.rbegin()->first}
                                                      : std::vector<int>{frames.begin()->first};
    auto picture_of = [&](int f) { return run_dir / "render" / fmt::format("mesh-browning-{}.png", frame_stem(f)); };
    std::vector<int> missing;
    for (int f : wanted)
      if (!fs::is_regular_file(picture_of(f))) missing.push_back(f);
    if (!missing.empty() && o.draw_pictures) {
      try {
        RenderRunOptions ro;
        ro.colour = "browning";  // the report's pictures are its crust colour, whatever the scene draws
        ro.frames = missing;
        render_run(run_dir, ro);
      } catch (const std::exception& e) {
        notes.push_back(std::string("no pictures: ") + e.what());
      }
    }
    for (int f : wanted)
      if (fs::is_regular_file(picture_of(f))) pictures.emplace_back(f, picture_of(f));
    // The last frame cut in half (render --cut z): the crumb, the moist core or the unset centre inside.
    const int last = frames.rbegin()->first;
    const fs::path cut = run_dir / "render" / fmt::format("mesh-browning-cut-z-{}.png", frame_stem(last));
    if (!fs::is_regular_file(cut) && o.draw_pictures) {
      try {
        RenderRunOptions ro;
        ro.colour = "browning";
        ro.frames = {last};
        ro.cut = "z";
        render_run(run_dir, ro);
      } catch (const std::exception& e) {
        notes.push_back(std::string("no cut view: ") + e.what());
      }
    }
    if (fs::is_regular_file(cut)) cut_picture = std::make_pair(last, cut);
  }
  std::optional<CrustColour> crust;
  if (!frames.empty()) crust = crust_colour(frames.rbegin()->second, scene, notes);

  // Each body's mass at the first frame, for the weight loss (water lost / mass).
  std::vector<double> body_mass;
  if (!frames.empty()) {
    try {
      const ParticleSet ps = read_particle_frame(frames.begin()->second);
      if (ps.has("mass") && ps.has("body_id")) {
        const auto& m = ps.scalar("mass");
        const auto& body = ps.scalar("body_id");  // frame files hold every attribute as a number
        for (std::size_t i = 0; i < m.size(); ++i) {
          if (!(body[i] >= 0) || body[i] > 1e6) continue;
          const auto b = std::size_t(body[i]);
          if (b >= body_mass.size()) body_mass.resize(b + 1, 0.0);
          body_mass[b] += m[i];
        }
      }
    } catch (const std::exception&) {
    }
  }
  auto body_index = [&](const std::string& name) -> int {
    for (std::size_t i = 0; i < scene["bodies"].size(); ++i)
      if (scene["bodies"][i].value("name", "") == name) return int(i);
    return -1;
  };

  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += fmt::format("<title>bakesim report: {}</title>\n<style>{}</style>\n</head>\n<body>\n", escape(r.scene_name),
                   kStyle);
  h += fmt::format("<h1>{}</h1>\n", escape(r.scene_name));
  if (scene.contains("description") && !scene["description"].get<std::string>().empty())
    h += fmt::format("<p class=\"description\">{}</p>\n", escape(scene["description"].get<std::string>()));
  h += fmt::format("<p>{} of baking at {}, simulated by the {} solver.</p>\n",
                   r.bake_minutes >= 2 ? number(r.bake_minutes, 1) + " minutes" : number(r.bake_minutes * 60, 1) + " s",
                   escape(scene_oven(scene["environment"])),
                   scene["solver"]["type"].get<std::string>() == "mpm" ? "MPM" : "SPH");

  // Key numbers.
  h += "<h2>Results</h2>\n<table id=\"results\">\n<tr><th>body</th><th>core reaches " +
       fmt::format("{:.3g}", r.done_degc) +
       " °C at</th><th>core at the end</th><th>crust at the end</th><th>rise (volume)</th><th>height</th>"
       "<th>moisture loss</th><th>weight loss</th><th>crust (moisture; crumb's)</th></tr>\n";
  for (const BodyResults& b : r.bodies) {
    const std::string done = !b.heated                          ? "–"
                             : std::isfinite(b.minutes_to_done) ? number(b.minutes_to_done, 1) + " min"
                                                                : "not reached";
    double weight_loss = kNaN;
    const int bi = body_index(b.name);
    if (const auto* water = t.column("water:" + b.name);
        water && bi >= 0 && std::size_t(bi) < body_mass.size() && body_mass[std::size_t(bi)] > 0)
      weight_loss = 100 * (water->front() - water->back()) / body_mass[std::size_t(bi)];
    h += fmt::format(
        "<tr data-body=\"{}\"><td>{}</td><td class=\"number\" data-key=\"done\">{}</td><td class=\"number\" "
        "data-key=\"core\">{}</td><td class=\"number\" data-key=\"crust\">{}</td><td class=\"number\" "
        "data-key=\"rise\">×{}</td><td class=\"number\" data-key=\"height\">{} → {} cm</td><td class=\"number\" "
        "data-key=\"moisture\">{}</td><td class=\"number\" data-key=\"weight\">{}</td><td class=\"number\" "
        "data-key=\"crust-layer\">{}</td></tr>\n",
        escape(b.name), escape(b.name), done, b.heated ? number(b.core_end, 1) + " °C" : "–",
        b.heated ? number(b.crust_end, 1) + " °C" : "–", number(b.volume_ratio, 2), number(b.height_start * 100, 2),
        number(b.height_end * 100, 2),
        std::isfinite(b.moisture_loss_percent) ? number(b.moisture_loss_percent, 1) + " % of the water" : "–",
        std::isfinite(weight_loss) ? number(weight_loss, 1) + " % of the mass" : "–",
        std::isfinite(b.crust_thickness) ? fmt::format("{} mm ({}; {} kg/kg)", number(b.crust_thickness * 1e3, 1),
                                                       number(b.crust_moisture, 2), number(b.crumb_moisture, 2))
                                         : "–");
  }
  h += "</table>\n<table id=\"totals\">\n";
  if (crust)
    h += fmt::format(
        "<tr><th>crust colour</th><td data-key=\"crust-colour\"><span class=\"swatch\" "
        "style=\"background:{}\"></span>{} "
        "(browning index {}, mean over the surface as drawn)</td></tr>\n",
        crust->hex, colour_name(crust->browning), number(crust->browning, 2));
  if (std::isfinite(r.heat_in_kilojoules))
    h += fmt::format(
        "<tr><th>heat in</th><td data-key=\"heat-in\">{} kJ through the surfaces (air and hot colliders)</td></tr>\n",
        number(r.heat_in_kilojoules, 2));
  h += fmt::format("<tr><th>oven air at the end</th><td>{} °C</td></tr>\n", number(r.air_end, 1));
  h += "</table>\n";

  // Pictures.
  if (!pictures.empty()) {
    h += "<h2>Pictures</h2>\n<div id=\"pictures\">\n";
    for (const auto& [f, file] : pictures) {
      const std::size_t row = std::min<std::size_t>(std::size_t(f), minutes.size() - 1);
      h += fmt::format(
          "<figure><img src=\"data:image/png;base64,{}\" alt=\"frame {}\"><figcaption>frame {}, {} min of bake "
          "(browning)</figcaption></figure>\n",
          base64(read_file(file)), f, f, number(minutes[row], 1));
    }
    if (cut_picture) {
      const auto& [f, file] = *cut_picture;
      const std::size_t row = std::min<std::size_t>(std::size_t(f), minutes.size() - 1);
      h += fmt::format(
          "<figure><img src=\"data:image/png;base64,{}\" alt=\"frame {} cut in half\"><figcaption>frame {}, {} min "
          "of bake, cut through the middle (browning inside and out)</figcaption></figure>\n",
          base64(read_file(file)), f, f, number(minutes[row], 1));
    }
    h += "</div>\n";
  }

  // Plots.
  std::vector<SvgPlot> plots;
  SvgPlot temps{"plot-temperature", "Temperatures", "bake time (min)", "temperature (°C)", {}};
  SvgPlot volume{"plot-volume", "Volume (relative to the first frame)", "bake time (min)", "V / V0", {}};
  SvgPlot rise{"plot-height", "Rise of the top", "bake time (min)", "height gain (cm)", {}};
  SvgPlot moisture{"plot-moisture", "Moisture loss", "bake time (min)", "water lost (% of the initial water)", {}};
  for (std::size_t k = 0; k < t.names.size(); ++k) {
    const std::string& n = t.names[k];
    const auto& col = t.columns[k];
    if (n.starts_with("core_temperature:"))
      temps.series.push_back({"core " + n.substr(17), minutes, col});
    else if (n.starts_with("crust_temperature:"))
      temps.series.push_back({"crust " + n.substr(18), minutes, col});
    else if (n.starts_with("probe:") && n.ends_with(":temperature"))
      temps.series.push_back({"probe " + n.substr(6, n.size() - 6 - 12), minutes, col});
    else if (n.starts_with("volume:")) {
      std::vector<double> rel = col;
      for (double& v : rel) v = col.front() > 0 ? v / col.front() : kNaN;
      volume.series.push_back({n.substr(7), minutes, rel});
    } else if (n.starts_with("height:")) {
      std::vector<double> gain = col;
      for (double& v : gain) v = (v - col.front()) * 100;
      rise.series.push_back({n.substr(7), minutes, gain});
    } else if (n.starts_with("moisture_loss_percent:")) {
      moisture.series.push_back({n.substr(22), minutes, col});
    }
  }
  if (!temps.series.empty()) {
    if (const auto* air = t.column("air_temperature")) temps.series.push_back({"oven air", minutes, *air, {}, true});
    const Series done = doneness_series(minutes.front(), minutes.back(), r.done_degc);
    temps.series.push_back({done.name, done.x, done.y, {}, true, false, "#555555"});
  }
  for (const Measured& m : measured)
    for (const MeasuredColumn& c : m.columns) {
      SvgSeries s{"measured " + c.name + " (" + m.label + ")", m.minutes, c.values, c.spread, false, true};
      if (c.quantity == Quantity::temperature)
        temps.series.push_back(s);
      else if (c.quantity == Quantity::rise)
        rise.series.push_back(s);
      else if (c.quantity == Quantity::moisture_loss)
        moisture.series.push_back(s);
      else
        notes.push_back(
            fmt::format("{}: column {} is not plotted (its unit is not one the report knows)", m.label, c.name));
    }
  h += "<h2>Plots</h2>\n<div id=\"plots\">\n";
  for (SvgPlot* p : {&temps, &volume, &rise, &moisture})
    if (!p->series.empty()) h += svg_plot(*p);
  h += "</div>\n";

  // Measured against simulated, where a column to compare with was named.
  std::string comparison;
  for (const Measured& m : measured) {
    if (m.compare_with.empty()) continue;
    const auto* sim = t.column(m.compare_with);
    if (!sim)
      throw InputError("--compare " + m.label + "=" + m.compare_with,
                       fmt::format("stats.csv has no such column; it has {}", fmt::join(t.names, ", ")));
    std::vector<double> simulated = *sim;
    if (m.compare_with.starts_with("height:"))
      for (double& v : simulated) v = (v - sim->front()) * 100;
    const MeasuredColumn& c = m.columns.front();
    double sum2 = 0, worst = 0;
    int count = 0;
    for (std::size_t i = 0; i < m.minutes.size(); ++i) {
      const double s = interpolate(minutes, simulated, m.minutes[i]);
      if (!std::isfinite(s) || !std::isfinite(c.values[i])) continue;
      sum2 += (s - c.values[i]) * (s - c.values[i]);
      worst = std::max(worst, std::abs(s - c.values[i]));
      ++count;
    }
    const std::string unit = c.quantity == Quantity::temperature     ? " °C"
                             : c.quantity == Quantity::rise          ? " cm"
                             : c.quantity == Quantity::moisture_loss ? " %"
                                                                     : "";
    comparison += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{}</td><td class=\"number\">{}</td><td class=\"number\" "
        "data-key=\"rms\">{}</td><td class=\"number\">{}</td></tr>\n",
        escape(m.label), escape(c.name), escape(m.compare_with), count,
        count ? number(std::sqrt(sum2 / count), 2) + unit : "–", count ? number(worst, 2) + unit : "–");
  }
  if (!comparison.empty())
    h +=
        "<h2>Measured and simulated</h2>\n<table id=\"comparison\">\n<tr><th>measured</th><th>column</th><th>simulated "
        "(stats.csv)</th><th>points in the bake</th><th>RMS difference</th><th>largest difference</th></tr>\n" +
        comparison + "</table>\n";

  // The scene.
  h += "<h2>Scene</h2>\n<table id=\"scene\">\n";
  const json& sv = scene["solver"];
  const std::string type = sv["type"].get<std::string>();
  auto row = [&](const std::string& k, const std::string& v) {
    h += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", escape(k), escape(v));
  };
  row("solver", type == "mpm" ? fmt::format("MPM, cell {:g} mm", sv["mpm"]["cell_size"].get<double>() * 1000)
                              : fmt::format("SPH, spacing {:g} mm", sv["sph"]["spacing"].get<double>() * 1000));
  if (const auto* p = t.column("particles")) row("particles", fmt::format("{:.0f}", p->front()));
  for (const auto& b : scene["bodies"])
    row("body " + b.value("name", ""), fmt::format("{} of {}, starting at {:g} °C", b["shape"].value("type", "shape"),
                                                   b.value("material", ""), b.value("temperature", 20.0)));
  for (const auto& c : scene["colliders"]) {
    const json& temp = c["temperature"];
    row("collider " + c.value("name", ""), fmt::format("{}{}", c["shape"].value("type", "shape"),
                                                       temp.is_number() ? fmt::format(" at {:g} °C", temp.get<double>())
                                                       : temp.is_string() ? " at the oven's temperature"
                                                       : temp.is_array()  ? " on a temperature schedule"
                                                                          : ""));
  }
  row("oven air", scene_oven(scene["environment"]));
  row("heat transfer coefficient",
      fmt::format("{:g} W/(m² K)", scene["environment"]["heat_transfer_coefficient"].get<double>()));
  const double emissivity = scene["environment"]["emissivity"].get<double>();
  row("wall radiation", emissivity > 0 ? fmt::format("emissivity {:g}, walls at the air's temperature", emissivity)
                                       : std::string("none"));
  // Off sea level: the air's pressure, and where free water boils in it.
  if (const auto air = named_air_pressure(scene["environment"]))
    row("air pressure", fmt::format("{:.1f} kPa{}: free water boils at {:.1f} °C", air->pascal / 1000,
                                    air->altitude ? fmt::format(" ({:g} m up)", *air->altitude) : std::string(),
                                    boiling_point_at(air->pascal)));
  row("bake clock",
      fmt::format("{:g} s of bake per simulated second", scene["environment"]["bake_time_scale"].get<double>()));
  row("simulated",
      fmt::format("{:g} s in {} frames ({:g} fps)", r.time_end, r.frames - 1, scene["time"]["fps"].get<double>()));
  if (const auto* steps = t.column("steps"))
    row("run", fmt::format("{:.0f} steps in {} s of wall time", steps->back(), number(r.wall_seconds, 0)));
  h += "</table>\n";
  if (!notes.empty()) {
    h += "<ul class=\"notes\">\n";
    for (const auto& n : notes) h += "<li>" + escape(n) + "</li>\n";
    h += "</ul>\n";
  }
  const std::time_t now = std::time(nullptr);
  char date[32] = {};
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  h += fmt::format("<footer>{} report of {}, {}. Temperatures in °C, bake time in minutes of oven.</footer>\n",
                   escape(o.generator), escape(fs::absolute(run_dir).lexically_normal().string()), date);
  h += "</body>\n</html>\n";

  result.file = o.output.empty() ? run_dir / "report.html" : o.output;
  write_file_atomic(result.file, h);
  return result;
}

}  // namespace

ReportResult write_report(const fs::path& run_dir, const ReportOptions& o) {
  try {
    return write_report_of(run_dir, o);
  } catch (const nlohmann::json::exception& e) {
    // bakesim wrote scene.json; one edited by hand into another shape is named, with what was wrong.
    throw InputError((run_dir / "scene.json").string(),
                     std::string("does not read as the resolved scene of a run: ") + e.what());
  }
}

}  // namespace bakesim::render
