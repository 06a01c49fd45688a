#pragma once
// A run into a run directory, as `bakesim run` and the Python module's
// Simulation(out=...) both do it, so the two write the same files:
//   open_resume()      the resolved scene and newest valid checkpoint of a run directory
//   frame_loop_config() the frame loop's settings from the scene (end, fps, step floor, bake clock)
//   bake_into()        the frame loop writing through RunOutput, with checkpoints at the
//                      scene's cadence and, when a step fails or a disk fills, the state
//                      of the last complete frame kept for `run --resume`
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/checkpoint.hpp"
#include "io/run_directory.hpp"
#include "io/run_output.hpp"
#include "io/scene.hpp"
#include "sim/frame_loop.hpp"

namespace bakesim {

struct ResumePoint {
  Scene scene;            // parsed from RUN_DIR/scene.json
  std::string scene_dir;  // where the scene's relative mesh paths resolve
  Checkpoint checkpoint;  // the newest one of this scene that decodes
  std::filesystem::path checkpoint_file;
  std::vector<std::string> refused;  // why newer checkpoints were passed over
  RunDirectoryLock lock;             // held for the resumed run
};

// InputError when `dir` is not a run directory or has no valid checkpoint of its scene.
ResumePoint open_resume(const std::filesystem::path& dir);

// Restores `solver` (built from the same scene) from `checkpoint` and readies
// `output` and `cfg` to go on after its frame.
void resume_from(Solver& solver, RunOutput& output, FrameLoopConfig& cfg, const Checkpoint& checkpoint,
                 const std::string& checkpoint_file);

// end time, fps, the step floor and (for a bake of at least a minute of oven) the bake clock of the progress bar.
FrameLoopConfig frame_loop_config(const Scene& scene, const Solver& solver);

// Whether the run is a bake (heat and at least a minute of oven): the summary says what it did.
bool is_bake(const Scene& scene, const Solver& solver);

struct CheckpointCadence {
  int every_frames = 0;      // 0: never by frames
  double every_minutes = 0;  // 0: never by wall time
};
// The scene's output.checkpoint, with the command line's overrides where they are >= 0.
CheckpointCadence checkpoint_cadence(const Scene& scene, int every_frames = -1, double every_minutes = -1);

struct BakeIntoOptions {
  std::string scene_dir;  // recorded in checkpoints
  CheckpointCadence cadence;
  // Called after each frame is written, before its checkpoint: false asks the
  // run to stop there (a checkpoint is written first). May be empty.
  std::function<bool(const FrameInfo&, const Solver&)> after_frame;
};

// Runs the frame loop of `cfg` (its after_frame is replaced) with `output` as
// the observer. Checkpoints go into the output's directory. A SimulationError
// or IoError is logged, the last complete frame's state written as a
// checkpoint where it can be, and rethrown (an IoError with where it was kept).
RunSummary bake_into(Solver& solver, const Scene& scene, RunOutput& output, FrameLoopConfig cfg,
                     const BakeIntoOptions& options, ProgressBar& progress, spdlog::logger& log);

// A checkpoint of `solver` at `info`'s place in the frame loop; `fingerprint`: scene_fingerprint(scene.resolved).
Checkpoint make_checkpoint(const Solver& solver, const std::string& fingerprint, const std::string& scene_dir,
                           const FrameInfo& info, const std::vector<std::int32_t>& follow_ids);

}  // namespace bakesim
