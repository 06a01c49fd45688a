#include "sweep.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <tbb/info.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/errors.hpp"
#include "core/progress.hpp"
#include "io/checkpoint.hpp"
#include "io/files.hpp"
#include "io/run_directory.hpp"
#include "io/scene.hpp"
#include "io/sweep.hpp"
#include "render/sweep_outputs.hpp"

namespace bakesim {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kSweepMarkerFile = "bakesim-sweep.json";
constexpr const char* kSweepLockFile = "bakesim-sweep.lock";

std::atomic<int> g_sweep_signal{0};
extern "C" void on_sweep_signal(int sig) { g_sweep_signal.store(sig); }

struct Job {
  std::size_t point;
  pid_t pid = -1;
  Stopwatch clock;
};

// Starts `argv` with stdout and stderr into `log`, in a process group of its
// own (a Ctrl-C reaches the sweep, which passes it on once: a second SIGINT
// would end a run without its checkpoint) that dies with the sweep.
pid_t spawn(const std::vector<std::string>& argv, const fs::path& log) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(log.string() + ": cannot open: " + std::strerror(errno));
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fd);
    throw IoError(std::string("cannot start a run: ") + std::strerror(errno));
  }
  if (pid == 0) {  // only async-signal-safe calls until exec
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(127);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  ::close(fd);
  return pid;
}

std::string exit_status(int status) {
  if (WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    if (code == 0) return "done";
    if (code > 128) return fmt::format("stopped (signal {})", code - 128);
    return fmt::format("failed (exit {})", code);
  }
  if (WIFSIGNALED(status)) return fmt::format("killed (signal {})", WTERMSIG(status));
  return "failed";
}

// Frames written so far by the run in `dir` (rows of its stats.csv).
int frames_written(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / "stats.csv", ec)) return 0;
  const std::string text = read_file(dir / "stats.csv");
  return std::max<int>(0, int(std::count(text.begin(), text.end(), '\n')) - 1);
}

}  // namespace

namespace {
// `--dask`: the same sweep handed to the Python module, which runs it on a
// dask.distributed cluster. The module is found next to this executable in
// a build tree (build/app/bakesim, build/python/bakesim) or where
// `cmake --install` put it.
int sweep_on_dask(const SweepArgs& a, const std::string& self) {
  const char* python = "/usr/bin/python3";
  std::vector<std::string> argv = {python, "-m", "bakesim", "sweep", a.scene, "--scheduler", a.dask};
  for (const auto& s : a.sets) argv.insert(argv.end(), {"--set", s});
  if (!a.out.empty()) argv.insert(argv.end(), {"--out", a.out});
  if (a.threads > 0) argv.insert(argv.end(), {"--threads", std::to_string(a.threads)});
  if (a.end_time > 0) argv.insert(argv.end(), {"--end-time", fmt::format("{:.17g}", a.end_time)});
  if (a.preview) argv.push_back("--preview");
  if (a.quiet) argv.push_back("--quiet");
  const fs::path build_tree = fs::path(self).parent_path().parent_path() / "python";
  std::error_code ec;
  if (fs::is_regular_file(build_tree / "bakesim" / "__init__.py", ec)) {
    const char* old = std::getenv("PYTHONPATH");
    const std::string path = build_tree.string() + (old && *old ? std::string(":") + old : "");
    ::setenv("PYTHONPATH", path.c_str(), 1);
  }
  std::vector<char*> args;
  for (auto& s : argv) args.push_back(s.data());
  args.push_back(nullptr);
  ::execv(python, args.data());
  throw IoError(std::string("sweep --dask: cannot start ") + python + ": " + std::strerror(errno) +
                " (Debian: python3, python3-distributed, and the bakesim module: docs/python.md)");
}
}  // namespace

int command_sweep(const SweepArgs& a, const std::string& self) {
  if (!a.dask.empty()) return sweep_on_dask(a, self);
  std::vector<SweepAxis> axes;
  for (const auto& s : a.sets) axes.push_back(parse_sweep_axis(s));
  const std::vector<SweepPoint> points = sweep_points(axes);
  if (points.size() < 2)
    throw InputError("sweep",
                     "give at least one --set KEY=V1,V2,... with two or more values (a single run is "
                     "bakesim run)");
  // Every point is checked before anything runs: a bad value is refused with its run's label.
  std::vector<Scene> scenes;
  for (const auto& p : points) {
    std::vector<SceneOverride> overrides;
    for (const auto& s : p.sets) overrides.push_back(parse_override(s));
    try {
      scenes.push_back(load_scene(a.scene, std::move(overrides), a.preview));
    } catch (const InputError& e) {
      throw InputError(e.where(), e.detail() + " (in the sweep's run " + p.label + ")");
    }
    if (a.end_time > 0) set_end_time(scenes.back(), a.end_time);
  }
  const fs::path dir =
      a.out.empty() ? fs::path("out") / (output_component(scenes.front().name) + "-sweep") : fs::path(a.out);

  // The sweep directory: new, empty, or an earlier sweep's (its marker).
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(dir.string(), "exists and is not a directory");
  if (fs::is_directory(dir, ec) && !fs::is_empty(dir, ec) && !fs::is_regular_file(dir / kSweepMarkerFile, ec))
    throw InputError(dir.string(), fmt::format("is not empty and holds no bakesim sweep ({}); choose another --out",
                                               kSweepMarkerFile));
  ensure_directory(dir);
  const RunDirectoryLock lock = RunDirectoryLock::take(dir, kSweepLockFile);
  json marker = json::object();
  if (fs::is_regular_file(dir / kSweepMarkerFile, ec)) {
    try {
      marker = json::parse(read_file(dir / kSweepMarkerFile, 64 << 20));
    } catch (const json::exception&) {
      marker = json::object();  // damaged: its runs are run again (their directories move aside)
    }
    if (!marker.is_object()) marker = json::object();
  }
  marker["scene"] = fs::absolute(a.scene).lexically_normal().string();
  marker["sets"] = a.sets;
  if (!marker.contains("runs") || !marker["runs"].is_object()) marker["runs"] = json::object();
  auto save_marker = [&] { write_file_atomic(dir / kSweepMarkerFile, marker.dump(2) + "\n"); };
  ensure_directory(dir / "runs");
  ensure_directory(dir / "logs");

  // What each point needs: nothing (finished with this very scene), a resume, or a run.
  std::vector<std::string> status(points.size(), "waiting");
  std::vector<std::string> fingerprints;
  std::vector<std::size_t> queue;
  std::vector<bool> resume(points.size(), false);
  for (std::size_t i = 0; i < points.size(); ++i) {
    fingerprints.push_back(scene_fingerprint(scenes[i].resolved));
    const fs::path run_dir = dir / "runs" / points[i].directory;
    const json& earlier = marker["runs"].value(points[i].directory, json::object());
    const bool same = earlier.is_object() && earlier.value("fingerprint", "") == fingerprints[i];
    if (same && earlier.value("status", "") == "done" && fs::is_regular_file(run_dir / "stats.csv", ec)) {
      status[i] = "done";
      continue;
    }
    resume[i] = same && earlier.value("status", "").rfind("stopped", 0) == 0 && !list_checkpoints(run_dir).empty();
    queue.push_back(i);
  }
  const int hw = static_cast<int>(tbb::info::default_concurrency());
  const int jobs = std::max(1, a.jobs > 0 ? a.jobs : std::min<int>(hw, std::max<int>(1, int(queue.size()))));
  const int threads = a.threads > 0 ? a.threads : std::max(1, hw / jobs);
  if (!a.quiet)
    fmt::print(stderr, "bakesim: sweep of {} runs into {}/ ({} to run, {} at a time on {} thread{} each)\n",
               points.size(), dir.string(), queue.size(), jobs, threads, threads == 1 ? "" : "s");

  g_sweep_signal = 0;
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, on_sweep_signal);
  std::vector<Job> running;
  std::size_t next = 0, finished = points.size() - queue.size();
  int forwarded = 0;
  Stopwatch since_status;
  const Stopwatch sweep_clock;
  while (next < queue.size() || !running.empty()) {
    const int sig = g_sweep_signal.load();
    if (sig != 0 && forwarded == 0) {
      forwarded = sig;  // each run checkpoints and stops after its frame
      for (const Job& j : running) ::kill(j.pid, sig);
    }
    while (forwarded == 0 && next < queue.size() && int(running.size()) < jobs) {
      const std::size_t i = queue[next++];
      const fs::path run_dir = dir / "runs" / points[i].directory;
      std::vector<std::string> argv{self, "run"};
      if (resume[i]) {
        argv.insert(argv.end(), {"--resume", run_dir.string()});
      } else {
        argv.push_back(a.scene);
        for (const auto& s : points[i].sets) argv.insert(argv.end(), {"--set", s});
        // runs/ is the sweep's own: an earlier point's run of another scene there (another grid, or a
        // preview) is moved aside into its previous/, never deleted.
        argv.insert(argv.end(), {"--out", run_dir.string(), "--force"});
        if (a.end_time > 0) argv.insert(argv.end(), {"--end-time", fmt::format("{}", a.end_time)});
        if (a.preview) argv.push_back("--preview");
      }
      argv.insert(argv.end(), {"--threads", std::to_string(threads), "--quiet"});
      marker["runs"][points[i].directory] = {{"label", points[i].label},
                                             {"sets", points[i].sets},
                                             {"fingerprint", fingerprints[i]},
                                             {"status", "running"}};
      save_marker();
      running.push_back({i, spawn(argv, dir / "logs" / (points[i].directory + ".txt")), {}});
      status[i] = "running";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    for (std::size_t k = 0; k < running.size();) {
      int st = 0;
      const pid_t got = ::waitpid(running[k].pid, &st, WNOHANG);
      if (got != running[k].pid) {
        ++k;
        continue;
      }
      const std::size_t i = running[k].point;
      status[i] = exit_status(st);
      marker["runs"][points[i].directory]["status"] = status[i];
      marker["runs"][points[i].directory]["wall_seconds"] = running[k].clock.seconds();
      save_marker();
      ++finished;
      if (!a.quiet)
        fmt::print(stderr, "bakesim: [{}/{}] {} {} after {}{}\n", finished, points.size(), points[i].label, status[i],
                   format_duration(running[k].clock.seconds()),
                   status[i] == "done"
                       ? ""
                       : fmt::format(" (see {})", (dir / "logs" / (points[i].directory + ".txt")).string()));
      running.erase(running.begin() + long(k));
    }
    if (!a.quiet && !running.empty() && since_status.seconds() >= 60) {
      std::string line;
      for (const Job& j : running) {
        const Scene& s = scenes[j.point];
        const int total = std::max(1, int(std::ceil(s.end_time * s.fps - 1e-9)));
        line += fmt::format("{}{} frame {}/{}", line.empty() ? "" : ", ", points[j.point].label,
                            std::max(0, frames_written(dir / "runs" / points[j.point].directory) - 1), total);
      }
      fmt::print(stderr, "bakesim: sweep {} in: {}\n", format_duration(sweep_clock.seconds()), line);
      since_status.restart();
    }
  }
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, SIG_DFL);

  std::vector<render::SweepRun> runs;
  for (std::size_t i = 0; i < points.size(); ++i) {
    render::SweepRun r{points[i], status[i], std::nullopt};
    const fs::path run_dir = dir / "runs" / points[i].directory;
    if (fs::is_regular_file(run_dir / "stats.csv", ec)) {
      try {
        r.results = render::read_run_results(run_dir);
      } catch (const InputError&) {
      }
    }
    runs.push_back(std::move(r));
  }
  const render::SweepOutputs outputs = render::write_sweep_outputs(dir, axes, runs);
  if (!a.quiet) {
    fmt::print("{}", outputs.table);
    fmt::print(stderr, "bakesim: sweep of {} runs in {}: {}, {}, plots/ ({} plots), runs/, logs/\n", points.size(),
               format_duration(sweep_clock.seconds()), outputs.csv.string(), outputs.markdown.string(),
               outputs.plots.size());
  }
  if (forwarded != 0) {
    fmt::print(stderr,
               "bakesim: sweep stopped by signal {}: run the same command again to finish it (stopped runs resume "
               "from their checkpoints, finished ones are kept)\n",
               forwarded);
    return 128 + forwarded;
  }
  std::size_t failed = 0;
  for (const auto& s : status) failed += s != "done";
  if (failed > 0) {
    fmt::print(stderr, "bakesim: {} of {} runs did not finish (their logs are in {}/)\n", failed, points.size(),
               (dir / "logs").string());
    return 1;
  }
  return 0;
}

}  // namespace bakesim
