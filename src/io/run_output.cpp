#include "io/run_output.hpp"

#include <fmt/format.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include <algorithm>
#include <fstream>
#include <cmath>
#include <limits>
#include <optional>

#include "core/errors.hpp"
#include "core/quantity.hpp"
#include "io/files.hpp"
#include "io/run_directory.hpp"
#include "sim/stats.hpp"

namespace bakesim {

namespace fs = std::filesystem;

std::string stats_column_unit(const std::string& column, const ParticleSet& ps) {
  static const std::vector<std::pair<std::string, std::string>> exact = {{"time", "s"},
                                                                         {"steps", ""},
                                                                         {"dt", "s"},
                                                                         {"particles", ""},
                                                                         {"kinetic_energy", "J"},
                                                                         {"max_speed", "m/s"},
                                                                         {"wall_time", "s"},
                                                                         {"bake_time", "s"},
                                                                         {"water_total", "kg"},
                                                                         {"water_evaporated", "kg"},
                                                                         {"heat_in", "J"},
                                                                         {"latent_heat_out", "J"},
                                                                         {"water_boiled", "kg"}};
  for (const auto& [name, unit] : exact)
    if (column == name) return unit;
  if (column.size() == 5 && (column.starts_with("min_") || column.starts_with("max_"))) return "m";
  static const std::vector<std::pair<std::string, std::string>> prefixed = {{"volume:", "m3"},
                                                                            {"height:", "m"},
                                                                            {"core_temperature:", "degC"},
                                                                            {"crust_temperature:", "degC"},
                                                                            {"water:", "kg"},
                                                                            {"moisture_loss_percent:", "%"},
                                                                            {"weight_loss_percent:", "%"},
                                                                            {"crust_thickness:", "m"},
                                                                            {"crust_moisture:", "kg/kg"},
                                                                            {"crumb_moisture:", "kg/kg"},
                                                                            {"co2_mol:", "mol"}};
  for (const auto& [prefix, unit] : prefixed)
    if (column.starts_with(prefix)) return unit;
  if (column.find("temperature") != std::string::npos && column.find(':') == std::string::npos) return "degC";
  if (column.starts_with("probe:")) {
    const std::string quantity = column.substr(column.rfind(':') + 1);
    if (quantity == "speed" || quantity.starts_with("velocity_")) return "m/s";
    for (const auto& a : ps.scalars())
      if (a.info.name == quantity) return a.info.unit;
  }
  return "";
}

RunLog::RunLog(bool echo_to_stderr) : stream_(std::make_shared<std::ostringstream>()) {
  auto file_sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(*stream_);
  file_sink->set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%l] %v");
  std::vector<spdlog::sink_ptr> sinks{file_sink};
  if (echo_to_stderr) {
    auto err = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
    err->set_level(spdlog::level::warn);
    err->set_pattern("%^%l%$: %v");
    sinks.push_back(err);
  }
  logger_ = std::make_shared<spdlog::logger>("bakesim", sinks.begin(), sinks.end());
  logger_->set_level(spdlog::level::debug);
}

void RunLog::append_to(const fs::path& file) {
  logger_->flush();
  const std::string lines = stream_->str();
  if (lines.empty()) return;
  append_file(file, lines);
  stream_->str("");
}

namespace {
std::string num(double v) {
  if (std::isnan(v)) return "nan";
  return fmt::format("{:.9g}", v);
}

// A number written by this program ("nan" aside); nullopt for anything else.
std::optional<double> parse_number(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

// Unit vector against gravity (the loaf's "up"); +y without gravity.
Vec3 up_direction(const Scene& scene) {
  const Vec3 g = scene.gravity;
  return g.norm() > 0 ? Vec3(-g.normalized()) : Vec3::UnitY();
}
}  // namespace

FrameRecorder::FrameRecorder(const Scene& scene, const Solver& solver) : scene_(scene) {
  if (solver.heats()) {
    std::vector<Real> boiling_points;
    for (const auto& b : scene.bodies) boiling_points.push_back(b.boiling_point);
    bake_.emplace(solver.particles(), boiling_points);
  }
  columns_ = {"time",
              "steps",
              "dt",
              "particles",
              "kinetic_energy",
              "max_speed",
              "min_x",
              "min_y",
              "min_z",
              "max_x",
              "max_y",
              "max_z",
              "mean_temperature",
              "min_temperature",
              "max_temperature",
              "air_temperature",
              "wall_time",
              "bake_time"};
  for (const auto& b : scene_.bodies) {
    if (b.hold_temperature) continue;
    columns_.push_back("volume:" + b.name);
    columns_.push_back("height:" + b.name);
  }
  for (const auto& p : scene_.probes)
    for (const auto& q : p.quantities) columns_.push_back(fmt::format("probe:{}:{}", p.name, q));
  if (bake_)
    for (const auto& b : scene_.bodies)
      if (!b.hold_temperature)
        for (const std::string& c : bake_->columns(b.name)) columns_.push_back(c);
}

void FrameRecorder::resume(std::vector<std::int32_t> follow_ids, std::vector<Real> first_volume) {
  follow_ids_ = std::move(follow_ids);
  first_volume_ = std::move(first_volume);
}

const std::vector<double>& FrameRecorder::record(const FrameInfo& info, const Solver& solver) {
  const ParticleSet& ps = solver.particles();
  const auto extra = solver.frame_quantities();
  if (!columns_complete_) {
    // Solver-specific columns (MPM: the mixture's water and heat totals) join on the first frame.
    for (const auto& [name, value] : extra) columns_.push_back(name);
    columns_complete_ = true;
  }
  const FrameStats s = compute_frame_stats(ps);
  const Real bake_time = scene_.oven.bake_time(info.time);
  row_ = {info.time,          double(info.steps), info.last_dt,      double(s.particles),
          s.kinetic_energy,   s.max_speed,        s.bounds.min.x(),  s.bounds.min.y(),
          s.bounds.min.z(),   s.bounds.max.x(),   s.bounds.max.y(),  s.bounds.max.z(),
          s.mean_temperature, s.min_temperature,  s.max_temperature, scene_.oven.air_temperature(bake_time),
          clock_.seconds(),   bake_time};
  const std::vector<BodyStats> bodies = compute_body_stats(ps, scene_.bodies.size(), up_direction(scene_));
  last_volume_.clear();
  for (const BodyStats& b : bodies) last_volume_.push_back(b.volume);
  if (first_volume_.empty()) first_volume_ = last_volume_;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (!scene_.bodies[b].hold_temperature) {
      row_.push_back(bodies[b].volume);
      row_.push_back(bodies[b].height());
    }
  if (follow_ids_.empty()) {
    // Followed probes pick their particle on the first frame.
    const auto& x = ps.vector("position");
    for (const auto& p : scene_.probes) {
      std::int32_t best = -1;
      Real best_d = std::numeric_limits<Real>::infinity();
      if (p.follow)
        for (std::size_t i = 0; i < ps.size(); ++i)
          if (const Real d = (x[i] - p.position).squaredNorm(); d < best_d) {
            best_d = d;
            best = ps.integer("id")[i];
          }
      follow_ids_.push_back(best);
    }
  }
  const auto& ids = ps.integer("id");
  for (std::size_t k = 0; k < scene_.probes.size(); ++k) {
    const auto& p = scene_.probes[k];
    if (!p.follow) {
      for (Real v : solver.sample(p.position, p.quantities)) row_.push_back(v);
      continue;
    }
    const auto at = std::find(ids.begin(), ids.end(), follow_ids_[k]);
    for (const auto& q : p.quantities)
      row_.push_back(at == ids.end() ? std::numeric_limits<Real>::quiet_NaN()
                                     : ParticleQuantity::resolve(ps, q, "probes")(std::size_t(at - ids.begin())));
  }
  if (bake_) {
    last_bake_ = bake_->compute(ps);
    for (std::size_t b = 0; b < last_bake_.size(); ++b)
      if (!scene_.bodies[b].hold_temperature)
        for (Real v : bake_->values(last_bake_[b])) row_.push_back(v);
  }
  for (const auto& [name, value] : extra) row_.push_back(value);
  recorded_ = true;
  return row_;
}

std::string FrameRecorder::progress_note() const {
  Real coldest = std::numeric_limits<Real>::infinity();
  for (std::size_t b = 0; b < last_bake_.size(); ++b)
    if (!scene_.bodies[b].hold_temperature) coldest = std::min(coldest, last_bake_[b].core_temperature);
  return std::isfinite(coldest) ? fmt::format("core {:.1f} degC", coldest) : "";
}

std::vector<std::string> FrameRecorder::bake_summary() const {
  std::vector<std::string> lines;
  for (std::size_t b = 0; b < last_bake_.size(); ++b) {
    if (scene_.bodies[b].hold_temperature) continue;
    const BodyBake& k = last_bake_[b];
    std::string line = fmt::format("{}: core {:.1f} degC, crust {:.1f} degC", scene_.bodies[b].name, k.core_temperature,
                                   k.crust_temperature);
    if (b < first_volume_.size() && b < last_volume_.size() && first_volume_[b] > 0)
      line += fmt::format(", volume x{:.2f}", last_volume_[b] / first_volume_[b]);
    if (bake_->has_water())
      line += fmt::format(", moisture loss {:.1f} % ({:.1f} % of its weight)", std::max(0.0, k.moisture_loss_percent),
                          std::max(0.0, k.weight_loss_percent));
    if (bake_->has_moisture()) line += fmt::format(", crust {:.1f} mm thick", 1e3 * k.crust_thickness);
    lines.push_back(line);
  }
  return lines;
}

RunOutput::RunOutput(fs::path dir, const Scene& scene, const Solver& solver, RunLog& log)
    : dir_(std::move(dir)), scene_(scene), log_(log), recorder_(scene, solver) {
  ensure_directory(dir_);
  ensure_directory(dir_ / "frames");
  write_file_atomic(dir_ / "scene.json", scene_.resolved.dump(2) + "\n");
  const auto& mesh = scene_.resolved["output"]["mesh"];
  if (mesh["enabled"].get<bool>()) {
    mesh_ = mesh_settings(mesh);
    geometry_ = run_geometry(scene_.resolved);
  }
}

void RunOutput::on_frame(const FrameInfo& info, const Solver& solver) {
  const ParticleSet& ps = solver.particles();
  const std::string stem = frame_stem(info.frame);
  const bool write_particles =
      info.frame % scene_.output.every_frames == 0 || info.frame == 0 || info.time >= scene_.end_time - 1e-12;
  if (write_particles) {
    // Every chosen format, in the order of the table (io/particle_files.hpp).
    for (const ParticleFormat& format : particle_formats()) {
      const auto& chosen = scene_.output.particle_formats;
      if (std::find(chosen.begin(), chosen.end(), format.name) == chosen.end()) continue;
      const std::string file = stem + format.extension;
      write_file_atomic(dir_ / "frames" / file, format.encode(ps));
      if (format.paraview_series) {
        pvd_.push_back({info.time, "frames/" + file});
        write_file_atomic(dir_ / "particles.pvd", encode_pvd(pvd_));
      }
    }
    if (mesh_) write_frame_mesh(dir_ / "meshes", info.frame, frame_mesh(ps, geometry_, *mesh_), *mesh_);
    if (mesh_ && mesh_->vdb) write_frame_vdb(dir_ / "meshes", info.frame, ps, geometry_, *mesh_);
  }
  const std::vector<double>& values = recorder_.record(info, solver);
  const std::vector<std::string>& columns = recorder_.columns();
  if (!header_written_) {
    std::string header;
    for (const auto& c : columns) header += (header.empty() ? "" : ",") + c;
    // The units for tools (pandas, a spreadsheet): one row per column of stats.csv.
    std::string units = "column,unit\n";
    for (const auto& c : columns) units += c + "," + stats_column_unit(c, ps) + "\n";
    write_file_atomic(dir_ / "stats.units.csv", units);
    write_file_atomic(dir_ / "stats.csv", header + "\n");
    header_written_ = true;
  }
  std::string row;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k > 0) row += ",";
    // The counts (steps, particles) as whole numbers.
    row += (k == 1 || k == 3) ? fmt::format("{}", static_cast<long long>(values[k])) : num(values[k]);
  }
  // One row appended per frame: the cost of a frame does not grow with the run.
  append_file(dir_ / "stats.csv", row + "\n");
  flush_log();
}

void RunOutput::flush_log() { log_.append_to(dir_ / "log.txt"); }

void RunOutput::resume_after(int frame, std::vector<std::int32_t> follow_ids) {
  // stats.csv: the header and one row per frame 0..frame (complete lines only:
  // a killed run may have left the last one unfinished).
  const fs::path stats = dir_ / "stats.csv";
  const std::string text = read_file(stats);
  std::string kept;
  const long lines_wanted = long(frame) + 2;  // the header and frames 0..frame
  long lines = 0;
  for (std::size_t at = 0; lines < lines_wanted; ++lines) {
    const std::size_t end = text.find('\n', at);
    if (end == std::string::npos) break;
    kept.append(text, at, end + 1 - at);
    at = end + 1;
  }
  if (lines < lines_wanted)
    throw InputError(stats.string(),
                     fmt::format("has {} frames, the checkpoint is at frame {}", std::max(0L, lines - 1), frame));
  // The bodies' volumes at frame 0 (the reference of the rise in the summary).
  {
    std::istringstream rows(kept);
    std::string header, first, cell;
    std::getline(rows, header);
    std::getline(rows, first);
    std::vector<std::string> names, values;
    for (std::istringstream h(header); std::getline(h, cell, ',');) names.push_back(cell);
    for (std::istringstream v(first); std::getline(v, cell, ',');) values.push_back(cell);
    std::vector<Real> first_volume(scene_.bodies.size(), std::numeric_limits<Real>::quiet_NaN());
    for (std::size_t b = 0; b < scene_.bodies.size(); ++b)
      for (std::size_t k = 0; k < names.size() && k < values.size(); ++k)
        if (names[k] == "volume:" + scene_.bodies[b].name)
          if (const auto v = parse_number(values[k])) first_volume[b] = *v;
    recorder_.resume(std::move(follow_ids), std::move(first_volume));
  }
  header_written_ = true;
  // particles.pvd: entries of frames up to `frame`, read back from the file.
  pvd_.clear();
  std::ifstream pvd(dir_ / "particles.pvd");
  std::string line;
  while (std::getline(pvd, line)) {
    const auto t = line.find("timestep=\""), f = line.find("file=\"frames/");
    if (t == std::string::npos || f == std::string::npos) continue;
    const std::size_t close = line.find('"', f + 6);
    if (close == std::string::npos) continue;
    const std::string file = line.substr(f + 6, close - (f + 6));
    const auto time = parse_number(line.substr(t + 10, line.find('"', t + 10) - (t + 10)));
    const auto number = frame_number(fs::path(file).stem().string());
    if (time && number && *number <= frame) pvd_.push_back({*time, file});
  }
  if (!pvd_.empty()) write_file_atomic(dir_ / "particles.pvd", encode_pvd(pvd_));
  // Half-written temporaries of the stopped run (killed in the middle of a write).
  remove_run_temporaries(dir_);
  // Files of frames after the checkpoint (bakesim's own only: a user's file there stays).
  for (const char* sub : {"frames", "meshes"}) {
    std::error_code ec;
    if (!fs::is_directory(dir_ / sub, ec)) continue;
    std::vector<fs::path> stale;
    for (const auto& e : fs::directory_iterator(dir_ / sub, ec))
      if (const auto number = frame_number(e.path().stem().string());
          number && *number > frame && is_run_file(fs::path(sub) / e.path().filename()))
        stale.push_back(e.path());
    for (const auto& p : stale) fs::remove(p, ec);
  }
  write_file_atomic(stats, kept);
}

}  // namespace bakesim
