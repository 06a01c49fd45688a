// Regression: the shipped bread-roll scene (thesis Fig 4.3/4.8), run at a
// coarser spacing for CI, must rise (final/initial volume 1.5–3.5), stay
// inside its tin, keep every state finite, heat its core monotonically, and
// keep its risen crumb from exchanging heat with the oven air.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "io/scene.hpp"
#include "sim/stats.hpp"
#include "sph/solver.hpp"

using namespace bakesim;

TEST(BreadRoll, RisesStaysInItsTinAndBakesThrough) {
  // ~2,900 particles instead of ~20,000.
  Scene scene = load_scene(std::string(BAKESIM_SOURCE_DIR) + "/scenes/bread-roll.json",
                           {parse_override("solver.sph.spacing=0.003")});
  sph::SphSolver solver(scene.sph);

  const auto& tin = std::get<ContainerCollider>(scene.sph.colliders.at(0).geometry).inner;
  const double v0 = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0].volume;
  // The core thermocouple follows the particle that starts at the centre.
  const Vec3 centre(0.0, 0.021, 0.0);
  const auto& x0 = solver.particles().vector("position");
  std::size_t core = 0;
  for (std::size_t i = 0; i < x0.size(); ++i)
    if ((x0[i] - centre).norm() < (x0[core] - centre).norm()) core = i;
  const int core_id = solver.particles().integer("id")[core];

  const double end = 0.6;  // 450 s of bake on the scene's clock of 750
  double last_core = -1e9, max_drop = 0;
  long outside = 0;
  while (solver.time() < end - 1e-12) {
    solver.step(std::min(solver.max_stable_dt(), end - solver.time()));  // throws on NaN
    if (solver.steps() % 100 != 0) continue;
    const auto& ps = solver.particles();
    const auto& x = ps.vector("position");
    const auto& id = ps.integer("id");
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (x[i].x() < tin.min.x() || x[i].x() > tin.max.x() || x[i].z() < tin.min.z() || x[i].z() > tin.max.z() ||
          x[i].y() < tin.min.y())
        ++outside;
      if (id[i] == core_id) {
        const double t = ps.scalar("temperature")[i];
        max_drop = std::max(max_drop, last_core - t);
        last_core = t;
      }
    }
  }
  const double v1 = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0].volume;
  // Issue 20: after the rise no particle deeper than two spacings is flagged
  // as surface. Depth: to the tin's walls and floor, or to the top of the
  // dough above the particle (the highest particle within a spacing of its
  // vertical, plus half a spacing); the spacing is the median (m/ρ)^(1/3).
  const auto& ps = solver.particles();
  const auto& x = ps.vector("position");
  const auto& surface = ps.integer("surface");
  const auto& area = ps.scalar("surface_area");
  std::vector<double> local(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) local[i] = std::cbrt(ps.scalar("mass")[i] / ps.scalar("density")[i]);
  std::nth_element(local.begin(), local.begin() + long(local.size() / 2), local.end());
  const double s = local[local.size() / 2];
  long deep = 0, deep_flagged = 0;
  double deep_area = 0, total_area = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    double top = x[i].y();
    for (const Vec3& p : x)
      if (std::hypot(p.x() - x[i].x(), p.z() - x[i].z()) < s) top = std::max(top, p.y());
    const double depth = std::min({top + 0.5 * s - x[i].y(), x[i].x() - tin.min.x(), tin.max.x() - x[i].x(),
                                   x[i].z() - tin.min.z(), tin.max.z() - x[i].z(), x[i].y() - tin.min.y()});
    total_area += area[i];
    if (depth <= 2 * s) continue;
    ++deep;
    if (surface[i]) ++deep_flagged, deep_area += area[i];
  }
  std::printf(
      "bread roll: volume x%.2f; %ld particles deeper than 2 spacings (%.2f mm), %ld of them flagged as "
      "surface, with %.1f%% of the exchange area\n",
      v1 / v0, deep, s * 1e3, deep_flagged, 100 * deep_area / total_area);
  // Measured at this spacing: 103 of 1,874 (5.5%) with 15.6% of the area;
  // before the scan cone 971 of 1,701 (57%) with 49.7% of it. The issue's
  // "none" is not met yet (docs/physics.md, "Surface particles").
  EXPECT_GT(deep, 200);
  EXPECT_LT(double(deep_flagged), 0.10 * double(deep));
  EXPECT_LT(deep_area, 0.25 * total_area);
  RecordProperty("volume_ratio", std::to_string(v1 / v0));
  RecordProperty("core_temperature", std::to_string(last_core));
  EXPECT_GE(v1 / v0, 1.5);
  EXPECT_LE(v1 / v0, 3.5);
  EXPECT_EQ(outside, 0);
  // The core passed 90 °C here while half the exchange area sat inside the
  // crumb; with the crust alone taking the oven's heat it is at 36 °C after
  // 450 s of bake (the 25-minute preview ends at 87 °C): the heat reaches it
  // by conduction, too slowly in the risen crumb (an open part of issue 20).
  EXPECT_GT(last_core, 31.0);
  EXPECT_LE(last_core, 100.5);
  // Monotone but for the particle's own travel: it moves with the rising dough
  // among neighbours 34–40 °C (measured at 450 s), and conduction from the
  // colder ones lowered it by 0.020 K once in 100 steps after the exchange
  // through the face (physics/heat.hpp, CrustFace); 0.01 K before it.
  EXPECT_LE(max_drop, 0.05);
}

// Issue 22 item 1: the cookie of the cookie-dough preset in SPH (the same
// preset and tray as the MPM cookie): it spreads as its butter melts, sets,
// stays on the tray and bakes through; its core reaches 95 °C when the MPM
// cookie's does, within a minute (both take the preset's thermal properties).
TEST(SphCookie, FromThePresetItSpreadsSetsAndBakesThrough) {
  // ~1,000 particles instead of 3,423.
  Scene scene = load_scene(std::string(BAKESIM_SOURCE_DIR) + "/scenes/cookie-on-a-tray-sph.json",
                           {parse_override("solver.sph.spacing=0.003")});
  sph::SphSolver solver(scene.sph);
  auto width = [](const ParticleSet& ps) {
    double lo = 1e9, hi = -1e9;
    for (const Vec3& x : ps.vector("position")) lo = std::min(lo, double(x.x())), hi = std::max(hi, double(x.x()));
    return hi - lo;
  };
  const auto before = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0];
  const double width0 = width(solver.particles());
  double minutes_to_95 = -1, lowest = 1;
  while (solver.time() < scene.end_time - 1e-12) {
    solver.step(std::min(solver.max_stable_dt(), scene.end_time - solver.time()));  // throws on NaN
    const auto& ps = solver.particles();
    const auto& temperature = ps.scalar("temperature");
    if (minutes_to_95 < 0 && *std::min_element(temperature.begin(), temperature.end()) >= 95)
      minutes_to_95 = scene.oven.bake_time(solver.time()) / 60;
    for (const Vec3& x : ps.vector("position")) lowest = std::min(lowest, double(x.y()));
  }
  const auto after = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0];
  const double width1 = width(solver.particles());
  std::printf("SPH cookie: width %.1f -> %.1f mm, height %.1f -> %.1f mm, core 95 degC at %.2f min, lowest %.2f mm\n",
              width0 * 1e3, width1 * 1e3, before.height() * 1e3, after.height() * 1e3, minutes_to_95, lowest * 1e3);
  RecordProperty("minutes_to_95", std::to_string(minutes_to_95));
  EXPECT_GT(width1, 1.05 * width0);            // it spreads
  EXPECT_LT(after.height(), before.height());  // and flattens
  EXPECT_GT(minutes_to_95, 3.0);               // the MPM cookie: 4.7 min at 3 mm
  EXPECT_LT(minutes_to_95, 7.0);
  EXPECT_GT(lowest, -0.001);  // on the tray (its top at y = 0)
}
