#pragma once
// Run directories are owned (docs/reliability.md, "What a run directory holds"):
// a run writes only into a directory it created, an empty one, or one that
// holds a bakesim run (the marker file bakesim-run.json). A lock
// (bakesim-run.lock, an flock held for the run's lifetime, the holder's PID
// inside) keeps a second process out. A new run in an earlier run's directory
// starts clean: the earlier run's files are moved into previous/, so frames,
// stats and checkpoints always belong to one run. Nothing bakesim did not
// write is ever deleted or overwritten.
#include <filesystem>
#include <string>
#include <vector>

namespace bakesim {

inline constexpr const char* kRunMarkerFile = "bakesim-run.json";
inline constexpr const char* kRunLockFile = "bakesim-run.lock";
inline constexpr const char* kPreviousRunDir = "previous";

// Whether `relative` (a path inside a run directory, e.g. "frames/00012.ply")
// names a file bakesim writes there: the files a run may move aside or delete.
bool is_run_file(const std::filesystem::path& relative);

class RunDirectoryLock {
 public:
  RunDirectoryLock() = default;
  RunDirectoryLock(RunDirectoryLock&& other) noexcept;
  RunDirectoryLock& operator=(RunDirectoryLock&& other) noexcept;
  RunDirectoryLock(const RunDirectoryLock&) = delete;
  RunDirectoryLock& operator=(const RunDirectoryLock&) = delete;
  ~RunDirectoryLock();

  // Takes DIR/bakesim-run.lock; InputError naming the PID of the run that
  // holds it. The lock ends with this object or with the process (a killed
  // run leaves no stale lock: the kernel releases it).
  // `file_name`: another lock file (bakesim sweep's directory has its own).
  static RunDirectoryLock take(const std::filesystem::path& dir, const char* file_name = kRunLockFile);

 private:
  explicit RunDirectoryLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

struct RunDirectoryClaim {
  RunDirectoryLock lock;
  // Entries of an earlier run moved into previous/ ("" when none were).
  std::vector<std::string> moved_aside;
};

// For a new run of the scene named `scene_name` into `dir`:
// * a missing or empty directory is created and marked;
// * a directory holding a bakesim run of the same scene has that run's files
//   moved into previous/ (replacing the files of an older previous/ run,
//   refused if previous/ holds anything else), and is marked afresh;
// * a bakesim run of another scene, or a directory with other files, is
//   refused (InputError). With `force` the other scene's run is moved aside
//   like the same scene's, and a foreign directory is used when none of the
//   names bakesim writes exist in it (it then touches no file it did not
//   write; otherwise refused, listing them).
RunDirectoryClaim claim_new_run(const std::filesystem::path& dir, const std::string& scene_name, bool force);

// For `run --resume` and the commands that write into a finished run
// (`bakesim mesh`): `dir` must hold a bakesim run; returns its lock.
RunDirectoryLock claim_existing_run(const std::filesystem::path& dir);

// Removes write_file_atomic's leftovers of a killed run from the run
// directory and its own subdirectories (never from a user's folders in it).
int remove_run_temporaries(const std::filesystem::path& dir);

// A scene's name as one safe path component, for the default out/NAME (a name
// with "/" or ".." must not reach another directory): letters, digits, - _ .
// kept, the rest _, no leading dots, at most 100 characters, "scene" when empty.
std::string output_component(const std::string& name);

// The scene name recorded in DIR's marker ("" when there is no marker).
std::string run_scene_name(const std::filesystem::path& dir);

// The directory of the run's scene file (where its relative mesh paths
// resolve), kept in the marker for the commands that draw a finished run's
// colliders; "" when the marker has none (runs made before it was kept).
void record_scene_dir(const std::filesystem::path& dir, const std::string& scene_dir);
std::string recorded_scene_dir(const std::filesystem::path& dir);

}  // namespace bakesim
