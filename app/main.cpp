// bakesim command line: a thin front end over the library. Turns exceptions
// into messages and exit codes: 0 ok, 1 runtime or I/O failure, 2 bad input,
// 3 the simulation reached an invalid state, 128 + N stopped by signal N
// (SIGINT, SIGTERM, SIGHUP) after writing a checkpoint.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <fstream>
#include <optional>
#include <sstream>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "bench.hpp"
#include "sweep.hpp"
#include "core/errors.hpp"
#include "core/progress.hpp"
#include "io/bake_run.hpp"
#include "io/checkpoint.hpp"
#include "io/files.hpp"
#include "io/materials.hpp"
#include "io/run_directory.hpp"
#include "io/run_meshes.hpp"
#include "io/run_output.hpp"
#include "io/scene.hpp"
#include "io/schema.hpp"
#include "render/plot.hpp"
#include "render/run_results.hpp"
#include "render/report.hpp"
#include "render/run_pictures.hpp"

namespace fs = std::filesystem;
using namespace bakesim;

namespace {

constexpr int kExitOk = 0, kExitFailure = 1, kExitBadInput = 2, kExitSimulation = 3;

struct RunArgs {
  std::string scene;
  std::string out;
  std::string resume;
  int threads = 0;
  double end_time = -1;
  int checkpoint_frames = -1;  // -1: the scene's output.checkpoint
  double checkpoint_minutes = -1;
  bool quiet = false;
  bool force = false;
  bool preview = false;           // coarser and fewer frames (preview_overrides), with pictures
  bool pictures = false;          // render pictures while running
  std::vector<std::string> sets;  // --set KEY.PATH=VALUE
};

std::vector<SceneOverride> parse_overrides(const std::vector<std::string>& sets) {
  std::vector<SceneOverride> out;
  for (const auto& s : sets) out.push_back(parse_override(s));
  return out;
}

// SIGINT/SIGTERM/SIGHUP: the first asks the run to stop after the current
// frame (with a checkpoint); a second one ends the process at once.
std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int sig) {
  if (g_stop_signal.exchange(sig) != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

// Control characters of file names and scene text are shown escaped, never sent to the terminal.
std::string printable(const std::string& s) {
  std::string out;
  for (const unsigned char ch : s)
    if ((ch < 0x20 && ch != '\n' && ch != '\t') || ch == 0x7f)
      out += fmt::format("\\x{:02x}", ch);
    else
      out += char(ch);
  return out;
}

// Each body's summary line ends with when its core was done (95 degC, lower
// where the scene's altitude lowers the boiling point: render/run_results.hpp),
// read back from stats.csv so that a resumed run counts its earlier frames.
void append_doneness(std::vector<std::string>& lines, const fs::path& run_dir) {
  if (lines.empty()) return;
  render::RunResults results;
  try {
    results = render::read_run_results(run_dir);
  } catch (const std::exception&) {
    return;
  }
  for (std::string& line : lines)
    for (const render::BodyResults& b : results.bodies)
      if (b.heated && line.starts_with(b.name + ": "))
        line += std::isfinite(b.minutes_to_done)
                    ? fmt::format(", done ({:.3g} degC) after {:.1f} min", results.done_degc, b.minutes_to_done)
                    : fmt::format(", not done ({:.3g} degC not reached)", results.done_degc);
}

int command_validate(const std::string& path, const std::vector<std::string>& sets, bool print_resolved, bool preview) {
  Scene scene = load_scene(path, parse_overrides(sets), preview);
  for (const auto& w : scene.warnings) fmt::print(stderr, "bakesim: warning: {}\n", printable(w));
  auto solver = make_solver(scene);
  for (const auto& w : solver->warnings()) fmt::print(stderr, "bakesim: warning: {}\n", printable(w));
  if (print_resolved) {
    std::cout << scene.resolved.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << describe(scene, *solver);
  std::cout << "scene is valid\n";
  return kExitOk;
}

int command_run(const RunArgs& a) {
  // A resumed run reads its resolved scene and newest valid checkpoint.
  std::optional<ResumePoint> resume;
  Scene scene;
  std::string scene_dir;
  RunDirectoryLock lock;
  if (!a.resume.empty()) {
    resume = open_resume(a.resume);
    lock = std::move(resume->lock);
    scene = std::move(resume->scene);
    scene_dir = resume->scene_dir;
  } else {
    scene = load_scene(a.scene, parse_overrides(a.sets), a.preview);
    scene_dir = fs::absolute(fs::path(a.scene)).parent_path().string();
  }
  if (a.end_time > 0) set_end_time(scene, a.end_time);
  const int hw = static_cast<int>(tbb::info::default_concurrency());
  const int threads = a.threads > 0 ? a.threads : hw;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

  const fs::path out = !a.resume.empty() ? fs::path(a.resume)
                       : a.out.empty()   ? fs::path("out") / output_component(scene.name)
                                         : fs::path(a.out);
  RunLog log(!a.quiet);
  auto& L = log.logger();
  L.info("bakesim {} run of {} ({} threads of {})", BAKESIM_VERSION, a.resume.empty() ? a.scene : a.resume, threads,
         hw);
  for (const auto& base : scene.extends) L.info("extends {}", base);
  for (const auto& note : scene.notes) L.info("{}", note);
  for (const auto& s : a.sets) L.info("--set {}", s);
  if (a.preview)
    L.info("preview: {} {:g} m, {:g} fps, into {}", scene.solver_type == "mpm" ? "cell size" : "spacing",
           scene.solver_type == "mpm" ? scene.resolved["solver"]["mpm"]["cell_size"].get<double>()
                                      : scene.resolved["solver"]["sph"]["spacing"].get<double>(),
           scene.fps, out.string());
  for (const auto& w : scene.warnings) L.warn("{}", w);  // echoed to stderr unless --quiet
  auto solver = make_solver(scene);
  for (const auto& w : solver->warnings()) L.warn("{}", w);
  if (a.resume.empty()) {
    // The directory is claimed only once the scene is known to be good: a bad scene touches nothing.
    RunDirectoryClaim claim = claim_new_run(out, scene.name, a.force);
    lock = std::move(claim.lock);
    if (!claim.moved_aside.empty()) {
      L.info("{} held an earlier run; its files were moved into {}", out.string(), (out / kPreviousRunDir).string());
      if (!a.quiet)
        fmt::print(stderr, "bakesim: {} held an earlier run; moved it into {}/\n", printable(out.string()),
                   printable((out / kPreviousRunDir).string()));
    }
  }
  L.info("{} particles; output in {}", solver->particles().size(), out.string());
  RunOutput output(out, scene, *solver, log);
  FrameLoopConfig cfg = frame_loop_config(scene, *solver);
  const bool baking = is_bake(scene, *solver);
  if (resume) {
    for (const auto& r : resume->refused) L.warn("refused checkpoint: {}", r);
    resume_from(*solver, output, cfg, resume->checkpoint, resume->checkpoint_file.string());
    L.info("resumed from {} (frame {}, t = {:.6g} s, {} steps)", resume->checkpoint_file.string(),
           resume->checkpoint.frame, solver->time(), resume->checkpoint.steps);
  }
  const int total_frames = std::max(1, static_cast<int>(std::ceil(scene.end_time * scene.fps - 1e-9)));
  ProgressBar progress(stderr, !a.quiet);
  // Pictures while the run goes: the first frame, the last, and between them
  // whenever the wall time since the last picture is ten times what that
  // picture took (at most a tenth of the run spent drawing), at least 20 s.
  const bool pictures = (a.pictures || a.preview) &&
                        std::find(scene.output.particle_formats.begin(), scene.output.particle_formats.end(), "ply") !=
                            scene.output.particle_formats.end();
  Stopwatch since_picture;
  double picture_seconds = 0;
  std::vector<fs::path> drawn;
  auto draw = [&](int frame) {
    try {
      Stopwatch clock;
      render::RenderRunOptions opt;
      opt.frames = {frame};
      const auto r = render::render_run(out, opt);
      picture_seconds = clock.seconds();
      since_picture.restart();
      for (const auto& f : r.images) {
        L.info("picture {} ({:.1f} s)", f.string(), picture_seconds);
        drawn.push_back(f);
      }
    } catch (const std::exception& e) {
      L.warn("no picture of frame {}: {}", frame, e.what());
    }
  };
  BakeIntoOptions bake_options;
  bake_options.scene_dir = scene_dir;
  bake_options.cadence = checkpoint_cadence(scene, a.checkpoint_frames, a.checkpoint_minutes);
  bake_options.after_frame = [&](const FrameInfo& info, const Solver&) {
    if (pictures && fs::exists(out / "frames" / (frame_stem(info.frame) + ".ply")) &&
        (drawn.empty() || info.frame == total_frames ||
         since_picture.seconds() >= std::max(20.0, 10 * picture_seconds)))
      draw(info.frame);
    if (baking) progress.set_note(output.progress_note());
    return g_stop_signal.load() == 0;
  };
  g_stop_signal = 0;
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, on_stop_signal);
  const RunSummary s = bake_into(*solver, scene, output, cfg, bake_options, progress, L);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, SIG_DFL);
  if (s.stopped) {
    const int sig = g_stop_signal.load();
    L.warn("stopped by signal {} after frame {}; resume with: bakesim run --resume {}", sig, s.last_frame,
           out.string());
    output.flush_log();
    fmt::print(
        stderr,
        "bakesim: stopped by signal {} after frame {} (checkpoint written); resume with: bakesim run --resume {}\n",
        sig, s.last_frame, printable(out.string()));
    return 128 + sig;
  }
  L.info("done: {} steps, {} frames, {:.2f} s wall, {:.3g} particle-steps/s", s.steps, s.frames, s.wall_seconds,
         s.particle_steps_per_second);
  L.info("time per step by phase:\n{}", solver->timers().report(std::max(1L, s.steps)));
  std::vector<std::string> bake = baking ? output.bake_summary() : std::vector<std::string>{};
  append_doneness(bake, out);
  for (const auto& line : bake) L.info("bake: {}", line);
  output.flush_log();
  if (!a.quiet) {
    fmt::print(stderr, "bakesim: {} particles, {} steps, {} frames in {} ({:.3g} particle-steps/s on {} threads)\n",
               s.particles, s.steps, s.frames, format_duration(s.wall_seconds), s.particle_steps_per_second, threads);
    // What this run wrote (a run without VTU frames has no ParaView series).
    std::vector<std::string> written;
    const auto& formats = scene.output.particle_formats;
    if (std::find(formats.begin(), formats.end(), "vtu") != formats.end()) written.push_back("particles.pvd");
    written.push_back("frames/ (" + fmt::format("{}", fmt::join(formats, ", ")) + ")");
    if (scene.resolved["output"]["mesh"]["enabled"].get<bool>()) written.push_back("meshes/");
    if (!drawn.empty())
      written.push_back(
          fmt::format("render/ ({} pictures, the last {})", drawn.size(), drawn.back().filename().string()));
    for (const char* f : {"stats.csv", "scene.json", "log.txt"}) written.push_back(f);
    fmt::print(stderr, "output: {}/ ({})\n", printable(out.string()), fmt::join(written, ", "));
    if (!bake.empty())
      fmt::print(stderr, "bake of {:.1f} min: {}\n", scene.oven.bake_time(scene.end_time) / 60,
                 printable(fmt::format("{}", fmt::join(bake, "; "))));
  }
  return kExitOk;
}

struct MeshArgs {
  std::string run_dir;
  std::string method = "levelset";
  std::string colour = "browning";
  std::string range;
  std::vector<int> frames;
  double voxel_ratio = 0;
  bool vdb = false;
  int threads = 0;
};

std::optional<std::pair<Real, Real>> parse_range(const std::string& s, const std::string& option) {
  if (s.empty()) return std::nullopt;
  const auto comma = s.find(',');
  try {
    if (comma != std::string::npos) {
      const double lo = std::stod(s.substr(0, comma)), hi = std::stod(s.substr(comma + 1));
      if (hi > lo) return std::make_pair(lo, hi);
    }
  } catch (const std::exception&) {
  }
  throw InputError(option, "expects LOW,HIGH with LOW < HIGH, got '" + s + "'");
}

int command_mesh(const MeshArgs& a) {
  const int threads = a.threads > 0 ? a.threads : static_cast<int>(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  MeshSettings settings;
  settings.surface.method = surface::parse_surface_method(a.method);
  settings.surface.voxel_ratio = a.voxel_ratio;
  settings.colour = a.colour;
  settings.range = parse_range(a.range, "mesh --range");
  settings.vdb = a.vdb;
  Stopwatch clock;
  const MeshRunResult r = mesh_run(a.run_dir, settings, a.frames);
  for (const auto& w : r.warnings) fmt::print(stderr, "bakesim: warning: {}\n", w);
  const auto& frames = r.frames;
  const std::size_t triangles = r.triangles;
  fmt::print(stderr, "bakesim: meshed {} frames ({} method, {} triangles in all) in {} into {}/meshes/{}\n",
             frames.size(), a.method, triangles, format_duration(clock.seconds()), a.run_dir,
             r.collider_files ? fmt::format(" ({} collider meshes in meshes/colliders/)", r.collider_files) : "");
  return kExitOk;
}

// X,Y,Z in metres.
Vec3 parse_point(const std::string& s, const std::string& option) {
  Vec3 p;
  std::stringstream ss(s);
  std::string item;
  int k = 0;
  while (std::getline(ss, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (k >= 3 || used == 0 || used != item.size() || !std::isfinite(v))
      throw InputError(option, "expects X,Y,Z in metres, got '" + s + "'");
    p[k++] = v;
  }
  if (k != 3) throw InputError(option, "expects X,Y,Z in metres, got '" + s + "'");
  return p;
}

std::vector<long> parse_counts(const std::string& s, const std::string& option) {
  std::vector<long> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || end != item.c_str() + item.size() || errno == ERANGE || v < 1)
      throw InputError(option, "expects comma-separated positive whole numbers, got '" + s + "'");
    out.push_back(v);
  }
  if (out.empty()) throw InputError(option, "expects comma-separated positive whole numbers, got nothing");
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bakesim " BAKESIM_VERSION " - baking and cooking simulator (SPH and MPM)", "bakesim"};
  app.set_version_flag("--version", "bakesim " BAKESIM_VERSION);
  app.require_subcommand(1);
  app.footer(
      "Examples:\n"
      "  bakesim run scenes/dam-break.json                 bake into out/dam-break/\n"
      "  bakesim run scenes/dam-break.json --out /tmp/db --threads 2 --end-time 0.5\n"
      "  bakesim run scenes/bread-roll.json --preview      a quick look (8x fewer particles, pictures) in a minute\n"
      "  bakesim run scenes/cookie-baseline.json --set environment.air_temperature=200 --out out/cookie-200\n"
      "  bakesim run --resume out/bread-roll               go on from the newest checkpoint (after Ctrl-C, a crash, a "
      "kill)\n"
      "  bakesim validate scenes/viscous-funnel.json       check a scene, print what it would simulate\n"
      "  bakesim sweep scenes/cookie.json --set environment.air_temperature=150,180,210\n"
      "                                                    three bakes, compared in out/cookie-sweep/sweep.md\n"
      "  bakesim bench --particles 50000,200000            SPH speed in particle-steps per second\n"
      "  bakesim bench --solver mpm --threads 1,2          MPM speed (100K and 500K points)\n"
      "  bakesim bench --scene scenes/bread-roll.json --threads 2   the whole bake, timed per phase\n"
      "  bakesim mesh out/bread-roll                       surface meshes of every frame (PLY, OBJ), colliders\n"
      "  bakesim render out/bread-roll --all --movie       pictures of every frame and an MP4\n"
      "  bakesim render out/bread-roll --mode particles --color temperature\n"
      "  bakesim render out/bread-roll --cut z             the loaf cut in half: crumb inside the crust\n"
      "  bakesim render out/bread-roll --turntable 36 --movie   a turntable movie of the last frame\n"
      "  bakesim mesh out/bread-roll --vdb                 also OpenVDB volumes (surface, temperature, ...)\n"
      "  bakesim plot out/bread-roll                       probe temperatures, volume, height as PNG\n"
      "  bakesim report out/bread-roll                     out/bread-roll/report.html: numbers, pictures, plots\n"
      "  bakesim schema --markdown > docs/scene-reference.md\n"
      "  bakesim materials                                 the material presets (\"preset\": \"cookie-dough\")\n"
      "Exit codes: 0 ok, 1 runtime or I/O failure, 2 bad input, 3 simulation failure, 129/130/143 stopped by "
      "SIGHUP/Ctrl-C/SIGTERM (checkpoint written).");

  RunArgs run_args;
  auto* run = app.add_subcommand("run", "Simulate a scene and write frames, stats.csv and log.txt");
  run->add_option("scene", run_args.scene, "Scene file (JSON)");
  run->add_option("--resume", run_args.resume, "Go on with the run in this directory from its newest valid checkpoint")
      ->excludes(run->get_option("scene"));
  run->add_option("--checkpoint-every", run_args.checkpoint_frames,
                  "Checkpoint every N frames (default: the scene's output.checkpoint)")
      ->check(CLI::Range(0, 1000000));
  run->add_option("--checkpoint-minutes", run_args.checkpoint_minutes,
                  "Checkpoint after M minutes of wall time (default: the scene's, 10)")
      ->check(CLI::Range(0.0, 1e6));
  run->add_option("--out,-o", run_args.out, "Output directory (default: out/SCENE_NAME)");
  run->add_option("--threads,-j", run_args.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
  run->add_option("--end-time", run_args.end_time, "Override the scene's time.end (s)")->check(CLI::PositiveNumber);
  run->add_flag("--quiet,-q", run_args.quiet, "No progress bar or summary");
  run->add_option("--set", run_args.sets,
                  "Change a scene value: KEY.PATH=VALUE, e.g. environment.air_temperature=200 or "
                  "bodies[0].temperature=5 (repeatable; checked like the file; recorded in scene.json)")
      ->excludes(run->get_option("--resume"));
  run->add_flag("--preview", run_args.preview,
                "A quick look: twice the particle spacing (MPM: cell size), so 8x fewer particles, at most 10 frames, "
                "pictures on the way, into out/NAME-preview; the physics and the bake stay as they are")
      ->excludes(run->get_option("--resume"));
  run->add_flag("--pictures", run_args.pictures,
                "Render pictures of frames as they are written into RUN_DIR/render/ (the first, the last, and between "
                "them as often as costs a tenth of the run)");
  run->add_flag("--force", run_args.force,
                "Write into a directory that is not empty or holds another scene's run (bakesim still never replaces "
                "or deletes files it did not write)");

  std::string validate_path;
  std::vector<std::string> validate_sets;
  auto* validate = app.add_subcommand("validate", "Check a scene and print what it would simulate");
  validate->add_option("scene", validate_path, "Scene file (JSON)")->required();
  validate->add_option("--set", validate_sets, "Change a scene value: KEY.PATH=VALUE (as for run)");
  bool validate_resolved = false, validate_preview = false;
  validate->add_flag("--preview", validate_preview, "Check the scene as run --preview would run it");
  validate->add_flag("--resolved", validate_resolved,
                     "Print the resolved scene as JSON (bases merged, --set applied, every default filled in): what a "
                     "run writes as scene.json");

  BenchOptions bench_opt;
  std::string bench_particles, bench_threads, bench_search = "grid,kdtree", bench_models = "elastic,viscoplastic";
  auto* bench =
      app.add_subcommand("bench", "Benchmark a solver: SPH dam break or MPM cube (particle-steps per second)");
  bench->add_option("--solver", bench_opt.solver, "sph (dam break) or mpm (cube squashed on the floor)")
      ->check(CLI::IsMember({"sph", "mpm"}));
  bench->add_option(
      "--model", bench_models,
      "MPM: comma-separated materials: elastic, viscoplastic, full (the thermomechanical dough: heat, water, gas)");
  bench->add_option("--particles", bench_particles,
                    "Comma-separated particle counts (default 50000,200000 for SPH, 100000,500000 for MPM)");
  bench->add_option("--threads", bench_threads, "Comma-separated thread counts (default: 1 and all)");
  bench->add_option("--search", bench_search, "Comma-separated neighbour searches: grid, kdtree");
  bench
      ->add_option("--skin", bench_opt.skins,
                   "SPH: comma-separated Verlet skins, fractions of the support (default: the scene default; 0: "
                   "search every step)")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 1.0));
  bench->add_option("--steps", bench_opt.steps, "Timed steps per case")->check(CLI::Range(1, 100000));
  bench->add_option("--scene", bench_opt.scene,
                    "Time a scene file's whole run instead (a bake; no output written): per thread count the wall "
                    "time, particle-steps/s, the steps each time-step bound limited and the time per phase");
  bench->add_option("--set", bench_opt.sets, "With --scene: override a scene value, KEY.PATH=VALUE (repeatable)");
  bench->add_flag("--preview", bench_opt.preview, "With --scene: its preview (bakesim run --preview)");
  bench->add_option("--end-time", bench_opt.end_time, "With --scene: stop at this simulated time (s)")
      ->check(CLI::PositiveNumber);

  MeshArgs mesh_args;
  auto* mesh =
      app.add_subcommand("mesh", "Reconstruct surface meshes (PLY, OBJ+MTL) of a run's frames into RUN_DIR/meshes/");
  mesh->add_option("run_dir", mesh_args.run_dir, "Run directory (made by bakesim run)")->required();
  mesh->add_option("--method", mesh_args.method, "levelset (default) or wyvill (the thesis's field, Eq 3.59-3.60)")
      ->check(CLI::IsMember({"levelset", "wyvill"}));
  mesh->add_option("--color,--colour", mesh_args.colour,
                   "Quantity the vertices are coloured by: browning (default), temperature, saturation, ...");
  mesh->add_option("--range", mesh_args.range,
                   "LOW,HIGH of the colour quantity (default: browning 0,1; temperature 20,220)");
  mesh->add_option("--frame", mesh_args.frames, "Frame numbers to mesh (default: all)");
  mesh->add_option("--voxel", mesh_args.voxel_ratio,
                   "Voxel size as a fraction of the particle spacing (default: levelset 0.75, wyvill 0.5)")
      ->check(CLI::Range(0.1, 2.0));
  mesh->add_flag("--vdb", mesh_args.vdb,
                 "Also write NNNNN.vdb per frame: the level set \"surface\" and float grids temperature, browning, "
                 "moisture (OpenVDB; for Houdini, Blender, vdb_print)");
  mesh->add_option("--threads,-j", mesh_args.threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));

  render::RenderRunOptions render_opt;
  std::string render_range, render_method = "levelset", render_camera, render_look_at;
  double render_fov = 0;
  int render_threads = 0;
  auto* render_cmd = app.add_subcommand("render", "Draw PNG pictures of a run's frames into RUN_DIR/render/");
  render_cmd->add_option("run_dir", mesh_args.run_dir, "Run directory (made by bakesim run)")->required();
  render_cmd->add_option("--frame", render_opt.frames, "Frame numbers (default: the last frame)");
  render_cmd->add_flag("--all", render_opt.all_frames, "Every frame with a particle file");
  render_cmd->add_option("--mode", render_opt.mode, "mesh (the surface, default) or particles")
      ->check(CLI::IsMember({"mesh", "particles"}));
  render_cmd->add_option("--color,--colour", render_opt.colour,
                         "browning, temperature, saturation, speed or any particle quantity (default: the scene's "
                         "render.colour, else browning)");
  render_cmd->add_option("--range", render_range, "LOW,HIGH of the colour quantity");
  render_cmd->add_option("--method", render_method, "Surface method for --mode mesh: levelset or wyvill")
      ->check(CLI::IsMember({"levelset", "wyvill"}));
  render_cmd->add_option("--width", render_opt.width, "Picture width (default: the scene's render.width, 1280)")
      ->check(CLI::Range(16, 8192));
  render_cmd->add_option("--height", render_opt.height, "Picture height (default: the scene's render.height, 720)")
      ->check(CLI::Range(16, 8192));
  render_cmd->add_flag("--movie", render_opt.movie, "Also assemble an MP4 of the rendered frames (needs ffmpeg)");
  render_cmd->add_flag("--strip", render_opt.strip, "Also write an image strip of up to six of the rendered frames");
  render_cmd->add_option("--camera", render_camera,
                         "Camera position X,Y,Z (m); default: the scene's render.camera, "
                         "else front-right and above, framing the bodies");
  render_cmd->add_option("--look-at", render_look_at, "Point the camera looks at, X,Y,Z (m)");
  render_cmd->add_option("--fov", render_fov, "Vertical field of view, degrees")->check(CLI::Range(1.0, 170.0));
  render_cmd
      ->add_option("--turntable", render_opt.turntable,
                   "N views of each frame, the camera circling the vertical axis (files ...-turn-KKK.png)")
      ->check(CLI::Range(1, 3600));
  render_cmd->add_option("--cut", render_opt.cut,
                         "Cut view: x, y or z (through the bodies' middle) or AXIS=METRES; the side of larger "
                         "coordinates is cut away and the cut face coloured like the surface (--colour)");
  render_cmd->add_option("--threads,-j", render_threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));

  SweepArgs sweep_args;
  auto* sweep = app.add_subcommand(
      "sweep", "Run a scene over a grid of values (--set KEY=V1,V2,...) and compare the bakes in a table and plots");
  sweep->add_option("scene", sweep_args.scene, "Scene file (JSON)")->required();
  sweep
      ->add_option("--set", sweep_args.sets,
                   "KEY.PATH=V1,V2,... : the values of one axis of the grid (repeatable: every combination runs; "
                   "one value applies to every run)")
      ->required();
  sweep->add_option("--out,-o", sweep_args.out, "Sweep directory (default: out/SCENE_NAME-sweep)");
  sweep->add_option("--jobs", sweep_args.jobs, "Runs at a time (default: one per core, at most the runs)")
      ->check(CLI::Range(1, 1024));
  sweep->add_option("--threads,-j", sweep_args.threads, "Threads per run (default: the cores shared among the jobs)")
      ->check(CLI::Range(1, 4096));
  sweep->add_option("--end-time", sweep_args.end_time, "Override the scene's time.end (s) for every run")
      ->check(CLI::PositiveNumber);
  sweep->add_flag("--quiet,-q", sweep_args.quiet, "No progress lines or table");
  sweep->add_flag("--preview", sweep_args.preview, "Every run as run --preview (a quick look at the grid)");
  auto* dask_option = sweep->add_option(
      "--dask", sweep_args.dask,
      "Where the runs go on Dask: 'local' (a LocalCluster on this machine; the default when python3-distributed "
      "and the Python module are installed) or a scheduler's address (tcp://HOST:8786); docs/python.md");
  sweep->add_flag("--processes", sweep_args.processes, "Run every run as a process here, without Dask")
      ->excludes(dask_option);

  std::string report_dir;
  render::ReportOptions report_opt;
  std::string report_out;
  auto* report = app.add_subcommand(
      "report", "Write RUN_DIR/report.html: the bake's numbers, pictures and plots on one self-contained page");
  report->add_option("run_dir", report_dir, "Run directory (made by bakesim run)")->required();
  report->add_option("--compare", report_opt.compare,
                     "Measured data to overlay: a CSV with t_s or t_min and columns ending in _C, _m or moisture_db; "
                     "FILE=COLUMN also compares it with that stats.csv column (repeatable)");
  report->add_option("--out,-o", report_out, "The page to write (default RUN_DIR/report.html)");

  std::string plot_dir;
  auto* plot =
      app.add_subcommand("plot", "Plot a run's stats.csv into RUN_DIR/plots/ (temperatures, volume, height, moisture)");
  plot->add_option("run_dir", plot_dir, "Run directory (made by bakesim run)")->required();

  bool materials_markdown_flag = false;
  auto* materials_cmd = app.add_subcommand("materials", "List the material presets (materials/*.json, compiled in)");
  materials_cmd->add_flag("--markdown", materials_markdown_flag,
                          "Print docs/materials.md: every preset, its values and sources");

  bool markdown = false;
  auto* schema = app.add_subcommand("schema", "Print the scene JSON schema (or its Markdown reference)");
  schema->add_flag("--markdown", markdown, "Print the scene reference in Markdown");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }

  // A file-size limit (ulimit -f) makes the write fail with EFBIG, reported with the file's name, instead of
  // killing the process without a word; a closed pipe on stderr does not kill a run either.
  std::signal(SIGXFSZ, SIG_IGN);
  std::signal(SIGPIPE, SIG_IGN);
  try {
    if (*run) {
      if (run_args.scene.empty() && run_args.resume.empty())
        throw InputError("run", "give a scene file, or --resume RUN_DIR");
      return command_run(run_args);
    }
    if (*sweep) {
      std::error_code ec;
      const fs::path self = fs::read_symlink("/proc/self/exe", ec);
      return command_sweep(sweep_args, ec ? std::string(argv[0]) : self.string());
    }
    if (*validate) return command_validate(validate_path, validate_sets, validate_resolved, validate_preview);
    if (*mesh) return command_mesh(mesh_args);
    if (*render_cmd) {
      const int threads = render_threads > 0 ? render_threads : static_cast<int>(tbb::info::default_concurrency());
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
      render_opt.range = parse_range(render_range, "render --range");
      if (!render_camera.empty()) render_opt.camera_position = parse_point(render_camera, "render --camera");
      if (!render_look_at.empty()) render_opt.look_at = parse_point(render_look_at, "render --look-at");
      if (render_fov > 0) render_opt.field_of_view = render_fov;
      render_opt.method = surface::parse_surface_method(render_method);
      Stopwatch clock;
      const auto r = render::render_run(mesh_args.run_dir, render_opt);
      fmt::print(stderr, "bakesim: {} picture(s) in {}: {}{}{}\n", r.images.size(), format_duration(clock.seconds()),
                 r.images.size() == 1 ? r.images[0].string() : (fs::path(mesh_args.run_dir) / "render/").string(),
                 r.strip ? ", strip " + r.strip->string() : "", r.movie ? ", movie " + r.movie->string() : "");
      if (!r.note.empty()) fmt::print(stderr, "bakesim: {}\n", r.note);
      return kExitOk;
    }
    if (*report) {
      report_opt.output = report_out;
      report_opt.generator = "bakesim " BAKESIM_VERSION;
      // The pictures it may draw go into render/: not while a run writes there.
      RunDirectoryLock lock;
      try {
        lock = claim_existing_run(report_dir);
      } catch (const InputError&) {
        if (!fs::is_regular_file(fs::path(report_dir) / "stats.csv")) throw;
        report_opt.draw_pictures = false;  // a run in progress: report what it has written so far
      }
      const auto r = render::write_report(report_dir, report_opt);
      for (const auto& n : r.notes) fmt::print(stderr, "bakesim: note: {}\n", printable(n));
      fmt::print("{}\n", r.file.string());
      return kExitOk;
    }
    if (*plot) {
      const auto files = render::plot_run(plot_dir);
      for (const auto& f : files) fmt::print("{}\n", f.string());
      return kExitOk;
    }
    if (*bench) {
      if (bench_particles.empty()) bench_particles = bench_opt.solver == "mpm" ? "100000,500000" : "50000,200000";
      bench_opt.particles = parse_counts(bench_particles, "bench --particles");
      if (!bench_threads.empty())
        for (long t : parse_counts(bench_threads, "bench --threads"))
          bench_opt.threads.push_back(int(std::min(t, 4096L)));
      bench_opt.searches.clear();
      std::stringstream ss(bench_search);
      std::string item;
      while (std::getline(ss, item, ',')) bench_opt.searches.push_back(item);
      bench_opt.models.clear();
      std::stringstream ms(bench_models);
      while (std::getline(ms, item, ',')) bench_opt.models.push_back(item);
      if (bench_opt.scene.empty() && (!bench_opt.sets.empty() || bench_opt.preview || bench_opt.end_time > 0))
        throw InputError("bench", "--set, --preview and --end-time time a scene: give it with --scene");
      return run_bench(bench_opt);
    }
    if (*materials_cmd) {
      if (materials_markdown_flag) {
        std::cout << materials_markdown();
      } else {
        for (const auto& name : material_preset_names()) {
          const auto p = material_preset(name, "materials");
          fmt::print("{:18} {:9} {}\n", name, fmt::format("{}", fmt::join(preset_solvers(p), ",")),
                     p.value("description", ""));
        }
      }
      return kExitOk;
    }
    if (*schema) {
      std::cout << (markdown ? scene_schema().markdown_reference() : scene_schema().schema().dump(2) + "\n");
      return kExitOk;
    }
  } catch (const InputError& e) {
    fmt::print(stderr, "bakesim: error: {}\n", printable(e.what()));
    return kExitBadInput;
  } catch (const SimulationError& e) {
    fmt::print(stderr, "bakesim: simulation failed: {}\n", printable(e.what()));
    return kExitSimulation;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "bakesim: error: out of memory (the scene needs more memory than this machine has free)\n");
    return kExitFailure;
  } catch (const std::exception& e) {
    fmt::print(stderr, "bakesim: error: {}\n", printable(e.what()));
    return kExitFailure;
  }
  return kExitFailure;
}
