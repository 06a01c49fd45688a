// bakesim command line: a thin front end over the library. Turns exceptions
// into messages and exit codes: 0 ok, 1 runtime or I/O failure, 2 bad input,
// 3 the simulation reached an invalid state.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "bench.hpp"
#include "core/errors.hpp"
#include "core/progress.hpp"
#include "io/run_output.hpp"
#include "io/scene.hpp"
#include "io/schema.hpp"

namespace fs = std::filesystem;
using namespace bakesim;

namespace {

constexpr int kExitOk = 0, kExitFailure = 1, kExitBadInput = 2, kExitSimulation = 3;

struct RunArgs {
  std::string scene;
  std::string out;
  int threads = 0;
  double end_time = -1;
  bool quiet = false;
};

int command_validate(const std::string& path) {
  Scene scene = load_scene(path);
  auto solver = make_solver(scene);
  std::cout << describe(scene, *solver);
  std::cout << "scene is valid\n";
  return kExitOk;
}

int command_run(const RunArgs& a) {
  Scene scene = load_scene(a.scene);
  if (a.end_time > 0) {
    scene.end_time = a.end_time;
    scene.resolved["time"]["end"] = a.end_time;
  }
  const int hw = static_cast<int>(tbb::info::default_concurrency());
  const int threads = a.threads > 0 ? a.threads : hw;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

  const fs::path out = a.out.empty() ? fs::path("out") / scene.name : fs::path(a.out);
  RunLog log(!a.quiet);
  auto& L = log.logger();
  L.info("bakesim {} run of {} ({} threads of {})", BAKESIM_VERSION, a.scene, threads, hw);
  auto solver = make_solver(scene);
  L.info("{} particles; output in {}", solver->particles().size(), out.string());
  RunOutput output(out, scene, log);
  ProgressBar progress(stderr, !a.quiet);
  FrameLoopConfig cfg{scene.end_time, scene.fps};
  RunSummary s;
  try {
    s = run_frames(*solver, cfg, output, progress, L);
  } catch (const SimulationError& e) {
    progress.finish();
    L.error("{}", e.what());
    output.flush_log();
    throw;
  }
  L.info("done: {} steps, {} frames, {:.2f} s wall, {:.3g} particle-steps/s", s.steps, s.frames, s.wall_seconds,
         s.particle_steps_per_second);
  L.info("time per step by phase:\n{}", solver->timers().report(s.steps));
  output.flush_log();
  if (!a.quiet) {
    fmt::print(stderr, "bakesim: {} particles, {} steps, {} frames in {} ({:.3g} particle-steps/s on {} threads)\n",
               s.particles, s.steps, s.frames, format_duration(s.wall_seconds), s.particle_steps_per_second, threads);
    fmt::print(stderr, "output: {}/ (particles.pvd, frames/, stats.csv, scene.json, log.txt)\n", out.string());
  }
  return kExitOk;
}

std::vector<long> parse_counts(const std::string& s) {
  std::vector<long> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(std::stol(item));
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
      "  bakesim validate scenes/viscous-funnel.json       check a scene, print what it would simulate\n"
      "  bakesim bench --particles 50000,200000            SPH speed in particle-steps per second\n"
      "  bakesim bench --solver mpm --threads 1,2          MPM speed (100K and 500K points)\n"
      "  bakesim schema --markdown > docs/scene-reference.md\n"
      "Exit codes: 0 ok, 1 runtime or I/O failure, 2 bad input, 3 simulation failure.");

  RunArgs run_args;
  auto* run = app.add_subcommand("run", "Simulate a scene and write frames, stats.csv and log.txt");
  run->add_option("scene", run_args.scene, "Scene file (JSON)")->required();
  run->add_option("--out,-o", run_args.out, "Output directory (default: out/SCENE_NAME)");
  run->add_option("--threads,-j", run_args.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
  run->add_option("--end-time", run_args.end_time, "Override the scene's time.end (s)")->check(CLI::PositiveNumber);
  run->add_flag("--quiet,-q", run_args.quiet, "No progress bar or summary");

  std::string validate_path;
  auto* validate = app.add_subcommand("validate", "Check a scene and print what it would simulate");
  validate->add_option("scene", validate_path, "Scene file (JSON)")->required();

  BenchOptions bench_opt;
  std::string bench_particles, bench_threads, bench_search = "grid,kdtree", bench_models = "elastic,viscoplastic";
  auto* bench = app.add_subcommand("bench", "Benchmark a solver: SPH dam break or MPM cube (particle-steps per second)");
  bench->add_option("--solver", bench_opt.solver, "sph (dam break) or mpm (cube squashed on the floor)")->check(CLI::IsMember({"sph", "mpm"}));
  bench->add_option("--model", bench_models, "MPM: comma-separated materials: elastic, viscoplastic, full (the thermomechanical dough: heat, water, gas)");
  bench->add_option("--particles", bench_particles, "Comma-separated particle counts (default 50000,200000 for SPH, 100000,500000 for MPM)");
  bench->add_option("--threads", bench_threads, "Comma-separated thread counts (default: 1 and all)");
  bench->add_option("--search", bench_search, "Comma-separated neighbour searches: grid, kdtree");
  bench->add_option("--steps", bench_opt.steps, "Timed steps per case")->check(CLI::Range(1, 100000));

  bool markdown = false;
  auto* schema = app.add_subcommand("schema", "Print the scene JSON schema (or its Markdown reference)");
  schema->add_flag("--markdown", markdown, "Print the scene reference in Markdown");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }

  try {
    if (*run) return command_run(run_args);
    if (*validate) return command_validate(validate_path);
    if (*bench) {
      if (bench_particles.empty()) bench_particles = bench_opt.solver == "mpm" ? "100000,500000" : "50000,200000";
      bench_opt.particles = parse_counts(bench_particles);
      if (!bench_threads.empty())
        for (long t : parse_counts(bench_threads)) bench_opt.threads.push_back(int(t));
      bench_opt.searches.clear();
      std::stringstream ss(bench_search);
      std::string item;
      while (std::getline(ss, item, ',')) bench_opt.searches.push_back(item);
      bench_opt.models.clear();
      std::stringstream ms(bench_models);
      while (std::getline(ms, item, ',')) bench_opt.models.push_back(item);
      return run_bench(bench_opt);
    }
    if (*schema) {
      std::cout << (markdown ? scene_schema().markdown_reference() : scene_schema().schema().dump(2) + "\n");
      return kExitOk;
    }
  } catch (const InputError& e) {
    fmt::print(stderr, "bakesim: error: {}\n", e.what());
    return kExitBadInput;
  } catch (const SimulationError& e) {
    fmt::print(stderr, "bakesim: simulation failed: {}\n", e.what());
    return kExitSimulation;
  } catch (const std::exception& e) {
    fmt::print(stderr, "bakesim: error: {}\n", e.what());
    return kExitFailure;
  }
  return kExitFailure;
}
