#include "render/run_results.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <cmath>

#include "core/errors.hpp"
#include "io/files.hpp"
#include "io/scene.hpp"
#include "physics/oven.hpp"

namespace bakesim::render {

namespace fs = std::filesystem;

double first_crossing(const std::vector<double>& t, const std::vector<double>& v, double level) {
  for (std::size_t i = 0; i < v.size() && i < t.size(); ++i) {
    if (!(v[i] >= level)) continue;
    if (i == 0 || !std::isfinite(v[i - 1])) return t[i];
    const double f = (level - v[i - 1]) / (v[i] - v[i - 1]);
    return t[i - 1] + f * (t[i] - t[i - 1]);
  }
  return NAN;
}

double done_core_degc(double boiling_point) { return std::min(kDoneCoreDegC, boiling_point - 5.0); }

double done_core_degc(const nlohmann::json& scene) {
  if (const auto air = named_air_pressure(scene.value("environment", nlohmann::json::object())))
    return done_core_degc(boiling_point_at(air->pascal));
  return kDoneCoreDegC;
}

double done_core_degc(const fs::path& run_dir) {
  try {
    return done_core_degc(nlohmann::json::parse(read_file(run_dir / "scene.json")));
  } catch (const std::exception&) {
    return kDoneCoreDegC;
  }
}

Series doneness_series(double from, double to, double level) {
  return {fmt::format("done ({:.3g} °C)", level), {from, to}, {level, level}, true};
}

RunResults read_run_results(const fs::path& run_dir) {
  RunResults r;
  r.dir = run_dir;
  r.stats = read_csv(run_dir / "stats.csv");
  const Table& t = r.stats;
  const auto* time = t.column("time");
  if (!time || time->empty()) throw InputError((run_dir / "stats.csv").string(), "has no rows");
  r.frames = static_cast<int>(time->size());
  r.time_end = time->back();
  std::vector<double> bake = *time;
  if (const auto* b = t.column("bake_time")) bake = *b;
  for (const double s : bake) r.minutes.push_back(s / 60.0);
  r.bake_minutes = r.minutes.back();
  if (const auto* air = t.column("air_temperature")) r.air_end = air->back();
  if (const auto* heat = t.column("heat_in")) r.heat_in_kilojoules = heat->back() / 1000.0;
  if (const auto* wall = t.column("wall_time")) r.wall_seconds = wall->back();
  try {
    const nlohmann::json scene = nlohmann::json::parse(read_file(run_dir / "scene.json"));
    r.scene_name = scene.value("name", "");
    r.done_degc = done_core_degc(scene);
  } catch (const std::exception&) {
    r.scene_name = run_dir.filename().string();
  }
  for (const std::string& n : t.names) {
    if (n.rfind("volume:", 0) != 0) continue;
    BodyResults b;
    b.name = n.substr(7);
    const auto& volume = *t.column(n);
    if (volume.front() > 0) b.volume_ratio = volume.back() / volume.front();
    if (const auto* h = t.column("height:" + b.name)) b.height_start = h->front(), b.height_end = h->back();
    if (const auto* core = t.column("core_temperature:" + b.name)) {
      b.heated = true;
      b.core_end = core->back();
      b.minutes_to_done = first_crossing(bake, *core, r.done_degc) / 60.0;
    }
    if (const auto* crust = t.column("crust_temperature:" + b.name)) b.crust_end = crust->back();
    if (const auto* loss = t.column("moisture_loss_percent:" + b.name)) b.moisture_loss_percent = loss->back();
    if (const auto* c = t.column("crust_thickness:" + b.name)) b.crust_thickness = c->back();
    if (const auto* c = t.column("crust_moisture:" + b.name)) b.crust_moisture = c->back();
    if (const auto* c = t.column("crumb_moisture:" + b.name)) b.crumb_moisture = c->back();
    r.bodies.push_back(std::move(b));
  }
  return r;
}

}  // namespace bakesim::render
