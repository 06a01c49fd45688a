#include "io/run_output.hpp"

#include <fmt/format.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/sinks/stdout_color_sinks.h>

#include <cmath>

#include "io/files.hpp"
#include "sim/stats.hpp"

namespace bakesim {

namespace fs = std::filesystem;

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

void RunLog::write_to(const fs::path& file) {
  logger_->flush();
  write_file_atomic(file, stream_->str());
}

namespace {
std::string num(double v) {
  if (std::isnan(v)) return "nan";
  return fmt::format("{:.9g}", v);
}
}  // namespace

RunOutput::RunOutput(fs::path dir, const Scene& scene, RunLog& log) : dir_(std::move(dir)), scene_(scene), log_(log) {
  ensure_directory(dir_);
  ensure_directory(dir_ / "frames");
  write_file_atomic(dir_ / "scene.json", scene_.resolved.dump(2) + "\n");
  stats_ = stats_header() + "\n";
}

std::string RunOutput::stats_header() const {
  std::string h =
      "time,steps,dt,particles,kinetic_energy,max_speed,min_x,min_y,min_z,max_x,max_y,max_z,"
      "mean_temperature,min_temperature,max_temperature,air_temperature,wall_time";
  for (const auto& p : scene_.probes)
    for (const auto& q : p.quantities) h += fmt::format(",probe:{}:{}", p.name, q);
  return h;
}

void RunOutput::on_frame(const FrameInfo& info, const Solver& solver) {
  const ParticleSet& ps = solver.particles();
  const std::string stem = fmt::format("{:05d}", info.frame);
  const bool write_particles = info.frame % scene_.output.every_frames == 0 || info.frame == 0 ||
                               info.time >= scene_.end_time - 1e-12;
  if (write_particles) {
    if (scene_.output.ply) write_file_atomic(dir_ / "frames" / (stem + ".ply"), encode_ply(ps));
    if (scene_.output.vtu) {
      write_file_atomic(dir_ / "frames" / (stem + ".vtu"), encode_vtu(ps));
      pvd_.push_back({info.time, "frames/" + stem + ".vtu"});
      write_file_atomic(dir_ / "particles.pvd", encode_pvd(pvd_));
    }
  }
  const FrameStats s = compute_frame_stats(ps);
  std::string row = fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", num(info.time), info.steps,
                                num(info.last_dt), s.particles, num(s.kinetic_energy), num(s.max_speed),
                                num(s.bounds.min.x()), num(s.bounds.min.y()), num(s.bounds.min.z()),
                                num(s.bounds.max.x()), num(s.bounds.max.y()), num(s.bounds.max.z()),
                                num(s.mean_temperature), num(s.min_temperature), num(s.max_temperature),
                                num(scene_.air_temperature(info.time)), num(clock_.seconds()));
  for (const auto& p : scene_.probes)
    for (Real v : solver.sample(p.position, p.quantities)) row += "," + num(v);
  stats_ += row + "\n";
  write_file_atomic(dir_ / "stats.csv", stats_);
  flush_log();
}

void RunOutput::flush_log() { log_.write_to(dir_ / "log.txt"); }

}  // namespace bakesim
