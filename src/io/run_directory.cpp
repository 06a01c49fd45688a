#include "io/run_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "io/files.hpp"

namespace bakesim {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The subdirectories a run (and mesh, render, plot) writes; they hold only the files is_run_file names.
const std::vector<std::string> kRunSubdirectories{"frames", "checkpoints", "meshes", "render", "plots"};

// The top-level entries a run writes: its files and its subdirectories.
const std::vector<std::string>& run_entries() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n{"scene.json",    "stats.csv",   "stats.units.csv", "log.txt",
                               "particles.pvd", "report.html", kRunMarkerFile};
    n.insert(n.end(), kRunSubdirectories.begin(), kRunSubdirectories.end());
    return n;
  }();
  return names;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string quoted_list(const std::vector<std::string>& names, std::size_t at_most = 4) {
  std::string s;
  for (std::size_t i = 0; i < names.size() && i < at_most; ++i) s += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > at_most) s += fmt::format(" and {} more", names.size() - at_most);
  return s;
}

// Entries of `dir` other than the lock file (sorted, for stable messages).
std::vector<std::string> entries_of(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().filename() != kRunLockFile) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// A run directory written before the marker existed: the three files every run writes, the log's
// first line by bakesim.
bool is_unmarked_run(const fs::path& dir) {
  std::error_code ec;
  for (const char* f : {"scene.json", "stats.csv", "log.txt"})
    if (!fs::is_regular_file(dir / f, ec)) return false;
  std::ifstream log(dir / "log.txt");
  std::string first;
  std::getline(log, first);
  return first.find("bakesim") != std::string::npos && first.find(" run of ") != std::string::npos;
}

bool is_run(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / kRunMarkerFile, ec) || is_unmarked_run(dir);
}

std::string scene_name_in(const fs::path& file) {
  try {
    const json j = json::parse(read_file(file, 1 << 20));
    if (j.is_object() && j.contains("scene") && j["scene"].is_string()) return j["scene"].get<std::string>();
    if (j.is_object() && j.contains("name") && j["name"].is_string()) return j["name"].get<std::string>();
  } catch (const std::exception&) {
  }
  return "";
}

void write_marker(const fs::path& dir, const std::string& scene_name) {
  const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  const json marker{{"bakesim_run", 1},
                    {"scene", scene_name},
                    {"started", stamp},
                    {"note", "written by bakesim; this directory is a bakesim run (docs/reliability.md)"}};
  write_file_atomic(dir / kRunMarkerFile, marker.dump(2) + "\n");
}

}  // namespace

void record_scene_dir(const fs::path& dir, const std::string& scene_dir) {
  json marker;
  try {
    marker = json::parse(read_file(dir / kRunMarkerFile, 1 << 20));
  } catch (const std::exception&) {
    return;  // no marker of ours: nothing to add to
  }
  if (!marker.is_object() || marker.value("scene_dir", std::string()) == scene_dir) return;
  marker["scene_dir"] = scene_dir;
  write_file_atomic(dir / kRunMarkerFile, marker.dump(2) + "\n");
}

std::string recorded_scene_dir(const fs::path& dir) {
  try {
    const json j = json::parse(read_file(dir / kRunMarkerFile, 1 << 20));
    if (j.is_object() && j.contains("scene_dir") && j["scene_dir"].is_string())
      return j["scene_dir"].get<std::string>();
  } catch (const std::exception&) {
  }
  return "";
}

namespace {

// Deletes the files of an earlier moved-aside run in `previous`; refuses when anything else is there.
void clear_previous(const fs::path& previous) {
  std::error_code ec;
  std::vector<fs::path> files, others, dirs;
  for (auto it = fs::recursive_directory_iterator(previous, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const fs::path rel = fs::relative(it->path(), previous);
    if (it->is_directory() && !it->is_symlink())
      dirs.push_back(it->path());
    else if (is_run_file(rel) && (it->is_regular_file() || it->is_symlink()))
      files.push_back(it->path());
    else
      others.push_back(rel);
  }
  if (ec) throw IoError(previous.string() + ": cannot be read: " + ec.message());
  if (!others.empty()) {
    std::vector<std::string> names;
    for (const auto& o : others) names.push_back(o.string());
    throw InputError(previous.string(),
                     fmt::format("holds files bakesim did not write ({}); the earlier run it keeps would be replaced "
                                 "by the one in {}: move those files away first",
                                 quoted_list(names), previous.parent_path().string()));
  }
  for (const auto& f : files)
    if (!fs::remove(f, ec) && ec) throw IoError(f.string() + ": cannot remove: " + ec.message());
  // Deepest first: only the now empty directories bakesim made.
  std::sort(dirs.begin(), dirs.end(), [](const fs::path& a, const fs::path& b) { return a.string() > b.string(); });
  for (const auto& d : dirs) fs::remove(d, ec);
  fs::remove(previous, ec);
}

// Moves the earlier run's entries of `dir` into dir/previous/.
std::vector<std::string> move_run_aside(const fs::path& dir) {
  const fs::path previous = dir / kPreviousRunDir;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(previous, ec))) {
    if (!fs::is_directory(fs::symlink_status(previous, ec)))
      throw InputError(previous.string(), "is not a directory bakesim made: move it away first");
    clear_previous(previous);
  }
  std::vector<std::string> moved;
  for (const auto& name : run_entries()) {
    if (!fs::exists(fs::symlink_status(dir / name, ec))) continue;
    ensure_directory(previous);
    fs::rename(dir / name, previous / name, ec);
    if (ec)
      throw IoError(fmt::format("{}: cannot move into {}: {}", (dir / name).string(), previous.string(), ec.message()));
    moved.push_back(name);
  }
  remove_run_temporaries(dir);
  return moved;
}

}  // namespace

bool is_run_file(const fs::path& relative) {
  const std::string dir = relative.has_parent_path() ? relative.parent_path().string() : "";
  const std::string name = relative.filename().string();
  const std::string stem = relative.stem().string(), ext = relative.extension().string();
  if (is_atomic_temporary(name)) return true;
  if (dir.empty()) return contains(run_entries(), name) && !contains(kRunSubdirectories, name);
  const bool numbered = frame_number(stem).has_value();
  if (dir == "frames") return numbered && (ext == ".ply" || ext == ".vtu");
  if (dir == "checkpoints") return numbered && ext == ".ckpt";
  if (dir == "meshes")
    return (numbered && (ext == ".ply" || ext == ".obj")) || (name.starts_with("gradient_") && ext == ".png") ||
           (name.starts_with("bakesim_") && ext == ".mtl");
  if (dir == "render") return ext == ".png" || name.ends_with(".mp4") || name.ends_with(".ffconcat.txt");
  if (dir == "plots") return ext == ".png";
  return false;
}

int remove_run_temporaries(const fs::path& dir) {
  int removed = remove_atomic_temporaries(dir);
  for (const std::string& sub : kRunSubdirectories) {
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(dir / sub, ec))) removed += remove_atomic_temporaries(dir / sub);
  }
  return removed;
}

RunDirectoryLock::RunDirectoryLock(RunDirectoryLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
RunDirectoryLock& RunDirectoryLock::operator=(RunDirectoryLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}
RunDirectoryLock::~RunDirectoryLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

RunDirectoryLock RunDirectoryLock::take(const fs::path& dir, const char* file_name) {
  const fs::path file = dir / file_name;
  const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd < 0) throw IoError(file.string() + ": cannot open the lock file: " + std::strerror(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    char buf[32] = {};
    const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
    ::close(fd);
    std::string pid = n > 0 ? std::string(buf, std::size_t(n)) : "";
    pid.erase(std::remove_if(pid.begin(), pid.end(), [](char c) { return c < '0' || c > '9'; }), pid.end());
    if (err != EWOULDBLOCK) throw IoError(file.string() + ": cannot lock: " + std::strerror(err));
    throw InputError(dir.string(), fmt::format("is in use by another bakesim process{} (it holds {}); wait for it "
                                               "to finish or choose another output directory",
                                               pid.empty() ? "" : " (PID " + pid + ")", file_name));
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != ssize_t(pid.size())) {
    const int err = errno;
    ::close(fd);
    throw IoError(file.string() + ": cannot write: " + std::strerror(err));
  }
  return RunDirectoryLock(fd);
}

std::string output_component(const std::string& name) {
  std::string out;
  for (const unsigned char ch : name) out += std::isalnum(ch) || ch == '-' || ch == '_' || ch == '.' ? char(ch) : '_';
  const std::size_t first = out.find_first_not_of('.');
  out = first == std::string::npos ? "" : out.substr(first);
  if (out.size() > 100) out.resize(100);
  return out.empty() ? "scene" : out;
}

std::string run_scene_name(const fs::path& dir) {
  std::error_code ec;
  if (fs::is_regular_file(dir / kRunMarkerFile, ec)) return scene_name_in(dir / kRunMarkerFile);
  if (is_unmarked_run(dir)) return scene_name_in(dir / "scene.json");
  return "";
}

RunDirectoryClaim claim_new_run(const fs::path& dir, const std::string& scene_name, bool force) {
  std::error_code ec;
  const auto status = fs::status(dir, ec);
  if (fs::exists(status) && !fs::is_directory(status))
    throw InputError(dir.string(), "exists and is not a directory: choose another output directory");
  const bool existed = fs::exists(status);
  std::vector<std::string> entries = existed ? entries_of(dir) : std::vector<std::string>{};
  enum class Kind { empty, same_scene, other_scene, foreign } kind = Kind::empty;
  std::string other_name;
  if (!entries.empty()) {
    if (is_run(dir)) {
      other_name = run_scene_name(dir);
      kind = other_name == scene_name ? Kind::same_scene : Kind::other_scene;
    } else {
      kind = Kind::foreign;
    }
  }
  // Refusals come before anything is written into the directory.
  if (kind == Kind::other_scene && !force)
    throw InputError(dir.string(),
                     fmt::format("holds a bakesim run of scene '{}', not of '{}': choose another output directory, "
                                 "or --force to move that run into {}/{} and start this one",
                                 other_name, scene_name, dir.string(), kPreviousRunDir));
  if (kind == Kind::foreign) {
    std::vector<std::string> clashes;
    for (const auto& e : entries)
      if (contains(run_entries(), e) || e == kPreviousRunDir) clashes.push_back(e);
    if (!force)
      throw InputError(dir.string(),
                       fmt::format("is not empty and is not a bakesim run directory (it holds {}): choose a new or "
                                   "empty directory, or --force to write into it beside those files",
                                   quoted_list(entries)));
    if (!clashes.empty())
      throw InputError(dir.string(),
                       fmt::format("holds {}, which a run would write: even with --force bakesim does not replace "
                                   "files it did not write; move them away or choose another directory",
                                   quoted_list(clashes)));
  }
  ensure_directory(dir);
  RunDirectoryClaim claim;
  claim.lock = RunDirectoryLock::take(dir);
  if (kind == Kind::same_scene || kind == Kind::other_scene) claim.moved_aside = move_run_aside(dir);
  write_marker(dir, scene_name);
  return claim;
}

RunDirectoryLock claim_existing_run(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir.string(), "is not a directory (not a bakesim run)");
  if (!is_run(dir))
    throw InputError(dir.string(), fmt::format("is not a bakesim run directory (no {})", kRunMarkerFile));
  RunDirectoryLock lock = RunDirectoryLock::take(dir);
  if (!fs::is_regular_file(dir / kRunMarkerFile, ec)) write_marker(dir, run_scene_name(dir));
  return lock;
}

}  // namespace bakesim
