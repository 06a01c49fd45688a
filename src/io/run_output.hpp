#pragma once
// Everything a run writes into its directory:
//   scene.json          the resolved scene (every default filled in)
//   frames/NNNNN.ply    binary PLY per written frame
//   frames/NNNNN.vtu    VTK XML per written frame, with particles.pvd listing them
//   meshes/NNNNN.*      surface meshes of written frames when output.mesh.enabled
//   stats.csv           one row per frame, appended (and flushed) per frame
//   stats.units.csv     the unit of each stats.csv column ("column,unit")
//   log.txt             the run's log, appended per frame
// Every other file is written atomically (temporary name, then rename). A
// crash can leave stats.csv or log.txt with an unfinished last line, never an
// earlier line damaged; readers skip a last line without its newline, and a
// resume cuts stats.csv back to its checkpoint's frame.
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <spdlog/logger.h>

#include "io/particle_files.hpp"
#include "io/run_meshes.hpp"
#include "io/scene.hpp"
#include "sim/bake_stats.hpp"
#include "core/timers.hpp"
#include "sim/frame_loop.hpp"

namespace bakesim {

// A logger that keeps its lines for log.txt until they are appended there,
// and optionally echoes warnings to stderr.
class RunLog {
 public:
  explicit RunLog(bool echo_to_stderr);
  spdlog::logger& logger() { return *logger_; }
  // Appends the lines logged since the last call to `file`.
  void append_to(const std::filesystem::path& file);

 private:
  std::shared_ptr<std::ostringstream> stream_;
  std::shared_ptr<spdlog::logger> logger_;
};

// The unit of a stats.csv column ("" for counts and ratios), as stats.units.csv gives it.
std::string stats_column_unit(const std::string& column, const ParticleSet& particles);

// The numbers of stats.csv, one row per frame, computed without writing them:
// RunOutput writes them, the Python module keeps them in memory.
class FrameRecorder {
 public:
  // `solver` in its initial state (before a resume restores it): the
  // reference of the bake statistics (the water each body started with).
  FrameRecorder(const Scene& scene, const Solver& solver);
  // stats.csv's columns; the solver's frame_quantities() join on the first record().
  const std::vector<std::string>& columns() const { return columns_; }
  // The row of this frame, in the order of columns().
  const std::vector<double>& record(const FrameInfo& info, const Solver& solver);
  const std::vector<double>& last_row() const { return row_; }
  bool recorded() const { return recorded_; }
  // Probes that follow a particle: its id (−1 for fixed probes), set on the first record().
  const std::vector<std::int32_t>& follow_ids() const { return follow_ids_; }
  // Goes on after a resume: the followed particles and the bodies' volumes at frame 0.
  void resume(std::vector<std::int32_t> follow_ids, std::vector<Real> first_volume);
  std::string progress_note() const;
  std::vector<std::string> bake_summary() const;

 private:
  const Scene& scene_;
  std::vector<std::string> columns_;
  std::vector<double> row_;
  bool recorded_ = false, columns_complete_ = false;
  std::vector<std::int32_t> follow_ids_;
  std::optional<BakeStatistics> bake_;
  std::vector<BodyBake> last_bake_;
  std::vector<Real> first_volume_, last_volume_;
  Stopwatch clock_;
};

class RunOutput final : public FrameObserver {
 public:
  // `solver` in its initial state (before a resume restores it): the
  // reference of the bake statistics (the water each body started with).
  RunOutput(std::filesystem::path dir, const Scene& scene, const Solver& solver, RunLog& log);
  void on_frame(const FrameInfo& info, const Solver& solver) override;
  const std::filesystem::path& directory() const { return dir_; }
  void flush_log();
  // Probes that follow a particle: its id (−1 for fixed probes), set on frame 0.
  const std::vector<std::int32_t>& follow_ids() const { return recorder_.follow_ids(); }
  // Continues a run after `frame`: keeps the stats rows and ParaView entries up
  // to it and removes particle and mesh files of later frames (left by the run
  // that stopped), so the resumed run appends without duplicates or gaps.
  void resume_after(int frame, std::vector<std::int32_t> follow_ids);
  // For the progress bar: the coldest core of the baking bodies ("core 87.3 degC"), "" when nothing bakes.
  std::string progress_note() const { return recorder_.progress_note(); }
  // What the bake did, one line per baking body (core and crust temperature,
  // rise, moisture loss), for the end of the run; empty when nothing bakes.
  std::vector<std::string> bake_summary() const { return recorder_.bake_summary(); }
  const FrameRecorder& recorder() const { return recorder_; }

 private:
  std::filesystem::path dir_;
  const Scene& scene_;
  RunLog& log_;
  FrameRecorder recorder_;
  bool header_written_ = false;
  std::vector<PvdEntry> pvd_;
  std::optional<MeshSettings> mesh_;  // output.mesh.enabled: mesh each written frame
  RunGeometry geometry_;
};

}  // namespace bakesim
