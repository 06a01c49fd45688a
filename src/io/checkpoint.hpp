#pragma once
// Checkpoints: everything a run needs to go on exactly where it was.
//
// File layout (little-endian): the magic "BAKESIM-CKPT", a format version
// (u32), the payload size (u64) and the payload's FNV-1a 64-bit checksum
// (u64), then the payload: the solver's name, the scene's fingerprint, the
// scene directory (to find mesh files again), the frame-loop position (frame,
// steps, last dt), the solver's named numbers, every particle attribute
// (exported or not) by name, and the run output's own state (followed probe
// particles). A file with another magic, version, size or checksum, or from
// another scene or solver, is refused with an InputError saying which.
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "core/solver.hpp"

namespace bakesim {

inline constexpr std::uint32_t kCheckpointVersion = 1;

struct Checkpoint {
  std::string solver;
  std::string scene_fingerprint;
  std::string scene_dir;  // where the scene's relative mesh paths resolve
  int frame = 0;
  long steps = 0;
  double last_dt = 0;
  std::vector<std::pair<std::string, double>> solver_state;
  ParticleSet particles;
  std::vector<std::int32_t> follow_ids;
};

// A fingerprint of what determines the simulation (the resolved scene without
// time.end and output, which a resumed run may change).
std::string scene_fingerprint(const nlohmann::json& resolved_scene);

std::string encode_checkpoint(const Checkpoint& checkpoint);
// The header (magic, version, size, checksum) in front of a payload; the
// checkpoint fuzz target seals crafted payloads with it to reach the checks
// that come after the checksum.
inline constexpr std::size_t kCheckpointHeaderBytes = 32;
std::string seal_checkpoint_payload(std::string_view payload);
Checkpoint decode_checkpoint(const std::string& bytes, const std::string& where);

// Captures a solver's state; restores it into a solver built from the same scene.
Checkpoint capture_checkpoint(const Solver& solver);
void restore_checkpoint(Solver& solver, const Checkpoint& checkpoint, const std::string& where);

// Writes RUN_DIR/checkpoints/NNNNN.ckpt (NNNNN = the frame) atomically and
// removes all but the newest `keep`.
std::filesystem::path write_checkpoint(const std::filesystem::path& run_dir, const Checkpoint& checkpoint,
                                       int keep = 2);
// RUN_DIR/checkpoints/NNNNN.ckpt, newest first.
std::vector<std::filesystem::path> list_checkpoints(const std::filesystem::path& run_dir);

}  // namespace bakesim
