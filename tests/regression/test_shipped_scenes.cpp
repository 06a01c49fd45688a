// Regression: every scene that ships in scenes/, as it is and as --preview runs
// it, sets up every point its bodies sample, body by body: no material is
// silently dropped (an MPM body the domain cuts is an error naming it).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/solver.hpp"
#include "geometry/shapes.hpp"
#include "io/scene.hpp"

using namespace bakesim;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> shipped_scenes() {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(fs::path(BAKESIM_SOURCE_DIR) / "scenes"))
    if (e.path().extension() == ".json") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

// Points the scene's bodies sample, body by body, at the solver's spacing.
std::vector<std::size_t> sampled_per_body(const Scene& scene) {
  std::vector<std::size_t> counts;
  if (scene.solver_type == "mpm") {
    const Real spacing = scene.mpm.settings.cell_size / std::cbrt(Real(scene.mpm.settings.particles_per_cell));
    for (const auto& b : scene.mpm.bodies) counts.push_back(sample_lattice(b.shape, spacing).size());
  } else {
    for (const auto& b : scene.sph.bodies) counts.push_back(sample_lattice(b.shape, scene.sph.settings.spacing).size());
  }
  return counts;
}

}  // namespace

TEST(ShippedScenes, EveryBodyKeepsEveryPointItSamples) {
  const auto files = shipped_scenes();
  ASSERT_GT(files.size(), 20u);
  for (const std::string& file : files)
    for (const bool preview : {false, true}) {
      SCOPED_TRACE(file + (preview ? " --preview" : ""));
      const Scene scene = load_scene(file, {}, preview);
      const std::vector<std::size_t> expected = sampled_per_body(scene);
      const auto solver = make_solver(scene);
      const auto& body = solver->particles().integer("body_id");
      std::vector<std::size_t> kept(expected.size(), 0);
      for (const std::int32_t b : body) {
        ASSERT_GE(b, 0);
        ASSERT_LT(std::size_t(b), kept.size());
        ++kept[b];
      }
      for (std::size_t b = 0; b < expected.size(); ++b) EXPECT_EQ(kept[b], expected[b]) << "body " << b;
    }
}
