// Regression: the shipped thermomechanical MPM scenes, run at a coarser grid
// for CI, state their outcome (paper Sec 6):
//   - cookies: more leavener ends taller, monotonically over the three
//     leavener scenes; the baseline-mode cookie (Stomakhin et al. 2014: no
//     gas, no water) ends lower than the full-model cookie;
//   - the bread loaf rises (final/initial volume 1.2–2.5) and its core passes 90 °C.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/scene.hpp"
#include "sim/stats.hpp"

using namespace bakesim;

namespace {

struct Outcome {
  double volume_ratio = 0, height = 0, core_temperature = 0;
};

// Runs a scene from scenes/ with the grid coarsened to `cell` to its end.
Outcome bake(const std::string& name, double cell) {
  const std::string dir = std::string(BAKESIM_SOURCE_DIR) + "/scenes";
  std::ifstream in(dir + "/" + name + ".json");
  std::stringstream ss;
  ss << in.rdbuf();
  auto doc = nlohmann::json::parse(ss.str());
  doc["solver"]["mpm"]["cell_size"] = cell;
  Scene scene = parse_scene(doc.dump(), name + ".json", dir);
  mpm::MpmSolver solver(scene.mpm);
  const auto before = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0];
  while (solver.time() < scene.end_time - 1e-12) solver.step(std::min(solver.max_stable_dt(), scene.end_time - solver.time()));
  const auto after = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0];
  Outcome out;
  out.volume_ratio = after.volume / before.volume;
  out.height = after.height();
  for (const auto& [key, value] : solver.frame_quantities())
    if (key.rfind("core_temperature:", 0) == 0) out.core_temperature = value;
  return out;
}

}  // namespace

TEST(MpmBakes, CookiesWithMoreLeavenerEndTallerAndTheBaselineCookieEndsLower) {
  const double cell = 0.005;  // scenes: 3 mm
  const Outcome low = bake("cookie-leavener-low", cell), medium = bake("cookie-leavener-medium", cell),
                high = bake("cookie-leavener-high", cell), baseline = bake("cookie-baseline", cell);
  std::printf("cookie heights: low %.2f, medium %.2f, high %.2f, baseline %.2f mm\n", low.height * 1e3, medium.height * 1e3,
              high.height * 1e3, baseline.height * 1e3);
  RecordProperty("heights_mm", std::to_string(low.height * 1e3) + " " + std::to_string(medium.height * 1e3) + " " +
                                   std::to_string(high.height * 1e3) + " baseline " + std::to_string(baseline.height * 1e3));
  EXPECT_LT(low.height, medium.height);
  EXPECT_LT(medium.height, high.height);
  EXPECT_LT(baseline.height, medium.height);
  EXPECT_LT(low.volume_ratio, high.volume_ratio);
}

TEST(MpmBakes, BreadLoafRisesAndItsCoreBakesThrough) {
  const Outcome loaf = bake("bread-loaf", 0.008);  // scene: 5 mm
  std::printf("bread loaf: volume ratio %.3f, core %.1f degC\n", loaf.volume_ratio, loaf.core_temperature);
  RecordProperty("volume_ratio", std::to_string(loaf.volume_ratio));
  RecordProperty("core_temperature", std::to_string(loaf.core_temperature));
  EXPECT_GE(loaf.volume_ratio, 1.2);
  EXPECT_LE(loaf.volume_ratio, 2.5);
  EXPECT_GT(loaf.core_temperature, 90.0);
}
