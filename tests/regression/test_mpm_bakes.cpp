// Regression: the shipped thermomechanical MPM scenes, run at a coarser grid
// for CI (the loaf also on a faster bake clock), state their outcome (paper
// Sec 6):
//   - cookies: more leavener ends taller, monotonically over the three
//     leavener scenes; the baseline-mode cookie (Stomakhin et al. 2014: no
//     gas, no water) ends lower than the full-model cookie;
//   - the bread loaf rises (final/initial volume 1.2–2.5) and its core passes 90 °C
//     but not the boiling point (its dough carries the water model);
//   - the unscored loaf's top crust tears: pairs of crust neighbours pulled
//     more than twice as far apart (none do without set_softening).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/scene.hpp"
#include "sim/bake_stats.hpp"
#include "sim/stats.hpp"

using namespace bakesim;

namespace {

struct Outcome {
  double volume_ratio = 0, height = 0, core_temperature = 0;
  std::size_t crust_bonds = 0, torn_crust_bonds = 0;
};

// Pairs of lattice neighbours among the particles selected by `in_crust` at
// the start, as particle ids.
template <class Select>
std::vector<std::pair<int, int>> crust_bonds(const ParticleSet& ps, Real spacing, Select in_crust) {
  const auto& x = ps.vector("position");
  const auto& id = ps.integer("id");
  std::vector<std::size_t> crust;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (in_crust(x[i])) crust.push_back(i);
  std::vector<std::pair<int, int>> bonds;
  for (std::size_t a = 0; a < crust.size(); ++a)
    for (std::size_t b = a + 1; b < crust.size(); ++b)
      if ((x[crust[a]] - x[crust[b]]).norm() < 1.05 * spacing) bonds.emplace_back(id[crust[a]], id[crust[b]]);
  return bonds;
}

// Runs a scene from scenes/ with the grid coarsened to `cell` to its end.
Outcome bake(const std::string& name, double cell, bool follow_loaf_crust = false) {
  const std::string dir = std::string(BAKESIM_SOURCE_DIR) + "/scenes";
  std::ifstream in(dir + "/" + name + ".json");
  std::stringstream ss;
  ss << in.rdbuf();
  auto doc = nlohmann::json::parse(ss.str());
  doc["solver"]["mpm"]["cell_size"] = cell;
  Scene scene = parse_scene(doc.dump(), name + ".json", dir);
  mpm::MpmSolver solver(scene.mpm);
  const auto before = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0];
  const BakeStatistics bake_stats(solver.particles(), 1);
  // The loaf (axis along z through y = 5 cm, radius 4 cm): its top within 7 mm
  // of the surface, away from the ends; particles start half a cell apart.
  const Real spacing = 0.5 * cell;
  std::vector<std::pair<int, int>> bonds;
  if (follow_loaf_crust)
    bonds = crust_bonds(solver.particles(), spacing, [](const Vec3& p) {
      return std::hypot(p.x(), p.y() - 0.05) > 0.033 && p.y() > 0.06 && std::abs(p.z()) < 0.07;
    });
  while (solver.time() < scene.end_time - 1e-12)
    solver.step(std::min(solver.max_stable_dt(), scene.end_time - solver.time()));
  const auto after = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0];
  Outcome out;
  if (follow_loaf_crust) {
    const auto& x = solver.particles().vector("position");
    const auto& id = solver.particles().integer("id");
    std::vector<std::size_t> index_of(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) index_of[std::size_t(id[i])] = i;
    out.crust_bonds = bonds.size();
    for (const auto& [a, b] : bonds)
      if ((x[index_of[std::size_t(a)]] - x[index_of[std::size_t(b)]]).norm() > 2 * spacing) ++out.torn_crust_bonds;
  }
  out.volume_ratio = after.volume / before.volume;
  out.height = after.height();
  out.core_temperature = bake_stats.compute(solver.particles())[0].core_temperature;
  return out;
}

}  // namespace

TEST(MpmBakes, CookiesWithMoreLeavenerEndTallerAndTheBaselineCookieEndsLower) {
  const double cell = 0.0075;  // scenes: 3 mm (at 6 mm the same order, three times as long)
  const Outcome low = bake("cookie-leavener-low", cell), medium = bake("cookie-leavener-medium", cell),
                high = bake("cookie-leavener-high", cell), baseline = bake("cookie-baseline", cell);
  std::printf("cookie heights: low %.2f, medium %.2f, high %.2f, baseline %.2f mm\n", low.height * 1e3,
              medium.height * 1e3, high.height * 1e3, baseline.height * 1e3);
  RecordProperty("heights_mm", std::to_string(low.height * 1e3) + " " + std::to_string(medium.height * 1e3) + " " +
                                   std::to_string(high.height * 1e3) + " baseline " +
                                   std::to_string(baseline.height * 1e3));
  EXPECT_LT(low.height, medium.height);
  EXPECT_LT(medium.height, high.height);
  EXPECT_LT(baseline.height, medium.height);
  EXPECT_LT(low.volume_ratio, high.volume_ratio);
}

TEST(MpmBakes, BreadLoafRisesItsCoreBakesThroughAndItsCrustTears) {
  // Scene: 5 mm cells, bake clock 2,400 (0.75 s of mechanics). Here 10 mm.
  // The loaf's motion is slow beside its clock: at 10 mm, clock 2,400 gave
  // x1.83 and 222 of 1,568 pairs torn, 1,200 x1.81 and 214, the scene's
  // earlier 600 x1.79 and 196.
  const Outcome loaf = bake("bread-loaf", 0.010, true);
  std::printf("bread loaf: volume ratio %.3f, core %.1f degC, %zu of %zu top-crust bonds torn\n", loaf.volume_ratio,
              loaf.core_temperature, loaf.torn_crust_bonds, loaf.crust_bonds);
  RecordProperty("torn_crust_bonds", std::to_string(loaf.torn_crust_bonds) + " of " + std::to_string(loaf.crust_bonds));
  RecordProperty("volume_ratio", std::to_string(loaf.volume_ratio));
  RecordProperty("core_temperature", std::to_string(loaf.core_temperature));
  EXPECT_GE(loaf.volume_ratio, 1.2);
  EXPECT_LE(loaf.volume_ratio, 2.5);
  EXPECT_GT(loaf.core_temperature, 90.0);
  EXPECT_LE(loaf.core_temperature, 100.5);  // moist crumb stops at the boiling point (152 degC without water)
  // At 10 mm cells 196 of 1,568 tore (12.5%; 112 before the loaf carried the
  // water model); the paper's law tears none (largest stretch ×1.37). Ask for 1%.
  EXPECT_GT(loaf.crust_bonds, 1000u);
  EXPECT_GT(double(loaf.torn_crust_bonds), 0.01 * double(loaf.crust_bonds));
}

// Issue 22 item 1: the 14-line cookie on a tray, from the cookie-dough preset
// (its density, heat capacity and conductivity from its composition, its
// viscosities physical and divided by the bake clock by bakesim).
TEST(MpmBakes, CookieFromThePresetPuffsAndBakesThrough) {
  const Outcome cookie = bake("cookie-on-a-tray", 0.005);  // scene: 3 mm
  std::printf("preset cookie: volume ratio %.3f, height %.2f mm, core %.1f degC\n", cookie.volume_ratio,
              cookie.height * 1e3, cookie.core_temperature);
  RecordProperty("volume_ratio", std::to_string(cookie.volume_ratio));
  EXPECT_GT(cookie.volume_ratio, 1.1);  // the leavener puffs it (at 3 mm: x1.57; here x1.61)
  EXPECT_LT(cookie.volume_ratio, 2.5);
  EXPECT_GT(cookie.core_temperature, 95.0);  // baked through in 12 minutes at 180 degC
  EXPECT_LT(cookie.core_temperature, 180.0);
}
