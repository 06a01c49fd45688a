#include "io/bake_run.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"
#include "core/timers.hpp"
#include "io/files.hpp"
#include "io/run_directory.hpp"

namespace bakesim {

namespace fs = std::filesystem;

ResumePoint open_resume(const fs::path& dir) {
  if (!fs::is_regular_file(dir / "scene.json")) throw InputError(dir.string(), "not a run directory (no scene.json)");
  ResumePoint r;
  r.lock = claim_existing_run(dir);
  // The newest checkpoint of this run's scene that decodes; damaged or foreign ones are passed over.
  std::string run_fingerprint;
  try {
    run_fingerprint = scene_fingerprint(nlohmann::json::parse(read_file(dir / "scene.json")));
  } catch (const nlohmann::json::exception& e) {
    throw InputError((dir / "scene.json").string(), std::string("not valid JSON: ") + e.what());
  }
  std::optional<Checkpoint> found;
  for (const auto& file : list_checkpoints(dir)) {
    try {
      Checkpoint candidate = decode_checkpoint(read_file(file), file.string());
      if (candidate.scene_fingerprint != run_fingerprint)
        throw InputError(file.string(), "checkpoint of a different scene than " + (dir / "scene.json").string());
      found = std::move(candidate);
      r.checkpoint_file = file;
      break;
    } catch (const InputError& e) {
      r.refused.push_back(e.what());
    }
  }
  if (!found)
    throw InputError(dir.string(), r.refused.empty() ? "has no checkpoint to resume from (checkpoints/*.ckpt)"
                                                     : "no valid checkpoint: " + r.refused.front());
  r.checkpoint = std::move(*found);
  r.scene_dir = r.checkpoint.scene_dir;
  r.scene = parse_scene(read_file(dir / "scene.json"), (dir / "scene.json").string(), r.scene_dir);
  if (scene_fingerprint(r.scene.resolved) != r.checkpoint.scene_fingerprint)
    throw InputError(r.checkpoint_file.string(),
                     "checkpoint of a different scene than " + (dir / "scene.json").string());
  return r;
}

void resume_from(Solver& solver, RunOutput& output, FrameLoopConfig& cfg, const Checkpoint& checkpoint,
                 const std::string& checkpoint_file) {
  restore_checkpoint(solver, checkpoint, checkpoint_file);
  output.resume_after(checkpoint.frame, checkpoint.follow_ids);
  cfg.start_frame = checkpoint.frame;
  cfg.start_steps = checkpoint.steps;
  cfg.start_last_dt = checkpoint.last_dt;
  cfg.start_frame_written = true;
}

bool is_bake(const Scene& scene, const Solver& solver) {
  return solver.heats() && scene.oven.bake_time(scene.end_time) >= 60;
}

FrameLoopConfig frame_loop_config(const Scene& scene, const Solver& solver) {
  FrameLoopConfig cfg;
  cfg.end_time = scene.end_time;
  cfg.fps = scene.fps;
  cfg.min_dt = scene.resolved["solver"]["min_dt"].get<double>();
  if (is_bake(scene, solver)) cfg.bake_time_scale = scene.oven.bake_time_scale;
  return cfg;
}

CheckpointCadence checkpoint_cadence(const Scene& scene, int every_frames, double every_minutes) {
  const auto& ck = scene.resolved["output"]["checkpoint"];
  CheckpointCadence c;
  c.every_frames = every_frames >= 0 ? every_frames : ck["every_frames"].get<int>();
  c.every_minutes = every_minutes >= 0 ? every_minutes : ck["every_minutes"].get<double>();
  return c;
}

Checkpoint make_checkpoint(const Solver& solver, const std::string& fingerprint, const std::string& scene_dir,
                           const FrameInfo& info, const std::vector<std::int32_t>& follow_ids) {
  Checkpoint c = capture_checkpoint(solver);
  c.scene_fingerprint = fingerprint;
  c.scene_dir = scene_dir;
  c.frame = info.frame;
  c.steps = info.steps;
  c.last_dt = info.last_dt;
  c.follow_ids = follow_ids;
  return c;
}

RunSummary bake_into(Solver& solver, const Scene& scene, RunOutput& output, FrameLoopConfig cfg,
                     const BakeIntoOptions& options, ProgressBar& progress, spdlog::logger& log) {
  const fs::path out = output.directory();
  // Where the scene's mesh files are, for the commands that later draw its colliders.
  if (!options.scene_dir.empty()) record_scene_dir(out, options.scene_dir);
  const std::string fingerprint = scene_fingerprint(scene.resolved);
  Stopwatch since_checkpoint;
  auto save = [&](const Checkpoint& c) {
    const fs::path file = write_checkpoint(out, c);
    log.info("checkpoint {} (frame {})", file.string(), c.frame);
    since_checkpoint.restart();
  };
  // The state of the last complete frame stays in memory, so a step that fails
  // leaves a checkpoint just before its frame (a copy of the particles per frame).
  std::optional<Checkpoint> last_good;
  const int total_frames = std::max(1, static_cast<int>(std::ceil(cfg.end_time * cfg.fps - 1e-9)));
  const CheckpointCadence cadence = options.cadence;
  cfg.after_frame = [&](const FrameInfo& info, const Solver& s) {
    const bool stop = options.after_frame && !options.after_frame(info, s);
    const bool due = (cadence.every_frames > 0 && info.frame > 0 && info.frame % cadence.every_frames == 0) ||
                     (cadence.every_minutes > 0 && since_checkpoint.seconds() >= 60.0 * cadence.every_minutes);
    if (info.frame < total_frames) {
      last_good = make_checkpoint(s, fingerprint, options.scene_dir, info, output.follow_ids());
      if (due || stop) save(*last_good);
    }
    return !stop;
  };
  try {
    return run_frames(solver, cfg, output, progress, log);
  } catch (const SimulationError& e) {
    progress.finish();
    log.error("{}", e.what());
    if (last_good) {
      const fs::path file = write_checkpoint(out, *last_good, 3);
      log.error("the state of frame {}, the last complete one, is in {}: resume with bakesim run --resume {}",
                last_good->frame, file.string(), out.string());
    }
    log.error("frames up to the last complete one are in {}", out.string());
    output.flush_log();
    throw;
  } catch (const IoError& e) {
    // A full disk, a file-size limit, a read-only file system: keep what can be kept.
    progress.finish();
    log.error("{}", e.what());
    std::string kept;
    try {
      if (last_good) {
        const fs::path file = write_checkpoint(out, *last_good, 3);
        kept = fmt::format("; the state of frame {} is in {}: resume with bakesim run --resume {}", last_good->frame,
                           file.string(), out.string());
      }
    } catch (const IoError& again) {
      log.error("no checkpoint either: {}", again.what());
    }
    try {
      log.error("frames up to the last complete one are in {}{}", out.string(), kept);
      output.flush_log();
    } catch (const IoError&) {
    }
    throw IoError(std::string(e.what()) + kept);
  }
}

}  // namespace bakesim
