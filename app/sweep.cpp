#include "sweep.hpp"

#include <fcntl.h>
#include <poll.h>
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
#include <memory>
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

// Starts `argv` in a process group of its own (a Ctrl-C reaches the sweep,
// which passes it on once: a second SIGINT would end a run without its
// checkpoint) that dies with the sweep. stdout and stderr go into `log`;
// with `pipes`, stdin and stdout are pipes instead (their other ends returned).
struct Spawned {
  pid_t pid = -1;
  int to_child = -1, from_child = -1;
};
Spawned spawn(const std::vector<std::string>& argv, const fs::path& log, bool pipes = false) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(log.string() + ": cannot open: " + std::strerror(errno));
  int in[2] = {-1, -1}, out[2] = {-1, -1};
  if (pipes && (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0)) {
    ::close(fd);
    throw IoError(std::string("cannot make a pipe: ") + std::strerror(errno));
  }
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
    if (pipes) {
      ::dup2(in[0], 0);
      ::dup2(out[1], 1);
    } else {
      ::dup2(fd, 1);
    }
    ::dup2(fd, 2);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  ::close(fd);
  Spawned child{pid};
  if (pipes) {
    ::close(in[0]);
    ::close(out[1]);
    child.to_child = in[1];
    child.from_child = out[0];
  }
  return child;
}

// A run's end as the sweep reports it: exited with `code`, or killed by `signal`.
std::string run_status(bool exited, int code_or_signal) {
  if (exited) {
    if (code_or_signal == 0) return "done";
    if (code_or_signal > 128) return fmt::format("stopped (signal {})", code_or_signal - 128);
    return fmt::format("failed (exit {})", code_or_signal);
  }
  return fmt::format("killed (signal {})", code_or_signal);
}

std::string exit_status(int status) {
  if (WIFEXITED(status)) return run_status(true, WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return run_status(false, WTERMSIG(status));
  return "failed";
}

// Where the sweep's runs execute: `bakesim run` processes here, or tasks on
// a Dask cluster. Both take a run's command line and its log file and say
// when it ends; the sweep around them is the same.
class RunLauncher {
 public:
  virtual ~RunLauncher() = default;
  virtual void start(std::size_t run, const std::vector<std::string>& argv, const fs::path& log) = 0;
  // Waits up to `wait` for runs to end; returns those that did, with their status.
  virtual std::vector<std::pair<std::size_t, std::string>> wait_for_ends(std::chrono::milliseconds wait) = 0;
  // Passes a signal on to every run started and not ended (each checkpoints and stops).
  virtual void signal_runs(int sig) = 0;
};

class ProcessLauncher final : public RunLauncher {
 public:
  void start(std::size_t run, const std::vector<std::string>& argv, const fs::path& log) override {
    running_.emplace_back(run, spawn(argv, log).pid);
  }
  std::vector<std::pair<std::size_t, std::string>> wait_for_ends(std::chrono::milliseconds wait) override {
    std::this_thread::sleep_for(wait);
    std::vector<std::pair<std::size_t, std::string>> ended;
    for (std::size_t k = 0; k < running_.size();) {
      int st = 0;
      if (::waitpid(running_[k].second, &st, WNOHANG) != running_[k].second) {
        ++k;
        continue;
      }
      ended.emplace_back(running_[k].first, exit_status(st));
      running_.erase(running_.begin() + long(k));
    }
    return ended;
  }
  void signal_runs(int sig) override {
    for (const auto& [run, pid] : running_) ::kill(pid, sig);
  }

 private:
  std::vector<std::pair<std::size_t, pid_t>> running_;
};

// The runs as tasks on a dask.distributed cluster, through the Python
// module's helper (python/bakesim/dask_runs.py: its line protocol is there).
class DaskLauncher final : public RunLauncher {
 public:
  // Starts the helper and waits for it to connect. Throws IoError when it
  // cannot; `unavailable` is set when Dask or the module is not installed.
  DaskLauncher(const std::string& scheduler, int local_workers, const std::string& self, const fs::path& log,
               bool& unavailable) {
    unavailable = false;
    std::vector<std::string> argv = {kPython,
                                     "-m",
                                     "bakesim.dask_runs",
                                     "--scheduler",
                                     scheduler,
                                     "--workers",
                                     std::to_string(std::max(1, local_workers))};
    // The module next to this executable in a build tree (build/app/bakesim, build/python/bakesim), else
    // where `cmake --install` put it.
    const fs::path build_tree = fs::path(self).parent_path().parent_path() / "python";
    std::error_code ec;
    const char* old = std::getenv("PYTHONPATH");
    const std::string saved = old ? old : "";
    if (fs::is_regular_file(build_tree / "bakesim" / "dask_runs.py", ec))
      ::setenv("PYTHONPATH", (build_tree.string() + (saved.empty() ? "" : ":" + saved)).c_str(), 1);
    helper_ = spawn(argv, log, true);
    if (old)
      ::setenv("PYTHONPATH", saved.c_str(), 1);
    else
      ::unsetenv("PYTHONPATH");
    // Connecting to a remote scheduler may take Dask's own 30 s timeout.
    for (const Stopwatch clock; clock.seconds() < 60;) {
      for (const std::string& line : read_lines(std::chrono::milliseconds(200))) {
        const json message = json::parse(line, nullptr, false);
        if (message.is_object() && message.contains("ready")) {
          slots_ = message.value("slots", 1);
          scheduler_ = message.value("scheduler", scheduler);
          return;
        }
        if (message.is_object() && message.contains("unavailable")) {
          unavailable = true;
          close_helper();
          throw IoError("sweep on Dask: " + message.value("unavailable", std::string()) +
                        " (Debian: python3-distributed)");
        }
      }
      int st = 0;
      if (::waitpid(helper_.pid, &st, WNOHANG) == helper_.pid) {
        helper_.pid = -1;
        // The module itself missing (not built, not installed) is "unavailable" too.
        const std::string text = read_file(log, 1 << 20);
        unavailable = text.find("No module named 'bakesim") != std::string::npos;
        close_helper();
        if (unavailable)
          throw IoError(
              "sweep on Dask: the bakesim Python module is not installed (cmake --install build, or "
              "PYTHONPATH=build/python; docs/python.md)");
        throw IoError(fmt::format("sweep on Dask: the helper ended before it connected ({}): see {}", exit_status(st),
                                  log.string()));
      }
    }
    close_helper();
    throw IoError("sweep on Dask: no connection to the scheduler " + scheduler + " within 60 s (see " + log.string() +
                  ")");
  }
  ~DaskLauncher() override { close_helper(); }

  int slots() const { return slots_; }
  const std::string& scheduler() const { return scheduler_; }

  void start(std::size_t run, const std::vector<std::string>& argv, const fs::path& log) override {
    std::error_code ec;
    send({{"start", run}, {"argv", argv}, {"log", fs::absolute(log).string()}, {"cwd", fs::current_path(ec).string()}});
    ++in_flight_;
  }
  std::vector<std::pair<std::size_t, std::string>> wait_for_ends(std::chrono::milliseconds wait) override {
    std::vector<std::pair<std::size_t, std::string>> ended;
    for (const std::string& line : read_lines(wait)) {
      const json message = json::parse(line, nullptr, false);
      if (!message.is_object() || !message.contains("finished")) continue;
      const auto run = message["finished"].get<std::size_t>();
      std::string status;
      if (message.contains("returncode")) {
        const int code = message["returncode"].get<int>();
        status = code >= 0 ? run_status(true, code) : run_status(false, -code);
      } else {
        status = "failed (Dask: " + message.value("error", std::string("unknown")) + ")";
      }
      ended.emplace_back(run, status);
      --in_flight_;
    }
    // The helper gone: the runs it held cannot report any more.
    if (helper_.pid > 0 && in_flight_ > 0) {
      int st = 0;
      if (::waitpid(helper_.pid, &st, WNOHANG) == helper_.pid) {
        helper_.pid = -1;
        throw IoError("sweep on Dask: the helper ended with runs still out (" + exit_status(st) + ")");
      }
    }
    return ended;
  }
  void signal_runs(int sig) override { send({{"signal", sig}}); }

 private:
  static constexpr const char* kPython = "/usr/bin/python3";

  void send(const json& message) {
    const std::string line = message.dump() + "\n";
    std::size_t done = 0;
    while (done < line.size()) {
      const ssize_t n = ::write(helper_.to_child, line.data() + done, line.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw IoError(std::string("sweep on Dask: cannot reach the helper: ") + std::strerror(errno));
      done += std::size_t(n);
    }
  }
  // Complete lines from the helper, waiting up to `wait` for the first.
  std::vector<std::string> read_lines(std::chrono::milliseconds wait) {
    std::vector<std::string> lines;
    pollfd p{helper_.from_child, POLLIN, 0};
    if (helper_.from_child >= 0 && ::poll(&p, 1, int(wait.count())) > 0) {
      char chunk[4096];
      const ssize_t n = ::read(helper_.from_child, chunk, sizeof chunk);
      if (n > 0) buffer_.append(chunk, std::size_t(n));
      if (n == 0) {  // end of its output: do not poll a closed pipe in a tight loop
        ::close(helper_.from_child);
        helper_.from_child = -1;
      }
    } else if (helper_.from_child < 0) {
      std::this_thread::sleep_for(wait);
    }
    for (std::size_t eol; (eol = buffer_.find('\n')) != std::string::npos;) {
      lines.push_back(buffer_.substr(0, eol));
      buffer_.erase(0, eol + 1);
    }
    return lines;
  }
  // End of input tells the helper to stop what still runs and exit; it is waited for.
  void close_helper() {
    if (helper_.to_child >= 0) ::close(helper_.to_child);
    helper_.to_child = -1;
    if (helper_.pid > 0) {
      int st = 0;
      for (const Stopwatch clock; clock.seconds() < 30;) {
        if (::waitpid(helper_.pid, &st, WNOHANG) == helper_.pid) {
          helper_.pid = -1;
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      if (helper_.pid > 0) {
        ::kill(helper_.pid, SIGKILL);
        ::waitpid(helper_.pid, &st, 0);
        helper_.pid = -1;
      }
    }
    if (helper_.from_child >= 0) ::close(helper_.from_child);
    helper_.from_child = -1;
  }

  Spawned helper_;
  std::string buffer_;
  std::string scheduler_;
  int slots_ = 1;
  int in_flight_ = 0;
};

// Frames written so far by the run in `dir` (rows of its stats.csv).
int frames_written(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / "stats.csv", ec)) return 0;
  const std::string text = read_file(dir / "stats.csv");
  return std::max<int>(0, int(std::count(text.begin(), text.end(), '\n')) - 1);
}

}  // namespace

int command_sweep(const SweepArgs& a, const std::string& self) {
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
    // A run the marker still calls "running" was left by a sweep that ended without hearing from it (killed,
    // or its Dask helper lost); no sweep runs here now (the lock), so it goes on from its newest checkpoint
    // like a stopped one (a run process still alive holds its directory's lock and the resume says so).
    const std::string was = earlier.value("status", "");
    resume[i] = same && (was.rfind("stopped", 0) == 0 || was == "running") && !list_checkpoints(run_dir).empty();
    queue.push_back(i);
  }
  const int hw = static_cast<int>(tbb::info::default_concurrency());
  const int local_jobs = std::max(1, a.jobs > 0 ? a.jobs : std::min<int>(hw, std::max<int>(1, int(queue.size()))));
  int jobs = local_jobs;
  int threads = a.threads > 0 ? a.threads : std::max(1, hw / jobs);
  // On Dask (a LocalCluster unless --dask names a scheduler) where the Python module and
  // python3-distributed are installed, else (or with --processes) as processes here.
  std::unique_ptr<RunLauncher> launcher;
  std::string where = "as processes here";
  if (!a.processes && !queue.empty()) {
    const std::string scheduler = a.dask.empty() ? "local" : a.dask;
    bool unavailable = false;
    try {
      auto dask = std::make_unique<DaskLauncher>(scheduler, local_jobs, self, dir / "logs" / "dask.txt", unavailable);
      if (scheduler != "local") {
        // A cluster's size is its workers' threads, one run on each; a run's threads are its own.
        jobs = a.jobs > 0 ? a.jobs : std::max(1, dask->slots());
        threads = a.threads > 0 ? a.threads : 1;
        where = "on the Dask scheduler " + dask->scheduler();
      } else {
        where = "on a Dask LocalCluster";
      }
      launcher = std::move(dask);
    } catch (const IoError& e) {
      if (!a.dask.empty()) throw;
      if (!a.quiet)
        fmt::print(stderr, "bakesim: {}{}: the runs go as processes here\n", e.what(),
                   unavailable ? "" : " (dask.txt in the sweep's logs/)");
    }
  }
  if (!launcher) launcher = std::make_unique<ProcessLauncher>();
  if (!a.quiet)
    fmt::print(stderr, "bakesim: sweep of {} runs into {}/ ({} to run, {} at a time on {} thread{} each, {})\n",
               points.size(), dir.string(), queue.size(), jobs, threads, threads == 1 ? "" : "s", where);

  g_sweep_signal = 0;
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, on_sweep_signal);
  struct Running {
    std::size_t point;
    Stopwatch clock;
  };
  std::vector<Running> running;
  std::size_t next = 0, finished = points.size() - queue.size();
  int forwarded = 0;
  Stopwatch since_status;
  const Stopwatch sweep_clock;
  while (next < queue.size() || !running.empty()) {
    const int sig = g_sweep_signal.load();
    if (sig != 0 && forwarded == 0) {
      forwarded = sig;  // each run checkpoints and stops after its frame
      launcher->signal_runs(sig);
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
      launcher->start(i, argv, dir / "logs" / (points[i].directory + ".txt"));
      running.push_back({i, {}});
      status[i] = "running";
    }
    for (const auto& [i, ended_status] : launcher->wait_for_ends(std::chrono::milliseconds(200))) {
      const auto it = std::find_if(running.begin(), running.end(), [&](const Running& r) { return r.point == i; });
      if (it == running.end()) continue;
      status[i] = ended_status;
      marker["runs"][points[i].directory]["status"] = status[i];
      marker["runs"][points[i].directory]["wall_seconds"] = it->clock.seconds();
      save_marker();
      ++finished;
      if (!a.quiet)
        fmt::print(stderr, "bakesim: [{}/{}] {} {} after {}{}\n", finished, points.size(), points[i].label, status[i],
                   format_duration(it->clock.seconds()),
                   status[i] == "done"
                       ? ""
                       : fmt::format(" (see {})", (dir / "logs" / (points[i].directory + ".txt")).string()));
      running.erase(it);
    }
    if (!a.quiet && !running.empty() && since_status.seconds() >= 60) {
      std::string line;
      for (const Running& j : running) {
        const Scene& s = scenes[j.point];
        const int total = std::max(1, int(std::ceil(s.end_time * s.fps - 1e-9)));
        line += fmt::format("{}{} frame {}/{}", line.empty() ? "" : ", ", points[j.point].label,
                            std::max(0, frames_written(dir / "runs" / points[j.point].directory) - 1), total);
      }
      fmt::print(stderr, "bakesim: sweep {} in: {}\n", format_duration(sweep_clock.seconds()), line);
      since_status.restart();
    }
  }
  launcher.reset();  // the Dask helper and its cluster closed before the table is written
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
