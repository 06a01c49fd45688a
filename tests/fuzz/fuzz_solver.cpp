// Fuzz target: a scene that loads must build its solver and step without a
// crash. Any input ends as a few finished steps, an InputError (the loader)
// or a SimulationError (the health checks), nothing else. Each input stays
// cheap: a scene whose estimated size passes the caps below is first made
// coarser (its spacing or cell size scaled up), so every shipped scene is
// exercised at low resolution; one that still does not fit is skipped.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/errors.hpp"
#include "io/particle_files.hpp"
#include "io/scene.hpp"
#include "io/scene_parts.hpp"
#include "sim/stats.hpp"

namespace {

using namespace bakesim;
constexpr double kMaxParticles = 2000, kMaxNodes = 60000;
constexpr int kSteps = 4;

// Estimated particles (and MPM grid nodes) of a loaded scene, before the solver allocates anything.
std::pair<double, double> estimated_size(const Scene& s) {
  double points = 0, nodes = 0;
  if (s.solver_type == "sph") {
    for (const auto& b : s.sph.bodies) points += scene_parts::lattice_points(b.shape, s.sph.settings.spacing);
  } else {
    const auto& st = s.mpm.settings;
    const Real spacing = st.cell_size / std::cbrt(Real(st.particles_per_cell));
    for (const auto& b : s.mpm.bodies) points += scene_parts::lattice_points(b.shape, spacing);
    nodes = 1;
    for (int k = 0; k < 3; ++k) nodes *= std::ceil(s.mpm.domain.extent()[k] / st.cell_size) + 1;
  }
  return {points, nodes};
}

void step_and_observe(const Scene& scene) {
  auto solver = make_solver(scene);
  const Real min_dt = scene.resolved["solver"]["min_dt"].get<double>();
  for (int i = 0; i < kSteps; ++i) {
    const Real dt = std::min<Real>(solver->max_stable_dt(), scene.end_time);
    if (!(dt >= min_dt)) break;  // the frame loop reports this as a SimulationError
    solver->step(dt);
  }
  // What a frame writes: statistics, probes, solver totals, a particle file.
  (void)compute_frame_stats(solver->particles());
  for (const auto& p : scene.probes) (void)solver->sample(p.position, p.quantities);
  (void)solver->frame_quantities();
  (void)encode_ply(solver->particles());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  static const bool verbose = std::getenv("BAKESIM_FUZZ_VERBOSE") != nullptr;  // what each input came to
  try {
    Scene scene = parse_scene(text, "fuzz.json", BAKESIM_FUZZ_SCENE_DIR);
    auto [points, nodes] = estimated_size(scene);
    if (points > kMaxParticles || nodes > kMaxNodes) {
      const double coarser = std::max(std::cbrt(points / kMaxParticles), std::cbrt(nodes / kMaxNodes)) * 1.05;
      nlohmann::json doc = scene.resolved;
      auto& settings = doc["solver"][scene.solver_type];
      const char* key = scene.solver_type == "sph" ? "spacing" : "cell_size";
      settings[key] = settings[key].get<double>() * coarser;
      scene = parse_scene(doc.dump(), "fuzz.json (coarsened)", BAKESIM_FUZZ_SCENE_DIR);
      std::tie(points, nodes) = estimated_size(scene);
      if (points > kMaxParticles || nodes > kMaxNodes) return 0;
    }
    step_and_observe(scene);
    if (verbose) std::fprintf(stderr, "stepped: %s, %.0f particles\n", scene.name.c_str(), points);
  } catch (const InputError& e) {
    if (verbose) std::fprintf(stderr, "refused: %s\n", e.what());
  } catch (const SimulationError& e) {
    if (verbose) std::fprintf(stderr, "stopped: %s\n", e.what());
  }
  return 0;
}
