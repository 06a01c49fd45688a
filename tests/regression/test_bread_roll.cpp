// Regression: the shipped bread-roll scene (thesis Fig 4.3/4.8), run at a
// coarser spacing for CI, must rise (final/initial volume 1.5–3.5), stay
// inside its tin, keep every state finite, never cool its coldest part, and
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

namespace {

// The particles' median spacing, (m/ρ)^(1/3).
double median_spacing(const ParticleSet& ps) {
  std::vector<double> local(ps.size());
  for (std::size_t i = 0; i < local.size(); ++i) local[i] = std::cbrt(ps.scalar("mass")[i] / ps.scalar("density")[i]);
  std::nth_element(local.begin(), local.begin() + long(local.size() / 2), local.end());
  return local[local.size() / 2];
}

// Each particle's depth in the dough: to the tin's walls and floor, or to the
// top of the dough above it (the highest particle within a spacing s of its
// vertical, plus half a spacing).
std::vector<double> depth_in_tin(const ParticleSet& ps, const Aabb& tin, double s) {
  const auto& x = ps.vector("position");
  std::vector<double> depth(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    double top = x[i].y();
    for (const Vec3& p : x)
      if (std::hypot(p.x() - x[i].x(), p.z() - x[i].z()) < s) top = std::max(top, double(p.y()));
    depth[i] = std::min({top + 0.5 * s - x[i].y(), x[i].x() - tin.min.x(), tin.max.x() - x[i].x(),
                         x[i].z() - tin.min.z(), tin.max.z() - x[i].z(), x[i].y() - tin.min.y()});
  }
  return depth;
}

}  // namespace

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
  double last_core = -1e9, coldest = -1e9, coldest_drop = 0;
  long outside = 0;
  while (solver.time() < end - 1e-12) {
    solver.step(std::min(solver.max_stable_dt(), end - solver.time()));  // throws on NaN
    const auto& temperature = solver.particles().scalar("temperature");
    const double now_coldest = *std::min_element(temperature.begin(), temperature.end());
    coldest_drop = std::max(coldest_drop, coldest - now_coldest);
    coldest = now_coldest;
    if (solver.steps() % 100 != 0) continue;
    const auto& ps = solver.particles();
    const auto& x = ps.vector("position");
    const auto& id = ps.integer("id");
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (x[i].x() < tin.min.x() || x[i].x() > tin.max.x() || x[i].z() < tin.min.z() || x[i].z() > tin.max.z() ||
          x[i].y() < tin.min.y())
        ++outside;
      if (id[i] == core_id) last_core = ps.scalar("temperature")[i];
    }
  }
  solver.synchronize();  // the surface flags and temperatures of the last positions
  const double v1 = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0].volume;
  // Issue 20: after the rise no particle deeper than two spacings is flagged
  // as surface. Depth: to the tin's walls and floor, or to the top of the
  // dough above the particle (the highest particle within a spacing of its
  // vertical, plus half a spacing); the spacing is the median (m/ρ)^(1/3).
  const auto& ps = solver.particles();
  const auto& surface = ps.integer("surface");
  const auto& area = ps.scalar("surface_area");
  const double s = median_spacing(ps);
  const std::vector<double> depth = depth_in_tin(ps, tin, s);
  long deep = 0, deep_flagged = 0;
  double deep_area = 0, total_area = 0;
  for (std::size_t i = 0; i < depth.size(); ++i) {
    total_area += area[i];
    if (depth[i] <= 2 * s) continue;
    ++deep;
    if (surface[i]) ++deep_flagged, deep_area += area[i];
  }
  std::printf(
      "bread roll: volume x%.2f; %ld particles deeper than 2 spacings (%.2f mm), %ld of them flagged as "
      "surface, with %.1f%% of the exchange area\n",
      v1 / v0, deep, s * 1e3, deep_flagged, 100 * deep_area / total_area);
  // Measured at this spacing: 7 of 1,665 (0.4%) with 1.3% of the area (colour
  // threshold 0.3, vented bubbles, the scene's viscosity tolerance 1e-4); 2 of 1,876 (0.1%) with 0.5% at 0.6 without
  // venting, with the open-space test (solver.sph.surface.open_space); with
  // the scan cone alone 110 of 1,840 (6%) with 17.2% of it; before the scan
  // cone 971 of 1,701 (57%) with 49.7%. The "none" is not quite met
  // (docs/physics.md, "Surface particles").
  EXPECT_GT(deep, 200);
  EXPECT_LE(double(deep_flagged), 0.01 * double(deep));
  EXPECT_LT(deep_area, 0.02 * total_area);
  // The top's exchange area with the oven air against the tin's opening (the
  // risen top is rougher, so larger). Measured at this spacing: 0.43 with the
  // scene as shipped (0.47 with the viscosity tolerance at 1e-6), 0.21 without vent_at_surface (the thesis's bubbles, pushed out of
  // the skin by their gas pressure, form a loose layer over the dough and
  // hide it: docs/physics.md, "Bubbles and the rise"); with the colour
  // threshold at its earlier 0.6, 0.34 and 0.16. Still short of 1: the
  // colour-gradient areas and flags undercount a disordered risen surface
  // (an open part of issue 20, docs/physics.md "External heat exchange").
  const auto& air_facing = ps.integer("air_facing");
  double air_area = 0;
  for (std::size_t i = 0; i < area.size(); ++i)
    if (air_facing[i]) air_area += area[i];
  const double opening = (tin.max.x() - tin.min.x()) * (tin.max.z() - tin.min.z());
  std::printf("bread roll: exchange area with the air %.0f mm2, %.2f of the tin's opening\n", air_area * 1e6,
              air_area / opening);
  RecordProperty("air_area_over_opening", std::to_string(air_area / opening));
  EXPECT_GT(air_area / opening, 0.35);
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
  // In an oven that only heats, conduction cannot cool the coldest dough
  // (the maximum principle; moving particles carry their temperature, and
  // vapour condenses where it is coldest): the body's coldest particle never
  // cools, step by step, beyond round-off. A followed core particle may: it
  // rises with the dough out of the cold spot among colder neighbours (with
  // the roll's radiating oven it lost 0.10 K at 440 s among neighbours at a
  // mean 33.3 °C while it stood at 33.9).
  RecordProperty("coldest_drop_kelvin", std::to_string(coldest_drop));
  EXPECT_LE(coldest_drop, 1e-9);
}

// Issue 20's "a brown crust over a pale crumb", on the shipped roll's whole
// 25-minute bake at a coarse spacing (about 800 particles): the top of the
// crust browns (its dried face passes 150 °C under the radiating oven's heat
// through the dried crust's 0.1 W/(m K)), the crumb deeper than two spacings
// holds water, stays at or below the boiling point and does not brown at all
// (moist dough browns only past it), and the core ends at or below 100 °C.
TEST(BreadRoll, CoarseWholeBakeBrownsItsTopAndNotItsCrumb) {
  Scene scene = load_scene(std::string(BAKESIM_SOURCE_DIR) + "/scenes/bread-roll.json",
                           {parse_override("solver.sph.spacing=0.0045")});
  sph::SphSolver solver(scene.sph);
  const auto& tin = std::get<ContainerCollider>(scene.sph.colliders.at(0).geometry).inner;
  while (solver.time() < scene.end_time - 1e-12)
    solver.step(std::min(solver.max_stable_dt(), scene.end_time - solver.time()));
  solver.synchronize();  // as the frame loop does before a frame

  const auto& ps = solver.particles();
  const auto& x = ps.vector("position");
  const auto& bubble = ps.integer("bubble");
  const auto& area = ps.scalar("surface_area");
  const auto& browning = ps.scalar("browning");
  const auto& temperature = ps.scalar("temperature");
  const auto& moisture = ps.scalar("moisture");
  const double s = median_spacing(ps);
  const std::vector<double> depth = depth_in_tin(ps, tin, s);
  // The top crust: the highest tenth of the particles with exchange area (what the camera sees; most are bubble
  // particles, which rise).
  std::vector<double> surface_heights;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (area[i] > 0) surface_heights.push_back(x[i].y());
  ASSERT_GE(surface_heights.size(), 100u);
  std::sort(surface_heights.begin(), surface_heights.end());
  const double top_from = surface_heights[surface_heights.size() * 9 / 10];
  std::vector<double> top_browning, top_face;
  std::vector<double> crumb_browning;
  long crumb = 0, browned_crumb = 0;
  double crumb_hottest = -1e9, crumb_driest = 1e9, core = -1e9;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (area[i] > 0 && x[i].y() >= top_from) {  // bubble particles too: most of the top is theirs
      top_browning.push_back(browning[i]);
      top_face.push_back(ps.scalar("surface_temperature")[i]);
    }
    if (bubble[i]) continue;
    if (depth[i] > 2 * s) {
      ++crumb;
      if (browning[i] > 0) ++browned_crumb;
      crumb_browning.push_back(browning[i]);
      crumb_hottest = std::max(crumb_hottest, double(temperature[i]));
      crumb_driest = std::min(crumb_driest, double(moisture[i]));
    }
  }
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!bubble[i] && depth[i] > 2 * s) core = std::max(core, -double(temperature[i]));  // coldest crumb
  core = -core;
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  ASSERT_GE(top_browning.size(), 10u);
  ASSERT_GE(crumb, 50);
  std::printf(
      "bread roll after 25 min: %zu top crust particles, browning median %.3f, face %.1f degC; %ld crumb particles "
      "(deeper than %.1f mm), %ld browned, hottest %.2f degC, coldest %.1f degC, driest %.2f kg/kg\n",
      top_browning.size(), median(top_browning), median(top_face), crumb, 2 * s * 1e3, browned_crumb, crumb_hottest,
      core, crumb_driest);
  // Measured: median 0.53 (ΔE 27 of Zanoni's 52: golden brown), face 166 °C
  // (colour threshold 0.3, vented bubbles); 0.29 and 157 °C before; without
  // the radiation and the crust's conductivity 0.03 and 108 °C (pale).
  EXPECT_GE(median(top_browning), 0.4);
  EXPECT_GE(median(top_face), 150.0);
  // The crumb: moist, at or below the boiling point, and unbrowned. Measured:
  // none of 113 crumb particles browned (1 of 161, 0.18, before the colour
  // threshold went to 0.3 and the bubbles vented). Before the open-space test
  // (solver.sph.surface.open_space) 36 of 170 did, up to 0.44: particles
  // beside the voids of the risen crumb passed the colour test, took the
  // oven's heat and browned.
  std::sort(crumb_browning.begin(), crumb_browning.end());
  const double crumb_p90 = crumb_browning[crumb_browning.size() * 9 / 10];
  std::printf("crumb browning: 90th percentile %.3f, largest %.3f\n", crumb_p90, crumb_browning.back());
  EXPECT_EQ(crumb_p90, 0.0);
  EXPECT_LE(double(browned_crumb), 0.05 * double(crumb));
  EXPECT_LE(crumb_hottest, 100.5);
  EXPECT_GT(crumb_driest, 0.3);
  // Baked through: the coldest crumb passed 95 °C (measured 99.4; 95.4 before
  // the colour threshold went to 0.3 and the bubbles vented). With the
  // open-space test and the thesis's Laplacian (corrected_laplacian false),
  // whose risen crumb conducts at a third of its rate, it ended at 63 °C;
  // with neither at 84 °C, heated from the air through the voids' walls.
  EXPECT_GT(core, 90.0);
}

// Issue 22 item 1: the cookie of the cookie-dough preset in SPH (the same
// preset and tray as the MPM cookie): it spreads as its butter melts, puffs
// with its bubble particles without spraying dough off the tray (with the
// thesis's bubble pressure it did), sets, stays on the tray and bakes through. It carries its water (the preset's SPH
// moisture, 0.167 kg/kg), so its moist dough stays at the boiling point and
// its core reaches 95 °C later than the MPM cookie's (4.7 min at 3 mm), whose
// water (the MPM paper's) takes no latent heat: 7.2 min at 3 mm and at 2 mm.
// Without the water it took 4.4-4.8 min and its core ended at 157-160 °C.
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
  double minutes_to_95 = -1, lowest = 1, past_line = -1e9;
  while (solver.time() < scene.end_time - 1e-12) {
    solver.step(std::min(solver.max_stable_dt(), scene.end_time - solver.time()));  // throws on NaN
    const auto& ps = solver.particles();
    const auto& temperature = ps.scalar("temperature");
    if (minutes_to_95 < 0 && *std::min_element(temperature.begin(), temperature.end()) >= 95)
      minutes_to_95 = scene.oven.bake_time(solver.time()) / 60;
    for (const Vec3& x : ps.vector("position")) lowest = std::min(lowest, double(x.y()));
    // How far any particle holding water is past its boiling line (bound water, physics/water.hpp): the
    // cap keeps it on the line (100.2 degC at 0.45 kg/kg, 124 degC at 0.1 with the default isotherm).
    const auto& moisture = ps.scalar("moisture");
    const auto& material = ps.integer("material_id");
    for (std::size_t i = 0; i < ps.size(); ++i)
      if (moisture[i] > 0 && temperature[i] > 100)
        past_line = std::max(
            past_line, double(temperature[i]) -
                           scene.sph.materials[std::size_t(material[i])].moisture.boiling_temperature(moisture[i]));
  }
  solver.synchronize();
  const auto after = compute_body_stats(solver.particles(), 1, Vec3::UnitY())[0];
  const double width1 = width(solver.particles());
  std::printf(
      "SPH cookie: width %.1f -> %.1f mm, height %.1f -> %.1f mm, volume x%.2f, core 95 degC at %.2f min, lowest "
      "%.2f mm, moist dough at most %.2g K past its boiling line\n",
      width0 * 1e3, width1 * 1e3, before.height() * 1e3, after.height() * 1e3, after.volume / before.volume,
      minutes_to_95, lowest * 1e3, past_line);
  RecordProperty("minutes_to_95", std::to_string(minutes_to_95));
  EXPECT_GT(width1, 1.05 * width0);               // it spreads (measured 45 -> 60 mm at 3 mm)
  EXPECT_LT(width1, 1.6 * width0);                // as one cookie: none sprayed off (20% bubbles at the Tait B: x2.4)
  EXPECT_GT(after.volume / before.volume, 1.08);  // and puffs (x1.13 at 3 mm, x1.22 at 2 mm)
  EXPECT_GT(minutes_to_95, 5.0);                  // later than the MPM cookie's 4.7 min (no latent heat there)
  EXPECT_LT(minutes_to_95, 10.0);                 // and within its 12-minute bake
  EXPECT_LE(past_line, 0.01);                     // dough holding water stays on its boiling line
  EXPECT_GT(lowest, -0.001);                      // on the tray (its top at y = 0)
}
