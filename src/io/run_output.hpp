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

class RunOutput final : public FrameObserver {
 public:
  // `solver` in its initial state (before a resume restores it): the
  // reference of the bake statistics (the water each body started with).
  RunOutput(std::filesystem::path dir, const Scene& scene, const Solver& solver, RunLog& log);
  void on_frame(const FrameInfo& info, const Solver& solver) override;
  const std::filesystem::path& directory() const { return dir_; }
  std::string stats_header() const;
  void flush_log();
  // Probes that follow a particle: its id (−1 for fixed probes), set on frame 0.
  const std::vector<std::int32_t>& follow_ids() const { return follow_ids_; }
  // Continues a run after `frame`: keeps the stats rows and ParaView entries up
  // to it and removes particle and mesh files of later frames (left by the run
  // that stopped), so the resumed run appends without duplicates or gaps.
  void resume_after(int frame, std::vector<std::int32_t> follow_ids);
  // For the progress bar: the coldest core of the baking bodies ("core 87.3 degC"), "" when nothing bakes.
  std::string progress_note() const;
  // What the bake did, one line per baking body (core and crust temperature,
  // rise, moisture loss), for the end of the run; empty when nothing bakes.
  std::vector<std::string> bake_summary() const;

 private:
  std::filesystem::path dir_;
  const Scene& scene_;
  RunLog& log_;
  bool header_written_ = false;
  std::vector<PvdEntry> pvd_;
  std::optional<MeshSettings> mesh_;  // output.mesh.enabled: mesh each written frame
  RunGeometry geometry_;
  std::vector<std::int32_t> follow_ids_;          // per probe: followed particle id, -1 for fixed probes
  std::optional<BakeStatistics> bake_;            // per-body bake columns, when the solver heats
  std::vector<BodyBake> last_bake_;               // of the last frame
  std::vector<Real> first_volume_, last_volume_;  // per body: frame 0 and the last frame
  Stopwatch clock_;
};

}  // namespace bakesim
