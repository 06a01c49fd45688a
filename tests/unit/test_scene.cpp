// Scene loading: every kind of bad input is answered with its location and
// what is allowed; good input is resolved with every default filled in.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>

#include "core/errors.hpp"
#include "geometry/shapes.hpp"
#include "io/checkpoint.hpp"
#include "io/materials.hpp"
#include "io/run_meshes.hpp"
#include "mpm/solver.hpp"
#include "physics/food_properties.hpp"
#include "io/scene.hpp"
#include "io/schema.hpp"

using namespace bakesim;
using nlohmann::json;

namespace {

json base_scene() {
  return json::parse(R"({
    "solver": {"type": "sph", "sph": {"spacing": 0.01}},
    "time": {"end": 0.1},
    "domain": {"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]},
    "materials": {"water": {"density": 1000}},
    "bodies": [{"name": "block", "material": "water",
                "shape": {"type": "box", "min": [0.02, 0.02, 0.02], "max": [0.08, 0.08, 0.08]}}]
  })");
}

// Expects an InputError whose message contains every fragment.
void expect_text_error(const std::string& text, const std::vector<std::string>& fragments) {
  try {
    parse_scene(text, "scene.json", ".");
    FAIL() << "no error for:\n" << text;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

void expect_error(const json& doc, const std::vector<std::string>& fragments) {
  expect_text_error(doc.dump(2), fragments);
}

}  // namespace

// --preview doubles the spacing, but a body a few spacings thick then loses a
// layer's share of itself: a 60 x 14 x 60 mm slab at 3.5 mm fills 98% of its
// shape, at 7 mm its 8 layers across span 56 of its 60 mm (87%). The preview
// takes the nearest finer spacing that fills it within 5%: 60/9 mm (9 layers
// across, 2 through, 95.2%); a cube the doubled spacing fills keeps it.
TEST(Scene, PreviewSpacingKeepsAThinBodysVolume) {
  auto preview_spacing = [](const json& doc) {
    const Scene s = parse_scene(doc.dump(), "scene.json", ".");
    for (const SceneOverride& o : preview_overrides(s))
      if (o.path == "solver.sph.spacing" || o.path == "solver.mpm.cell_size") return o.value.get<double>();
    return 0.0;
  };
  EXPECT_DOUBLE_EQ(preview_spacing(base_scene()), 0.02);  // 60 mm: 3 layers of 20 mm
  json slab = base_scene();
  slab["solver"]["sph"]["spacing"] = 0.0035;
  slab["bodies"][0]["shape"]["max"] = {0.08, 0.034, 0.08};
  const double s = preview_spacing(slab);
  EXPECT_DOUBLE_EQ(s, 0.00666666);  // 60/9 mm to six digits, rounded down
  const Shape box = BoxShape{Vec3(0.02, 0.02, 0.02), Vec3(0.08, 0.034, 0.08)};
  EXPECT_NEAR(sampling_fill(box, sample_lattice(box, 0.007), 0.007).fraction, 0.871, 0.001);
  EXPECT_NEAR(sampling_fill(box, sample_lattice(box, s), s).fraction, 0.952, 0.001);
  // MPM: the cell size, the spacing times the cube root of particles_per_cell (8: 2).
  json mpm = slab;
  mpm["solver"] = json::parse(R"({"type": "mpm", "mpm": {"cell_size": 0.007}})");
  mpm["materials"]["water"] = json::parse(R"({"density": 1000, "youngs_modulus": 1e5, "poisson_ratio": 0.3})");
  EXPECT_DOUBLE_EQ(preview_spacing(mpm), 2 * 0.00666666);
}

TEST(Scene, ValidSceneResolvesEveryDefault) {
  const Scene s = parse_scene(base_scene().dump(), "scene.json", ".");
  const json& r = s.resolved;
  EXPECT_EQ(r["format"], "bakesim-scene/1");
  EXPECT_EQ(r["name"], "scene");
  EXPECT_DOUBLE_EQ(r["solver"]["sph"]["smoothing_ratio"].get<double>(), 2.0);
  EXPECT_TRUE(r["solver"]["sph"]["speed_of_sound"].is_number());  // "auto" is replaced by its value
  EXPECT_DOUBLE_EQ(r["solver"]["sph"]["artificial_viscosity"]["beta"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(r["materials"]["water"]["viscosity"].get<double>(), 0.001);
  EXPECT_EQ(r["bodies"][0]["velocity"], json::array({0, 0, 0}));
  EXPECT_DOUBLE_EQ(r["gravity"][1].get<double>(), -9.81);
  EXPECT_EQ(r["output"]["particles"], json::array({"ply", "vtu"}));
  EXPECT_DOUBLE_EQ(r["time"]["fps"].get<double>(), 30.0);
  EXPECT_EQ(s.sph.bodies.size(), 1u);
  // The resolved scene is itself a valid scene that resolves to itself.
  const Scene again = parse_scene(r.dump(), "scene.json", ".");
  EXPECT_EQ(again.resolved, r);
}

TEST(Scene, SyntaxErrorGivesLineAndColumn) {
  expect_text_error("{\n  \"solver\": {\"type\": \"sph\"},\n  \"time\": {\"end\": 1,}\n}",
                    {"scene.json:3:", "JSON syntax error"});
  expect_text_error("{\n  \"solver\": \n", {"scene.json:3:", "JSON syntax error"});
}

TEST(Scene, UnknownKeyGivesPathAndClosestKey) {
  json d = base_scene();
  d["bodies"][0]["shape"] = {{"type", "sphere"}, {"center", {0.1, 0.1, 0.1}}, {"raduis", 0.03}};
  expect_error(d, {"scene.json: bodies[0].shape.raduis", "unknown key", "did you mean 'radius'"});
  d["bodies"][0]["shape"].erase("raduis");
  expect_error(d, {"scene.json: bodies[0].shape", "missing required key 'radius'"});
  json top = base_scene();
  top["gravty"] = {0, -9.81, 0};
  expect_error(top, {"scene.json: gravty", "did you mean 'gravity'"});
  json sph = base_scene();
  sph["solver"]["sph"]["smoothing_ration"] = 2;
  expect_error(sph, {"solver.sph.smoothing_ration", "did you mean 'smoothing_ratio'"});
}

TEST(Scene, WrongTypeGivesPathAndExpectedType) {
  json d = base_scene();
  d["time"]["end"] = "ten";
  expect_error(d, {"scene.json: time.end", "expected a number", "\"ten\""});
  json e = base_scene();
  e["bodies"][0]["velocity"] = {1, 2};
  expect_error(e, {"bodies[0].velocity", "exactly 3 items"});
  json f = base_scene();
  f["output"] = {{"every_frames", 1.5}};
  expect_error(f, {"output.every_frames", "expected an integer"});
  json g = base_scene();
  g["bodies"][0]["shape"]["type"] = "cube";
  expect_error(g, {"bodies[0].shape.type", "unknown type \"cube\"", "box, sphere"});
}

TEST(Scene, OutOfRangeGivesPathAndAllowedRange) {
  json d = base_scene();
  d["materials"]["water"]["density"] = -5;
  expect_error(d, {"materials.water.density", "must be > 0 kg/m^3", "-5"});
  json e = base_scene();
  e["bodies"][0]["temperature"] = -300;
  expect_error(e, {"bodies[0].temperature", ">= -273.15 degC"});
  json f = base_scene();
  f["solver"]["sph"]["neighbour_search"] = "octree";
  expect_error(f, {"solver.sph.neighbour_search", "\"grid\", \"kdtree\""});
  json g = base_scene();
  g["domain"]["max"] = {0.2, -0.1, 0.2};
  expect_error(g, {"domain", "min must be below max", "axis y"});
}

TEST(Scene, ReferencesAreChecked) {
  json d = base_scene();
  d["bodies"][0]["material"] = "watr";
  expect_error(d, {"bodies[0].material", "unknown material 'watr'", "did you mean 'water'"});
  json e = base_scene();
  e["bodies"].push_back(e["bodies"][0]);
  expect_error(e, {"bodies[1].name", "duplicate name 'block'"});
  json f = base_scene();
  f["solver"]["type"] = "mpm";
  // The SPH section left behind is named first; without it the missing MPM section is.
  expect_error(f, {"solver.sph", "read only by the SPH solver"});
  f["solver"].erase("sph");
  expect_error(f, {"solver", "missing section 'mpm'", "cell_size"});
  json g = base_scene();
  g["solver"].erase("sph");
  expect_error(g, {"solver", "missing section 'sph'"});
}

TEST(Scene, MissingMeshFileIsNamed) {
  json d = base_scene();
  d["bodies"][0]["shape"] = {{"type", "mesh"}, {"file", "no/such/bunny.obj"}};
  expect_error(d, {"bodies[0].shape.file", "no/such/bunny.obj", "not found"});
  json c = base_scene();
  c["colliders"] = json::array({{{"name", "funnel"}, {"shape", {{"type", "mesh"}, {"file", "missing.ply"}}}}});
  expect_error(c, {"colliders[0].shape.file", "missing.ply"});
}

TEST(Scene, UnreadableMeshFileIsNamed) {
  const auto dir = std::filesystem::temp_directory_path() / "bakesim_test_mesh";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "broken.ply")
      << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n1\n2\n";
  json d = base_scene();
  d["bodies"][0]["shape"] = {{"type", "mesh"}, {"file", (dir / "broken.ply").string()}};
  expect_error(d, {"bodies[0].shape.file", "broken.ply", "lacks x, y or z"});
}

TEST(Scene, BodyWithoutParticlesIsReported) {
  json d = base_scene();
  d["bodies"][0]["shape"] = {{"type", "sphere"}, {"center", {0.1, 0.1, 0.1}}, {"radius", 0.001}};
  const Scene s = parse_scene(d.dump(), "scene.json", ".");
  try {
    make_solver(s);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[0]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("contains no particles"), std::string::npos) << e.what();
  }
}

TEST(Scene, OverlappingBodiesAndBodiesInsideCollidersAreReported) {
  json d = base_scene();
  d["bodies"].push_back({{"name", "ball"},
                         {"material", "water"},
                         {"shape", {{"type", "sphere"}, {"center", {0.08, 0.08, 0.08}}, {"radius", 0.03}}}});
  try {
    make_solver(parse_scene(d.dump(), "scene.json", "."));
    FAIL() << "expected an overlap error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[1]: body 'ball' overlaps body 'block'"), std::string::npos)
        << e.what();
  }
  json c = base_scene();
  c["colliders"] = json::array(
      {{{"name", "shelf"}, {"shape", {{"type", "box"}, {"min", {0.0, 0.0, 0.0}}, {"max", {0.2, 0.03, 0.2}}}}}});
  try {
    make_solver(parse_scene(c.dump(), "scene.json", "."));
    FAIL() << "expected an inside-collider error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("body 'block' starts inside collider 'shelf'"), std::string::npos) << e.what();
  }
}

TEST(Scene, MaterialPropertiesMayBeCurvesOfTemperature) {
  json d = base_scene();
  d["materials"]["water"]["viscosity"] = {{"curve", "piecewise_linear"},
                                          {"points", {{26, 0.1}, {45, 1.0}, {120, 5000.0}}}};
  d["materials"]["water"]["xsph"] = {{"curve", "zhang_arctan"}, {"scale", 0.2}};
  const Scene s = parse_scene(d.dump(), "scene.json", ".");
  EXPECT_DOUBLE_EQ(evaluate(s.sph.materials[0].viscosity, 45.0), 1.0);
  EXPECT_DOUBLE_EQ(s.resolved["materials"]["water"]["xsph"]["centre"].get<double>(), 65.0);  // defaults filled
  json e = base_scene();
  e["materials"]["water"]["viscosity"] = {{"curve", "piecewise_linaer"}, {"points", {{0, 1}}}};
  expect_error(e, {"materials.water.viscosity.curve", "unknown curve \"piecewise_linaer\"",
                   "did you mean \"piecewise_linear\""});
  json f = base_scene();
  f["materials"]["water"]["viscosity"] = {{"curve", "piecewise_linear"}, {"points", {{50, 1}, {40, 2}}}};
  expect_error(f, {"materials.water.viscosity.points[1]", "increase strictly"});
  json g = base_scene();
  g["materials"]["water"]["viscosity"] = "thick";
  expect_error(g, {"materials.water.viscosity", "expected a number or an object"});
}

TEST(Scene, ClosestMatch) {
  EXPECT_EQ(closest_match("raduis", {"type", "center", "radius"}), "radius");
  EXPECT_EQ(closest_match("zzzzzz", {"type", "center", "radius"}), "");
}

TEST(Scene, ScheduleMustIncrease) {
  json d = base_scene();
  d["environment"] = {{"air_temperature", {{0, 20}, {60, 180}, {30, 190}}}};
  expect_error(d, {"environment.air_temperature[2]", "increase strictly"});
  d["environment"] = {{"air_temperature", {{0, 20}, {60, 180}}}};
  const Scene s = parse_scene(d.dump(), "scene.json", ".");
  EXPECT_DOUBLE_EQ(s.oven.air_temperature(30), 100.0);
  EXPECT_DOUBLE_EQ(s.oven.air_temperature(600), 180.0);
}

TEST(Scene, MinDtMustBeBelowMaxDt) {
  json d = base_scene();
  d["solver"]["max_dt"] = 1e-3;
  d["solver"]["min_dt"] = 2e-3;
  expect_error(d, {"solver.min_dt", "must be below solver.max_dt"});
  d["solver"]["min_dt"] = 1e-5;
  EXPECT_DOUBLE_EQ(parse_scene(d.dump(), "scene.json", ".").resolved["solver"]["min_dt"].get<double>(), 1e-5);
}

namespace {
json mpm_scene() {
  return json::parse(R"({
    "solver": {"type": "mpm", "mpm": {"cell_size": 0.005}},
    "time": {"end": 0.1},
    "domain": {"min": [-0.1, -0.02, -0.1], "max": [0.1, 0.1, 0.1]},
    "materials": {"dough": {"density": 500, "set_temperature": 90, "plasticity": {"model": "cam_clay", "initial_porosity": 0.2,
                  "yield_stress": {"curve": "piecewise_linear", "points": [[20, 300], [90, 3000]]}},
                  "water": {"saturation": 0.4}}},
    "bodies": [{"name": "muffin", "material": "dough",
                "shape": {"type": "cylinder", "center": [0, 0.02, 0], "axis": [0, 1, 0], "radius": 0.02, "height": 0.02}}],
    "colliders": [{"name": "cup", "shape": {"type": "cup", "base": [0, 0.0, 0], "radius": 0.022, "height": 0.03,
                   "wall_thickness": 0.01}}]
  })");
}
}  // namespace

TEST(Scene, MpmCupWallsMustBeTwoCellsThick) {
  json d = mpm_scene();
  EXPECT_NO_THROW(parse_scene(d.dump(), "scene.json", "."));
  d["colliders"][0]["shape"]["wall_thickness"] = 0.006;
  expect_error(d, {"colliders[0].shape.wall_thickness", "thinner than two MPM cells", "0.01"});
}

TEST(Scene, SetSofteningNeedsCamClayASetTemperatureAndWater) {
  json d = mpm_scene();
  d["materials"]["dough"]["plasticity"]["set_softening"] = 60;
  EXPECT_NO_THROW(parse_scene(d.dump(), "scene.json", "."));
  json dry = d;
  dry["materials"]["dough"]["water"]["saturation"] = 0;
  expect_error(dry, {"materials.dough.plasticity.set_softening", "water.saturation > 0"});
  json unset = d;
  unset["materials"]["dough"].erase("set_temperature");
  expect_error(unset, {"materials.dough.plasticity.set_softening", "set_temperature"});
  json ramp = d;
  ramp["materials"]["dough"]["plasticity"]["brittle_water_loss"] = 0;
  expect_error(ramp, {"materials.dough.plasticity.brittle_water_loss"});
}

// moisture.surface_evaporation: "free" by default; "supply_limited" brings the liquid to the face by
// diffusion, so it needs a liquid diffusivity (refused without one, naming the key), in both solvers.
TEST(Scene, SupplyLimitedSurfaceEvaporationNeedsALiquidDiffusivity) {
  for (const json& base : {base_scene(), mpm_scene()}) {
    json d = base;
    const std::string name = d["materials"].begin().key();
    d["materials"][name].erase("water");  // MPM: the water comes from the moisture
    d["materials"][name]["moisture"] = {{"content", 0.5}, {"surface_evaporation", "supply_limited"}};
    expect_error(d, {"materials." + name + ".moisture.surface_evaporation", "liquid_diffusivity"});
    d["materials"][name]["moisture"]["liquid_diffusivity"] = 5e-10;
    EXPECT_NO_THROW(parse_scene(d.dump(), "scene.json", "."));
    d["materials"][name]["moisture"]["surface_evaporation"] = "wet";
    expect_error(d, {"surface_evaporation"});
  }
}

// Keys only the other solver reads are refused with the key path and the
// solver that reads them, in both directions; their defaults do not appear in
// the resolved scene.
TEST(Scene, KeysOfTheOtherSolverAreRefusedInBothDirections) {
  json sph = base_scene();
  const std::vector<std::pair<std::string, json>> mpm_only_material = {
      {"youngs_modulus", 1e5},        {"poisson_ratio", 0.3},      {"elastic_model", "hencky"},
      {"plasticity", json::object()}, {"thermal_expansion", 1e-4}, {"water", json::object()},
      {"leavening", json::object()}};
  for (const auto& [key, value] : mpm_only_material) {
    json d = sph;
    d["materials"]["water"][key] = value;
    expect_error(d, {"materials.water." + key, "read only by the MPM solver", "solver.type is \"sph\""});
  }
  json spin = sph;
  spin["bodies"][0]["angular_velocity"] = {0, 1, 0};
  expect_error(spin, {"bodies[0].angular_velocity", "MPM solver"});
  json section = sph;
  section["solver"]["mpm"] = {{"cell_size", 0.01}};
  expect_error(section, {"solver.mpm", "MPM solver"});

  json mpm = mpm_scene();
  const std::vector<std::pair<std::string, json>> sph_only_material = {
      {"viscosity", 1.0}, {"surface_tension", 0.07}, {"xsph", 0.1}, {"elasticity", 10.0}, {"relaxation_time", 2.0}};
  for (const auto& [key, value] : sph_only_material) {
    json d = mpm;
    d["materials"]["dough"][key] = value;
    expect_error(d, {"materials.dough." + key, "read only by the SPH solver", "solver.type is \"mpm\""});
  }
  for (const char* key : {"bubbles", "hold_temperature"}) {
    json d = mpm;
    d["bodies"][0][key] = std::string(key) == "bubbles" ? json{{"fraction", 0.2}} : json(true);
    expect_error(d, {std::string("bodies[0].") + key, "SPH solver"});
  }
  json sph_section = mpm;
  sph_section["solver"]["sph"] = {{"spacing", 0.01}};
  expect_error(sph_section, {"solver.sph", "SPH solver"});

  // Shared keys are read by both; the other solver's defaults are not filled in.
  const json r_sph = parse_scene(sph.dump(), "scene.json", ".").resolved;
  EXPECT_FALSE(r_sph["materials"]["water"].contains("youngs_modulus"));
  EXPECT_FALSE(r_sph["bodies"][0].contains("angular_velocity"));
  EXPECT_TRUE(r_sph["materials"]["water"].contains("viscosity"));
  const json r_mpm = parse_scene(mpm.dump(), "scene.json", ".").resolved;
  EXPECT_FALSE(r_mpm["materials"]["dough"].contains("viscosity"));
  EXPECT_FALSE(r_mpm["bodies"][0].contains("bubbles"));
  EXPECT_TRUE(r_mpm["materials"]["dough"].contains("plasticity"));
  EXPECT_TRUE(r_mpm["colliders"][0].contains("damping"));  // the contact law is shared
}

TEST(Scene, ReplacedSettingKeysNameTheNewKey) {
  json d = base_scene();
  d["materials"]["water"]["property_temperature"] = "peak";
  expect_error(d, {"materials.water.property_temperature", "use 'set_temperature'", "-273.15"});
  json m = mpm_scene();
  m["materials"]["dough"]["plasticity"]["set_temperature"] = 90;
  expect_error(m, {"materials.dough.plasticity.set_temperature", "use 'set_temperature'", "moved up one level"});
  // One key for both solvers.
  json s = base_scene();
  s["materials"]["water"]["set_temperature"] = 60;
  EXPECT_DOUBLE_EQ(parse_scene(s.dump(), "scene.json", ".").sph.materials[0].set.temperature, 60.0);
  EXPECT_DOUBLE_EQ(parse_scene(mpm_scene().dump(), "scene.json", ".").mpm.materials[0].set.temperature, 90.0);
}

TEST(Scene, ContactLawAndMotionAreSharedAndFrictionModelsResolvePerSolver) {
  json d = base_scene();
  d["colliders"] =
      json::parse(R"([{"name": "paddle", "shape": {"type": "box", "min": [0.1, 0.0, 0.0], "max": [0.12, 0.05, 0.2]},
    "contact": "sticky", "friction": 0.3, "motion": {"keyframes": [{"time": 0}, {"time": 1, "translation": [0.05, 0, 0]}]}}])");
  const Scene s = parse_scene(d.dump(), "scene.json", ".");
  ASSERT_EQ(s.sph.colliders.size(), 1u);
  EXPECT_EQ(s.sph.colliders[0].contact.mode, ContactMode::sticky);
  EXPECT_EQ(s.sph.colliders[0].contact.friction_model, FrictionModel::velocity_share);
  EXPECT_TRUE(s.sph.colliders[0].motion.moves());
  d["colliders"][0]["friction_model"] = "coulomb";
  EXPECT_EQ(parse_scene(d.dump(), "scene.json", ".").sph.colliders[0].contact.friction_model, FrictionModel::coulomb);
  EXPECT_EQ(parse_scene(mpm_scene().dump(), "scene.json", ".").mpm.colliders[0].contact.friction_model,
            FrictionModel::coulomb);
  // SPH moves analytic colliders, not meshes.
  json mesh = base_scene();
  mesh["colliders"] = json::array(
      {{{"name", "m"},
        {"shape", {{"type", "mesh"}, {"file", std::string(BAKESIM_SOURCE_DIR) + "/scenes/meshes/funnel.obj"}}},
        {"motion", {{"keyframes", {{{"time", 0}}, {{"time", 1}}}}}}}});
  expect_error(mesh, {"colliders[0].motion", "moving mesh colliders", "MPM solver only"});
}

TEST(Scene, ProbeQuantitiesAreTheSolversAttributes) {
  json d = base_scene();
  d["probes"] =
      json::parse(R"([{"name": "core", "position": [0.05, 0.05, 0.05], "quantities": ["temperature", "saturation"]}])");
  const Scene s = parse_scene(d.dump(), "scene.json", ".");
  try {
    make_solver(s);
    FAIL() << "an SPH probe of saturation was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("probes[0].quantities[1]"), std::string::npos) << msg;
    EXPECT_NE(msg.find("unknown quantity 'saturation'"), std::string::npos) << msg;
  }
  d["probes"][0]["quantities"] = {"temperature", "density", "speed"};
  EXPECT_NO_THROW(make_solver(parse_scene(d.dump(), "scene.json", ".")));
}

// Crafted inputs (issue 21): each was a crash or a silent harm before.
TEST(Scene, CraftedSizesAndNamesAreRefusedBeforeAnythingIsAllocated) {
  // A node count that wraps around 2^64 as an integer product (nx = ny = 2^22, nz = 2^20).
  json wrap = mpm_scene();
  wrap["colliders"] = json::array();
  wrap["solver"]["mpm"]["cell_size"] = 1e-6;
  wrap["domain"] = {{"min", {0, 0, 0}}, {"max", {4.194303, 4.194303, 1.048575}}};
  wrap["bodies"][0]["shape"] = {{"type", "box"}, {"min", {0.1, 0.1, 0.1}}, {"max", {0.2, 0.2, 0.2}}};
  expect_error(wrap, {"solver.mpm.cell_size", "nodes (at most 4e8)"});
  // An SPH spacing that would need more particles than memory holds: exit 2 with an estimate.
  json fine = base_scene();
  fine["solver"]["sph"]["spacing"] = 2e-5;
  expect_error(fine, {"solver.sph.spacing", "particles"});
  // A comma or newline in a body name would split the stats.csv header.
  for (const char* name : {"a,b", "a\nb", "say \"hi\""}) {
    json d = base_scene();
    d["bodies"][0]["name"] = name;
    expect_error(d, {"bodies[0].name", "commas, double quotes or control characters"});
  }
  // A value nested 100,000 deep is reported without serialising it (stack overflow before).
  std::string deep = base_scene().dump();
  const std::string nested = std::string(100000, '[') + std::string(100000, ']');
  deep.replace(deep.find("\"density\":1000"), std::string("\"density\":1000").size(), "\"density\":" + nested);
  expect_text_error(deep, {"materials.water.density", "expected a number"});
  // A union nested 100 deep is refused by depth.
  json shape = {{"type", "sphere"}, {"center", {0.05, 0.05, 0.05}}, {"radius", 0.02}};
  for (int i = 0; i < 100; ++i) shape = {{"type", "union"}, {"shapes", json::array({shape})}};
  json u = base_scene();
  u["bodies"][0]["shape"] = shape;
  expect_error(u, {"nested more than 64 levels deep"});
}

// A checkpoint resumes a bake bit for bit: the default roll's preview (SPH with
// water, a hot tin, the open-space surface test whose grid is kept from one
// neighbour search to the next) stopped after 20 steps and restored into a
// fresh solver ends 40 steps later where the uninterrupted run does.
namespace {
// The scene run `before` steps, checkpointed, then `after` more; and a fresh
// solver restored from that checkpoint (through its encoding) run `after` steps.
struct WholeAndResumed {
  std::unique_ptr<Solver> whole, resumed;
};
WholeAndResumed run_whole_and_resumed(const Scene& scene, int before, int after) {
  WholeAndResumed r{make_solver(scene), make_solver(scene)};
  for (int k = 0; k < before; ++k) r.whole->step(r.whole->max_stable_dt());
  const Checkpoint half = capture_checkpoint(*r.whole);
  for (int k = 0; k < after; ++k) r.whole->step(r.whole->max_stable_dt());
  restore_checkpoint(*r.resumed, decode_checkpoint(encode_checkpoint(half), "half.ckpt"), "half.ckpt");
  for (int k = 0; k < after; ++k) r.resumed->step(r.resumed->max_stable_dt());
  return r;
}
}  // namespace

TEST(Checkpoint, ARestoredSphBakeContinuesBitForBit) {
  std::string path = BAKESIM_SOURCE_DIR;
  path += "/scenes/bread-roll.json";
  const WholeAndResumed run = run_whole_and_resumed(load_scene(path, {}, true), 20, 40);
  const ParticleSet &a = run.whole->particles(), &b = run.resumed->particles();
  ASSERT_EQ(a.size(), b.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    differ += a.vector("position")[i] != b.vector("position")[i] ||
              a.scalar("temperature")[i] != b.scalar("temperature")[i] ||
              a.scalar("surface_area")[i] != b.scalar("surface_area")[i] || a.integer("id")[i] != b.integer("id")[i];
  EXPECT_EQ(differ, 0u) << "particles that differ from the uninterrupted run";
}

// An elastoviscoplastic SPH body (its relaxation time is "never", a finite
// 1e30 s: a checkpoint refuses non-finite particle data) resumes bit for bit,
// its Maxwell stress and the gradient correction included.
TEST(Checkpoint, AnElastoviscoplasticSphBodyResumesBitForBit) {
  json doc = base_scene();
  doc["gravity"] = {0, -9.81, 0};
  doc["solver"]["sph"]["viscosity_operator"] = "stress";
  doc["solver"]["sph"]["elasticity_solver"] = "implicit";
  doc["materials"]["water"]["elasticity"] = 2e4;
  doc["materials"]["water"]["viscosity"] = 10.0;
  doc["materials"]["water"]["herschel_bulkley"] = {{"yield_stress", 30.0}, {"form", "elastoviscoplastic"}};
  const WholeAndResumed run = run_whole_and_resumed(parse_scene(doc.dump(), "scene.json", "."), 30, 30);
  const ParticleSet &a = run.whole->particles(), &b = run.resumed->particles();
  ASSERT_EQ(a.size(), b.size());
  std::size_t differ = 0, stressed = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    differ += a.vector("position")[i] != b.vector("position")[i] ||
              a.vector("stress_normal")[i] != b.vector("stress_normal")[i] ||
              a.vector("stress_shear")[i] != b.vector("stress_shear")[i];
    stressed += a.vector("stress_normal")[i].norm() > 0;
  }
  EXPECT_EQ(differ, 0u) << "particles that differ from the uninterrupted run";
  EXPECT_GT(stressed, a.size() / 2) << "the block carries its weight in its Maxwell stress";
}

// A checkpoint edited and re-checksummed is refused unless it could have come
// from a run of this scene (issue 21: a NaN position, an out-of-range body or
// material id, a NaN time or a negative frame were trusted).
TEST(Checkpoint, CraftedContentsAreRefusedAfterTheChecksum) {
  const Scene scene = parse_scene(base_scene().dump(), "scene.json", ".");
  auto solver = make_solver(scene);
  solver->step(1e-4);
  const Checkpoint good = capture_checkpoint(*solver);
  auto restore = [&](const Checkpoint& c) {
    auto fresh = make_solver(scene);
    const Checkpoint decoded = decode_checkpoint(encode_checkpoint(c), "crafted.ckpt");  // checksum recomputed
    restore_checkpoint(*fresh, decoded, "crafted.ckpt");
  };
  EXPECT_NO_THROW(restore(good));
  auto expect_refused = [&](const std::function<void(Checkpoint&)>& edit, const std::string& why) {
    Checkpoint c = good;
    edit(c);
    try {
      restore(c);
      ADD_FAILURE() << "accepted: " << why;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("checkpoint refused"), std::string::npos) << e.what();
    }
  };
  expect_refused([](Checkpoint& c) { c.particles.vector("position")[3].x() = std::nan(""); }, "NaN position");
  expect_refused([](Checkpoint& c) { c.particles.integer("material_id")[0] = 7; }, "material id");
  expect_refused([](Checkpoint& c) { c.particles.integer("body_id")[1] = -1; }, "body id");
  expect_refused([](Checkpoint& c) { c.particles.integer("id")[2] = c.particles.integer("id")[3]; }, "duplicate id");
  expect_refused([](Checkpoint& c) { c.frame = -1; }, "negative frame");
  // Finite but where the solver's grids cannot hold it (the MPM one crashed P2G: found by fuzz_checkpoint).
  expect_refused([](Checkpoint& c) { c.particles.vector("position")[0] = Vec3(5, 5, 5); }, "position outside");
  expect_refused([](Checkpoint& c) { c.particles.scalar("mass")[0] = -1; }, "negative mass");
  expect_refused([](Checkpoint& c) { c.steps = long(1e18); }, "step count past any run");
  expect_refused(
      [](Checkpoint& c) {
        for (auto& [name, value] : c.solver_state)
          if (name == "time") value = std::nan("");
      },
      "NaN time");
  // The SPH heat waits a few steps at most (heat on its own step): a crafted wait of 10⁶ s would have
  // made the next step take ~10¹⁰ heat substeps.
  expect_refused(
      [](Checkpoint& c) {
        for (auto& [name, value] : c.solver_state)
          if (name == "heat_pending") value = 1e6;
      },
      "heat a million seconds behind");
  expect_refused([](Checkpoint& c) { c.particles.resize(c.particles.size() - 1); }, "a particle missing");
}

// Issue 21: nlohmann keeps the last of two equal keys silently; a value typed twice must not lose the first.
TEST(Scene, DuplicateKeysAreRefusedWithTheirPath) {
  std::string text = base_scene().dump();
  text.replace(text.find("\"material\":\"water\""), std::string("\"material\":\"water\"").size(),
               "\"material\":\"water\",\"name\":\"again\"");
  expect_text_error(text, {"scene.json", "bodies[0].name", "duplicate key"});
  expect_text_error(R"({"time": {"end": 1}, "time": {"end": 2}})", {"scene.json: time: duplicate key"});
  // Equal keys in different objects are fine.
  json two = base_scene();
  two["bodies"].push_back(two["bodies"][0]);
  two["bodies"][1]["name"] = "second";
  two["bodies"][1]["shape"] = {{"type", "box"}, {"min", {0.1, 0.1, 0.1}}, {"max", {0.15, 0.15, 0.15}}};
  EXPECT_NO_THROW(parse_scene(two.dump(), "scene.json", "."));
}

TEST(Scene, NamesThatReachTheTerminalHoldNoControlCharacters) {
  json s = base_scene();
  s["name"] = "loaf\x1b[2J";
  expect_error(s, {"name", "control characters"});
  json p = base_scene();
  p["probes"] = json::array({{{"name", "core,1"}, {"position", {0.05, 0.05, 0.05}}}});
  expect_error(p, {"probes[0].name"});  // the schema allows letters, digits, _ . - only
  json m = base_scene();
  m["materials"]["wa\nter"] = m["materials"]["water"];
  expect_error(m, {"control characters"});
}

// Issue 22: "$schema" (for editors) was refused as an unknown key.
TEST(Scene, SchemaKeyForEditorsIsAllowed) {
  json s = base_scene();
  s["$schema"] = "./scene.schema.json";
  EXPECT_NO_THROW(parse_scene(s.dump(), "scene.json", "."));
}

// Issue 22: an oven typed in kelvin or °F and a body typed in millimetres were accepted silently.
TEST(Scene, ValuesThatLookLikeAUnitMistakeAreWarnedAbout) {
  EXPECT_TRUE(parse_scene(base_scene().dump(), "scene.json", ".").warnings.empty());
  json kelvin = base_scene();
  kelvin["environment"]["air_temperature"] = 493;
  const auto w = parse_scene(kelvin.dump(), "scene.json", ".").warnings;
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("environment.air_temperature reaches 493 degC"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("would be 220 degC"), std::string::npos) << w[0];
  json schedule = base_scene();
  schedule["environment"]["air_temperature"] = json::array({json::array({0, 180}), json::array({600, 356})});
  EXPECT_EQ(parse_scene(schedule.dump(), "scene.json", ".").warnings.size(), 1u);
  // A 25 mm radius typed as 25: the particle-count refusal says what was probably meant.
  json mm = base_scene();
  mm["bodies"][0]["shape"] = {{"type", "sphere"}, {"center", {0.1, 0.1, 0.1}}, {"radius", 25}};
  expect_error(mm, {"solver.sph.spacing", "bodies[0].shape is about 50 m across", "50 mm would be 0.05 m"});
}

// Issue 22 item 2: `--set key.path=value` changes a scene before it is checked.
TEST(Scene, OverridesChangeTheDocumentBeforeItIsChecked) {
  const std::string text = base_scene().dump();
  const Scene s =
      parse_scene(text, "scene.json", ".",
                  {parse_override("bodies[0].temperature=5"), parse_override("environment.air_temperature=200"),
                   parse_override("solver.sph.spacing=0.008"), parse_override("name=hot")});
  EXPECT_EQ(s.resolved["bodies"][0]["temperature"], 5.0);
  EXPECT_EQ(s.resolved["environment"]["air_temperature"], 200.0);
  EXPECT_EQ(s.resolved["solver"]["sph"]["spacing"], 0.008);
  EXPECT_EQ(s.name, "hot");  // not JSON: a plain string
  // The schema still judges the value, naming the key.
  auto refused = [&](const std::string& set, const std::string& fragment) {
    try {
      parse_scene(text, "scene.json", ".", {parse_override(set)});
      ADD_FAILURE() << "accepted --set " << set;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  refused("bodies[0].temperature=hot", "bodies[0].temperature: expected a number");
  refused("bodies[0].temperatur=5", "did you mean 'temperature'");
  refused("bodies[2].temperature=5", "--set bodies[2].temperature: bodies has 1 entries");
  refused("time.end.x=1", "time.end is not an object");
  EXPECT_THROW(parse_override("no-equals-sign"), InputError);
  EXPECT_THROW(parse_override("bodies[a].x=1"), InputError);
  EXPECT_THROW(parse_override("bodies..x=1"), InputError);
}

namespace {

// A folder of scene files for the "extends" tests, emptied first.
std::filesystem::path scene_folder(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

void write_json(const std::filesystem::path& file, const json& doc) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file) << doc.dump(2);
}

}  // namespace

// Issue 22 item 2: "extends" lays a variant over a base scene (RFC 7386 merge patch).
TEST(Scene, ExtendsMergesTheVariantOverItsBase) {
  const auto dir = scene_folder("bakesim_test_extends");
  json base = base_scene();
  base["name"] = "base";
  base["environment"] = {{"air_temperature", 180}, {"heat_transfer_coefficient", 25}};
  base["output"] = {{"particles", {"ply"}}};
  write_json(dir / "base" / "base.json", base);
  write_json(dir / "variant.json", {{"extends", "base/base.json"},
                                    {"environment", {{"air_temperature", 150}}},
                                    {"materials", {{"water", {{"viscosity", 0.002}}}}},
                                    {"output", nullptr}});
  const Scene s = load_scene((dir / "variant.json").string());
  const json& r = s.resolved;
  EXPECT_EQ(r["environment"]["air_temperature"], 150);           // the variant's value
  EXPECT_EQ(r["environment"]["heat_transfer_coefficient"], 25);  // kept from the base
  EXPECT_EQ(r["materials"]["water"]["density"], 1000);           // objects merge key by key
  EXPECT_EQ(r["materials"]["water"]["viscosity"], 0.002);
  EXPECT_EQ(r["output"]["particles"], json::array({"ply", "vtu"}));  // null removes: the default again
  EXPECT_EQ(s.name, "variant");                                      // the base's name is not inherited
  EXPECT_FALSE(r.contains("extends"));                               // the resolved scene stands alone
  ASSERT_EQ(s.extends.size(), 1u);
  EXPECT_NE(s.extends[0].find("base.json"), std::string::npos);
  // Lists are replaced whole; --set comes after the merge.
  write_json(dir / "two.json", {{"extends", "variant.json"}, {"name", "two"}});
  const Scene t = load_scene((dir / "two.json").string(), {parse_override("environment.air_temperature=210")});
  EXPECT_EQ(t.resolved["environment"]["air_temperature"], 210);
  EXPECT_EQ(t.resolved["materials"]["water"]["viscosity"], 0.002);
  EXPECT_EQ(t.extends.size(), 2u);
}

TEST(Scene, ExtendsResolvesMeshPathsAgainstTheFileThatNamesThem) {
  const auto dir = scene_folder("bakesim_test_extends_mesh");
  std::filesystem::create_directories(dir / "base" / "meshes");
  std::ofstream(dir / "base" / "meshes" / "tri.obj") << "v 0 0 0\nv 0.1 0 0\nv 0 0 0.1\nf 1 2 3\n";
  json base = base_scene();
  base["colliders"] = json::array({{{"name", "sheet"}, {"shape", {{"type", "mesh"}, {"file", "meshes/tri.obj"}}}}});
  write_json(dir / "base" / "base.json", base);
  write_json(dir / "variant.json", {{"extends", "base/base.json"}});
  const Scene s = load_scene((dir / "variant.json").string());
  const std::string file = s.resolved["colliders"][0]["shape"]["file"].get<std::string>();
  EXPECT_EQ(std::filesystem::path(file), (dir / "base" / "meshes" / "tri.obj").lexically_normal());
}

TEST(Scene, ExtendsErrorsNameTheFileThatHoldsTheKey) {
  const auto dir = scene_folder("bakesim_test_extends_errors");
  json base = base_scene();
  base["materials"]["water"]["density"] = -5;
  write_json(dir / "base.json", base);
  write_json(dir / "variant.json", {{"extends", "base.json"}, {"time", {{"end", 0.2}}}});
  auto refused = [](const std::filesystem::path& file, const std::vector<std::string>& fragments) {
    try {
      load_scene(file.string());
      ADD_FAILURE() << "accepted " << file;
    } catch (const InputError& e) {
      for (const auto& f : fragments)
        EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << "'" << f << "' not in: " << e.what();
    }
  };
  refused(dir / "variant.json", {"base.json: materials.water.density", "which extends"});
  write_json(dir / "good.json", base_scene());
  write_json(dir / "bad-time.json", {{"extends", "good.json"}, {"time", {{"end", "soon"}}}});
  refused(dir / "bad-time.json", {"bad-time.json: time.end"});
  write_json(dir / "missing.json", {{"extends", "nowhere.json"}});
  refused(dir / "missing.json", {"missing.json: extends", "no such scene file", "nowhere.json"});
  write_json(dir / "a.json", {{"extends", "b.json"}});
  write_json(dir / "b.json", {{"extends", "a.json"}});
  refused(dir / "a.json", {"a.json", "extend each other in a circle"});
  write_json(dir / "self.json", {{"extends", "self.json"}});
  refused(dir / "self.json", {"circle"});
  write_json(dir / "number.json", {{"extends", 3}});
  refused(dir / "number.json", {"number.json: extends", "must be the path"});
  std::ofstream(dir / "broken.json") << "{\"time\": }";
  write_json(dir / "on-broken.json", {{"extends", "broken.json"}});
  refused(dir / "on-broken.json", {"broken.json:1:", "JSON syntax error"});
}

// A tray preheated with the oven: "temperature": "oven" follows the air's schedule.
TEST(Scene, ColliderTemperatureCanFollowTheOven) {
  json d = base_scene();
  d["environment"]["air_temperature"] = json::array({json::array({0, 150}), json::array({600, 200})});
  d["colliders"] = json::array({{{"name", "tray"},
                                 {"shape", {{"type", "plane"}, {"point", {0, 0.01, 0}}, {"normal", {0, 1, 0}}}},
                                 {"temperature", "oven"}}});
  const Scene s = parse_scene(d.dump(), "scene.json", ".");
  ASSERT_TRUE(s.sph.colliders.at(0).temperature.has_value());
  EXPECT_DOUBLE_EQ((*s.sph.colliders[0].temperature)(300.0), 175.0);
  d["colliders"][0]["temperature"] = "hot";
  expect_error(d, {"colliders[0].temperature"});
}

namespace {

json mpm_preset_scene(double clock) {
  return json::parse(fmt::format(R"({{
    "solver": {{"type": "mpm", "mpm": {{"cell_size": 0.005}}}},
    "time": {{"end": 0.1}},
    "domain": {{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}},
    "environment": {{"bake_time_scale": {}}},
    "materials": {{"dough": {{"preset": "cookie-dough"}}}},
    "bodies": [{{"name": "cookie", "material": "dough",
                "shape": {{"type": "box", "min": [0.05, 0.05, 0.05], "max": [0.1, 0.07, 0.1]}}}}]
  }})",
                                 clock));
}

}  // namespace

// Issue 22 item 1: presets with physical viscosities; bakesim divides them by the bake clock.
TEST(Scene, PresetViscositiesArePhysicalAndDividedByTheBakeClock) {
  const Scene a = parse_scene(mpm_preset_scene(360).dump(), "scene.json", ".");
  const json& m = a.resolved["materials"]["dough"];
  // The preset file holds 72,000 Pa s at 5 degC (bakesim's cookie scene: 200 Pa s on its clock of 360).
  EXPECT_DOUBLE_EQ(m["plasticity"]["viscosity"]["points"][0][1].get<double>(), 200.0);
  EXPECT_EQ(m["preset"], "none");  // the resolved scene holds the divided values and re-runs as it is
  const Scene b = parse_scene(mpm_preset_scene(720).dump(), "scene.json", ".");
  EXPECT_DOUBLE_EQ(b.resolved["materials"]["dough"]["plasticity"]["viscosity"]["points"][0][1].get<double>(), 100.0);
  // A scene's own value for a physical time is physical too.
  json own = mpm_preset_scene(360);
  own["materials"]["dough"]["plasticity"] = {{"viscosity", 3600.0}};
  EXPECT_DOUBLE_EQ(parse_scene(own.dump(), "scene.json", ".")
                       .resolved["materials"]["dough"]["plasticity"]["viscosity"]
                       .get<double>(),
                   10.0);
  // The resolved scene parses to itself.
  const Scene again = parse_scene(a.resolved.dump(), "scene.json", ".");
  EXPECT_EQ(again.resolved, a.resolved);
  ASSERT_EQ(a.notes.size(), 1u);
  EXPECT_NE(a.notes[0].find("preset cookie-dough"), std::string::npos) << a.notes[0];
  EXPECT_NE(a.notes[0].find("divided by the bake clock 360"), std::string::npos) << a.notes[0];
}

TEST(Scene, PresetThermalPropertiesAndWaterComeFromTheComposition) {
  const Scene s = parse_scene(mpm_preset_scene(360).dump(), "scene.json", ".");
  const json& m = s.resolved["materials"]["dough"];
  FoodComposition cookie;  // materials/cookie-dough.json
  cookie[FoodComponent::water] = 0.1433, cookie[FoodComponent::protein] = 0.0427, cookie[FoodComponent::fat] = 0.1933;
  cookie[FoodComponent::carbohydrate] = 0.5973, cookie[FoodComponent::fibre] = 0.0074,
  cookie[FoodComponent::ash] = 0.0159;
  cookie.porosity = 0.1;
  const ThermalProperties t = food_properties(cookie, 20);
  EXPECT_NEAR(m["density"].get<double>(), t.density, 0.5);
  EXPECT_NEAR(m["specific_heat"].get<double>(), t.specific_heat, 0.5);
  EXPECT_NEAR(m["conductivity"].get<double>(), t.conductivity, 5e-4);
  // The particles carry the composition's water: the section's moisture (dry basis) X₀ = x / (1 − x).
  EXPECT_NEAR(m["moisture"]["content"].get<double>(), 0.1433 / (1 - 0.1433), 1e-4);
  // A density the scene gives wins.
  json denser = mpm_preset_scene(360);
  denser["materials"]["dough"]["density"] = 1300;
  const Scene dense = parse_scene(denser.dump(), "scene.json", ".");
  EXPECT_EQ(dense.resolved["materials"]["dough"]["density"], 1300);
  // A preset whose MPM section has no moisture (the enriched dough) carries the water as the paper's
  // saturation ρ_w / ρ = its mass fraction, following the density the scene gives.
  denser["materials"]["dough"]["preset"] = "enriched-dough";
  const json enriched = parse_scene(denser.dump(), "scene.json", ".").resolved["materials"]["dough"];
  const double x = material_preset("enriched-dough", "test")["composition"]["water"].get<double>();
  EXPECT_NEAR(enriched["water"]["saturation"].get<double>() * 1000 / 1300, x, 1e-4);
  // One with moisture (the muffin batter) carries it as moisture content and no saturation.
  denser["materials"]["dough"]["preset"] = "muffin-batter";
  const json muffin = parse_scene(denser.dump(), "scene.json", ".").resolved["materials"]["dough"];
  const double xm = material_preset("muffin-batter", "test")["composition"]["water"].get<double>();
  EXPECT_NEAR(muffin["moisture"]["content"].get<double>(), xm / (1 - xm), 1e-4);
  EXPECT_EQ(muffin["water"]["saturation"], 0);
}

// Issue 22 item 1: an SPH section's particles carry the composition's water (dry basis) with its porosity as the
// pores' gas fraction; a section may give its own porosity (the lean dough's particles are the dough between the
// bubble particles), which sets the thermal properties too; the scene's values win.
TEST(Scene, SphPresetsCarryTheCompositionsWaterAndPores) {
  json doc = base_scene();
  doc["environment"] = {{"air_temperature", 180}, {"bake_time_scale", 400}};
  doc["materials"]["water"] = {{"preset", "muffin-batter"}};
  const json muffin = parse_scene(doc.dump(), "scene.json", ".").resolved["materials"]["water"];
  const json composition = material_preset("muffin-batter", "test")["composition"];
  const double x = composition["water"].get<double>();
  EXPECT_NEAR(muffin["moisture"]["content"].get<double>(), x / (1 - x), 1e-3);
  EXPECT_EQ(muffin["moisture"]["gas_fraction"], composition["porosity"]);
  // Its viscosity is physical and divided by the clock: 20,000 Pa s at 20 degC (the MPM section's 40,000 halved).
  EXPECT_DOUBLE_EQ(muffin["viscosity"]["points"][1][1].get<double>(), 20000.0 / 400);
  doc["materials"]["water"] = {{"preset", "lean-bread-dough"}};
  const json lean = parse_scene(doc.dump(), "scene.json", ".").resolved["materials"]["water"];
  FoodComposition dough = preset_composition(material_preset("lean-bread-dough", "test")["composition"]);
  dough.porosity = 0.1;  // the SPH section's
  EXPECT_NEAR(lean["density"].get<double>(), food_properties(dough, 20).density, 0.5);
  EXPECT_EQ(lean["moisture"]["gas_fraction"], 0.1);
  EXPECT_FALSE(lean.contains("porosity"));  // a preset-file key, not a scene key
  doc["materials"]["water"]["moisture"] = {{"content", 0.5}, {"gas_fraction", 0.3}};
  const json own = parse_scene(doc.dump(), "scene.json", ".").resolved["materials"]["water"];
  EXPECT_EQ(own["moisture"]["content"], 0.5);
  EXPECT_EQ(own["moisture"]["gas_fraction"], 0.3);
  EXPECT_EQ(own["moisture"]["tortuosity"], 10);  // the rest of the preset's moisture stays
}

// An MPM scene that gives a preset material `moisture` takes its water from the moisture model: the preset
// no longer fills the MPM `water.saturation` beside it (which the scene check refuses with a moisture
// content, and which the scene could not leave out since it never wrote it).
TEST(Scene, MpmPresetsWithMoistureCarryTheirWaterAsMoisture) {
  json doc = mpm_preset_scene(600);
  // The enriched dough's MPM section has the paper's water only; the scene gives it moisture.
  doc["materials"]["dough"] = {{"preset", "enriched-dough"}, {"moisture", {{"tortuosity", 10}}}};
  const Scene scene = parse_scene(doc.dump(), "scene.json", ".");
  const json& dough = scene.resolved["materials"]["dough"];
  const double x = material_preset("enriched-dough", "test")["composition"]["water"].get<double>();
  EXPECT_NEAR(dough["moisture"]["content"].get<double>(), x / (1 - x), 1e-3);
  // The resolved scene holds the schema's defaults for what the preset no longer gives.
  EXPECT_EQ(dough["water"]["saturation"], 0);
  EXPECT_EQ(dough["water"]["evaporation_rate"], 0);
  EXPECT_EQ(dough["water"]["stiffness"], 2000.0);  // the rest of the preset's MPM water law stays
  // Without moisture the preset's MPM water is its saturation, as before.
  doc["materials"]["dough"].erase("moisture");
  const json plain = parse_scene(doc.dump(), "scene.json", ".").resolved["materials"]["dough"];
  EXPECT_NEAR(plain["water"]["saturation"].get<double>(), x * plain["density"].get<double>() / 1000, 1e-3);
  // A scene's own saturation beside a moisture content is still refused, naming the key.
  doc["materials"]["dough"]["moisture"] = {{"content", 0.6}};
  doc["materials"]["dough"]["water"] = {{"saturation", 0.4}};
  expect_error(doc, {"materials.dough.water.saturation", "leave water.saturation out"});
}

// Issue 23: a material's raw_colour (CIE L*a*b*) is what its particles brown from in pictures and meshes: a
// preset gives it (dark chocolate's measured colour), the run's geometry reads it by material id (materials in
// name order), the colour samples carry it per particle, and a lightness outside 0-100 is refused by its path.
TEST(Scene, RawColoursComeFromPresetsAndReachTheColourSamples) {
  json doc = base_scene();
  doc["materials"]["chocolate"] = {{"preset", "dark-chocolate"}};
  const Scene scene = parse_scene(doc.dump(), "scene.json", ".");
  EXPECT_EQ(scene.resolved["materials"]["chocolate"]["raw_colour"], json::parse("[17.4, 2.6, 1.4]"));
  EXPECT_TRUE(scene.resolved["materials"]["water"]["raw_colour"].is_null());  // the schema's default: none
  const RunGeometry g = run_geometry(scene.resolved);
  ASSERT_EQ(g.raw_colour.size(), 2u);
  EXPECT_DOUBLE_EQ(g.raw_colour[0].L, 17.4);  // "chocolate" sorts before "water"
  EXPECT_DOUBLE_EQ(g.raw_colour[1].L, surface::dough_lab().L);
  ParticleSet ps;
  ps.add_vector("position", "m");
  ps.add_scalar("browning", "");
  std::vector<std::int32_t>& material = ps.add_int("material_id");
  ps.resize(2);
  material[0] = 1, material[1] = 0;
  const surface::ColourSamples samples = colour_samples(ps, g, MeshSettings{});
  ASSERT_EQ(samples.raw.size(), 2u);
  EXPECT_DOUBLE_EQ(samples.raw[0].L, 80.0);
  EXPECT_DOUBLE_EQ(samples.raw[1].L, 17.4);
  // A scene of doughs only carries none (the dough's path, as before raw colours).
  doc["materials"].erase("chocolate");
  EXPECT_TRUE(colour_samples(ps, run_geometry(parse_scene(doc.dump(), "scene.json", ".").resolved), MeshSettings{})
                  .raw.empty());
  doc["materials"]["water"]["raw_colour"] = {120, 0, 0};
  expect_error(doc, {"materials.water.raw_colour[0]", "L* is 120"});
  doc["materials"]["water"]["raw_colour"] = {50, 0};
  expect_error(doc, {"materials.water.raw_colour"});
}

TEST(Scene, PresetsAreCheckedByNameAndSolver) {
  json typo = mpm_preset_scene(360);
  typo["materials"]["dough"]["preset"] = "cookie-dought";
  expect_error(typo, {"materials.dough.preset", "unknown preset 'cookie-dought'", "did you mean 'cookie-dough'"});
  // Every food preset has an SPH section now; the thesis's dough alone has no MPM one.
  json mpm = mpm_preset_scene(360);
  mpm["materials"]["dough"]["preset"] = "dough";
  expect_error(mpm, {"materials.dough.preset", "'dough' has no MPM rheology", "for the SPH solver"});
  // The thesis's SPH dough is what it was: its values, and its name kept in the resolved scene.
  json thesis = base_scene();
  thesis["materials"]["water"] = {{"preset", "dough"}};
  const Scene t = parse_scene(thesis.dump(), "scene.json", ".");
  const json& r = t.resolved["materials"]["water"];
  EXPECT_EQ(r["preset"], "dough");
  EXPECT_EQ(r["viscosity"]["points"], json::parse("[[26, 0.1], [45, 1.0], [120, 5000.0]]"));
  EXPECT_DOUBLE_EQ(r["density"].get<double>(), 1100.0);
}

TEST(Scene, EveryPresetLoadsForItsSolvers) {
  for (const std::string& name : material_preset_names()) {
    const json p = material_preset(name, "test");
    for (const char* solver : {"mpm", "sph"}) {
      if (!p.contains(solver)) continue;
      json doc = std::string(solver) == "mpm" ? mpm_preset_scene(360) : base_scene();
      doc["materials"] = {{"m", {{"preset", name}}}};
      doc["bodies"][0]["material"] = "m";
      EXPECT_NO_THROW(make_solver(parse_scene(doc.dump(), "scene.json", "."))) << name << " " << solver;
    }
    EXPECT_TRUE(p.contains("sources")) << name;
  }
}

// Issue 22 item 1: a dough baked with water's thermal properties (the schema's defaults) is warned about.
TEST(Scene, ABakeOfAMaterialWithoutThermalPropertiesIsWarnedAbout) {
  json bake = base_scene();
  bake["environment"] = {{"air_temperature", 180}, {"bake_time_scale", 100}};
  const auto w = parse_scene(bake.dump(), "scene.json", ".").warnings;
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("materials.water (specific_heat, conductivity) not given: water's are used"), std::string::npos)
      << w[0];
  bake["materials"]["water"] = {{"preset", "dough"}};  // the preset gives them
  EXPECT_TRUE(parse_scene(bake.dump(), "scene.json", ".").warnings.empty());
  EXPECT_TRUE(parse_scene(base_scene().dump(), "scene.json", ".").warnings.empty());  // water at room temperature
}

// Found by fuzzing (2026-12-02): values of the wrong type that the loader reads before the schema
// (a shape's "type", a preset material's viscosity curve) threw JSON's own error, not one with the key path.
TEST(Scene, WrongTypesReadBeforeTheSchemaAreErrorsWithTheirKeyPath) {
  json shape = base_scene();
  shape["bodies"][0]["shape"]["type"] = 7;
  expect_error(shape, {"bodies[0].shape"});
  json curve = mpm_preset_scene(360);
  curve["materials"]["dough"]["plasticity"] = {{"viscosity", {{"curve", 5}, {"points", {{20, 100}}}}}};
  expect_error(curve, {"materials.dough.plasticity.viscosity", "divides by the bake clock"});
}

// Issue 22 item 1: oven presets give the air coefficient where the scene gives none.
TEST(Scene, OvenPresetsGiveTheAirCoefficient) {
  auto coefficient = [](const json& doc) {
    return parse_scene(doc.dump(), "scene.json", ".").oven.heat_transfer_coefficient;
  };
  json d = base_scene();
  EXPECT_DOUBLE_EQ(coefficient(d), 10.0);  // no preset: the default
  d["environment"]["oven"] = "fan";
  EXPECT_DOUBLE_EQ(coefficient(d), 30.0);
  d["environment"]["oven"] = "conventional";
  EXPECT_DOUBLE_EQ(coefficient(d), 15.0);
  d["environment"]["heat_transfer_coefficient"] = 22;  // the scene's own value wins
  EXPECT_DOUBLE_EQ(coefficient(d), 22.0);
  d["environment"]["oven"] = "convection";
  expect_error(d, {"environment.oven", "conventional"});
}

// And their walls radiate (issue 22 item 1: "h and, where the oven model has it, wall radiation"): a
// food surface's emissivity of 0.9 unless the scene gives its own; no preset, no radiation.
TEST(Scene, OvenPresetsRadiateFromTheirWalls) {
  auto emissivity = [](const json& doc) { return parse_scene(doc.dump(), "scene.json", ".").oven.emissivity; };
  json d = base_scene();
  EXPECT_DOUBLE_EQ(emissivity(d), 0.0);
  for (const char* oven : {"conventional", "fan", "deck"}) {
    d["environment"]["oven"] = oven;
    EXPECT_DOUBLE_EQ(emissivity(d), 0.9) << oven;
  }
  d["environment"]["heat_transfer_coefficient"] = 22;  // the scene's own coefficient keeps the walls
  EXPECT_DOUBLE_EQ(emissivity(d), 0.9);
  d["environment"]["emissivity"] = 0.0;  // the scene's own emissivity wins: no radiation
  EXPECT_DOUBLE_EQ(emissivity(d), 0.0);
  d["environment"]["oven"] = "none";
  d["environment"].erase("emissivity");
  EXPECT_DOUBLE_EQ(emissivity(d), 0.0);
}

// Found under AddressSanitizer (2026-12-02): the copies that "extends", presets and --set make
// recursed through a value nested 100,000 deep. Such values are refused before they are copied.
TEST(Scene, DeeplyNestedValuesAreRefusedBeforeTheyAreCopied) {
  const std::string nested = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_THROW(parse_override("materials.water.density=" + nested), InputError);
  try {
    parse_override("materials.water.density=" + nested);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nested more than 200 levels deep"), std::string::npos) << e.what();
  }
  const auto dir = scene_folder("bakesim_test_deep");
  std::string base = base_scene().dump();
  base.replace(base.find("\"density\":1000"), std::string("\"density\":1000").size(), "\"density\":" + nested);
  std::ofstream(dir / "base.json") << base;
  write_json(dir / "variant.json", {{"extends", "base.json"}});
  try {
    load_scene((dir / "variant.json").string());
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nested more than"), std::string::npos) << e.what();
  }
  json preset = mpm_preset_scene(360);
  std::string text = preset.dump();
  text.replace(text.find("\"preset\":\"cookie-dough\""), std::string("\"preset\":\"cookie-dough\"").size(),
               "\"preset\":\"cookie-dough\",\"density\":" + nested);
  expect_text_error(text, {"materials.dough", "nested more than"});
}

// Issue 26: domain.periodic names axes once; a periodic box shorter than two
// supports would find a neighbour twice; MPM needs whole cells along the axis.
TEST(Scene, PeriodicAxesAreCheckedForEachSolver) {
  json ok = base_scene();
  ok["domain"]["periodic"] = {"x", "z"};
  const Scene s = parse_scene(ok.dump(), "scene.json", ".");
  EXPECT_TRUE(s.sph.periodic[0]);
  EXPECT_FALSE(s.sph.periodic[1]);
  EXPECT_TRUE(s.sph.periodic[2]);
  json twice = base_scene();
  twice["domain"]["periodic"] = {"x", "x"};
  expect_error(twice, {"scene.json: domain.periodic[1]", "axis 'x' is listed twice"});
  json bad = base_scene();
  bad["domain"]["periodic"] = {"w"};
  expect_error(bad, {"domain.periodic[0]", "\"x\", \"y\", \"z\""});
  json short_box = base_scene();
  short_box["domain"]["periodic"] = {"y"};
  short_box["domain"]["max"] = {0.2, 0.035, 0.2};
  short_box["bodies"][0]["shape"]["max"] = {0.08, 0.03, 0.08};
  expect_error(short_box, {"domain.periodic", "periodic axis y", "two smoothing supports (0.04 m)"});
  // MPM: a whole number of cells along the axis, and not with implicit heat;
  // the loader names the file, the solver refuses a setup built in code too.
  json mpm = mpm_scene();
  mpm["domain"]["periodic"] = {"x"};
  mpm["solver"]["mpm"]["heat"] = "explicit";
  const Scene whole = parse_scene(mpm.dump(), "scene.json", ".");
  EXPECT_NO_THROW(mpm::MpmSolver{whole.mpm});  // 0.2 m of 5 mm cells
  json part = mpm;
  part["domain"]["max"][0] = 0.1013;
  expect_error(part, {"scene.json: domain.periodic", "40.26 cells of 0.005 m along the periodic axis x"});
  json implicit_heat = mpm;
  implicit_heat["solver"]["mpm"]["heat"] = "implicit";
  expect_error(implicit_heat, {"scene.json: domain.periodic", "needs explicit heat"});
  mpm::Setup in_code = whole.mpm;
  in_code.domain.max.x() = 0.1013;
  EXPECT_THROW(mpm::MpmSolver{in_code}, InputError);
}

// MPM's herschel_bulkley plasticity: the shared law's numbers (shear yield
// stress, consistency, flow index), temperature curves through the setting
// curves as for von Mises; flow_index with another model is an error.
TEST(Scene, MpmHerschelBulkleyPlasticityTakesTheSharedLawsNumbers) {
  json doc = mpm_scene();
  doc["materials"]["dough"]["plasticity"] = {
      {"model", "herschel_bulkley"}, {"yield_stress", 80.0}, {"viscosity", 12.0}, {"flow_index", 0.4}};
  const Scene s = parse_scene(doc.dump(), "scene.json", ".");
  const auto* law = std::get_if<mpm::HerschelBulkleyFlow>(&s.mpm.materials.at(0).plastic);
  ASSERT_NE(law, nullptr);
  EXPECT_DOUBLE_EQ(law->yield_stress, 80.0);
  EXPECT_DOUBLE_EQ(law->viscosity, 12.0);
  EXPECT_DOUBLE_EQ(law->flow_index, 0.4);
  json wrong = mpm_scene();
  wrong["materials"]["dough"]["plasticity"]["flow_index"] = 0.5;
  expect_error(wrong, {"scene.json: materials.dough.plasticity.flow_index", "herschel_bulkley"});
}

// SPH's elastoviscoplastic yield form reads the material's elasticity as the
// solid below the yield stress: without one it is an error naming the key.
TEST(Scene, SphElastoviscoplasticYieldNeedsAnElasticity) {
  json d = base_scene();
  d["materials"]["water"]["herschel_bulkley"] = {{"yield_stress", 50.0}, {"form", "elastoviscoplastic"}};
  expect_error(d, {"scene.json: materials.water.herschel_bulkley.form", "needs the material's elasticity"});
  d["materials"]["water"]["elasticity"] = 2e4;
  const Scene s = parse_scene(d.dump(), "scene.json", ".");
  ASSERT_TRUE(s.sph.materials[0].yield_flow.has_value());
  EXPECT_TRUE(s.sph.materials[0].yield_flow->elastoviscoplastic);
  // With the Laplacian operator, clamped negative pressure and a support of 2 spacings (the
  // defaults) it warns, naming the three keys.
  const std::vector<std::string> w = parse_scene(d.dump(), "scene.json", ".").warnings;
  ASSERT_EQ(w.size(), 3u);
  EXPECT_NE(w[0].find("viscosity_operator to stress"), std::string::npos) << w[0];
  EXPECT_NE(w[1].find("negative_pressure to keep"), std::string::npos) << w[1];
  EXPECT_NE(w[2].find("smoothing_ratio 2:"), std::string::npos) << w[2];
  EXPECT_NE(w[2].find("set smoothing_ratio to 2.5"), std::string::npos) << w[2];
  d["solver"]["sph"]["viscosity_operator"] = "stress";
  d["solver"]["sph"]["negative_pressure"] = "keep";
  d["solver"]["sph"]["smoothing_ratio"] = 2.5;
  EXPECT_TRUE(parse_scene(d.dump(), "scene.json", ".").warnings.empty());
  json regularised = base_scene();
  regularised["materials"]["water"]["herschel_bulkley"] = {{"yield_stress", 50.0}};
  EXPECT_FALSE(parse_scene(regularised.dump(), "scene.json", ".").sph.materials[0].yield_flow->elastoviscoplastic);
}

// The elastoviscoplastic form reads neither the regularisation rate nor the
// Maxwell relaxation time: given, each is refused with its key path (the
// schema's defaults fill both, so the check reads the scene as written); a
// preset's relaxation time is dropped from the resolved scene.
TEST(Scene, SphElastoviscoplasticRefusesTheKeysItDoesNotRead) {
  json d = base_scene();
  d["materials"]["water"]["elasticity"] = 2e4;
  d["materials"]["water"]["herschel_bulkley"] = {
      {"yield_stress", 50.0}, {"form", "elastoviscoplastic"}, {"regularisation_rate", 0.01}};
  expect_error(d, {"scene.json: materials.water.herschel_bulkley.regularisation_rate", "remove it"});
  d["materials"]["water"]["herschel_bulkley"].erase("regularisation_rate");
  d["materials"]["water"]["relaxation_time"] = 5.0;
  expect_error(d, {"scene.json: materials.water.relaxation_time", "remove it"});
  d["materials"]["water"].erase("relaxation_time");
  EXPECT_NO_THROW(parse_scene(d.dump(), "scene.json", "."));
  // The regularised form reads both.
  json regularised = base_scene();
  regularised["materials"]["water"]["relaxation_time"] = 5.0;
  regularised["materials"]["water"]["herschel_bulkley"] = {{"yield_stress", 50.0}, {"regularisation_rate", 0.01}};
  EXPECT_NO_THROW(parse_scene(regularised.dump(), "scene.json", "."));
  // A preset's relaxation time (the lean dough's viscoelastic curve) is dropped, not refused.
  json preset = base_scene();
  preset["materials"]["water"] = {{"preset", "lean-bread-dough"},
                                  {"herschel_bulkley", {{"yield_stress", 50.0}, {"form", "elastoviscoplastic"}}}};
  const Scene s = parse_scene(preset.dump(), "scene.json", ".");
  ASSERT_TRUE(s.sph.materials[0].yield_flow.has_value());
  EXPECT_TRUE(s.sph.materials[0].yield_flow->elastoviscoplastic);
  EXPECT_FALSE(s.resolved["materials"]["water"].contains("relaxation_time"));
  // A variant that switches a base's regularised material to the form: the error names the base
  // file's key; null in the variant removes it (the merge patch's rule).
  const auto dir = scene_folder("bakesim_test_extends_evp");
  write_json(dir / "base.json", regularised);
  json variant = {{"extends", "base.json"},
                  {"materials",
                   {{"water",
                     {{"elasticity", 2e4},
                      {"herschel_bulkley", {{"form", "elastoviscoplastic"}, {"regularisation_rate", nullptr}}}}}}}};
  write_json(dir / "variant.json", variant);
  try {
    load_scene((dir / "variant.json").string());
    ADD_FAILURE() << "the base's relaxation_time was not refused";
  } catch (const InputError& e) {
    EXPECT_NE(e.where().find("base.json: materials.water.relaxation_time"), std::string::npos) << e.where();
    EXPECT_NE(e.detail().find("write it as null"), std::string::npos) << e.detail();
  }
  variant["materials"]["water"]["relaxation_time"] = nullptr;
  write_json(dir / "variant.json", variant);
  const Scene v = load_scene((dir / "variant.json").string());
  EXPECT_TRUE(v.sph.materials[0].yield_flow->elastoviscoplastic);
  EXPECT_FALSE(v.resolved["materials"]["water"].contains("relaxation_time"));
}

// SPH's stress-form viscosity is implicit: auto picks the implicit solve,
// explicit is an error naming the key; MPM does not read it.
TEST(Scene, SphStressViscosityIsImplicit) {
  json doc = base_scene();
  doc["solver"]["sph"]["viscosity_operator"] = "stress";
  const Scene s = parse_scene(doc.dump(), "scene.json", ".");
  EXPECT_TRUE(s.sph.settings.stress_viscosity);
  doc["solver"]["sph"]["viscosity_solver"] = "explicit";
  expect_error(doc, {"scene.json: solver.sph.viscosity_operator", "implicit"});
  json plain = base_scene();
  EXPECT_FALSE(parse_scene(plain.dump(), "scene.json", ".").sph.settings.stress_viscosity);
}

// The stress form beside a sticky collider warns, naming the operator's key
// and the collider (a known defect: docs/validation.md).
TEST(Scene, SphStressViscosityBesideAStickyWallWarns) {
  json doc = base_scene();
  doc["solver"]["sph"]["viscosity_operator"] = "stress";
  doc["colliders"] = json::array({{{"name", "plate"},
                                   {"shape", {{"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 1, 0}}}},
                                   {"contact", "sticky"}}});
  const std::vector<std::string> w = parse_scene(doc.dump(), "scene.json", ".").warnings;
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("scene.json: solver.sph.viscosity_operator"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("'plate' (colliders[0])"), std::string::npos) << w[0];
  doc["colliders"][0]["contact"] = "slip";
  EXPECT_TRUE(parse_scene(doc.dump(), "scene.json", ".").warnings.empty());
  doc["colliders"][0]["contact"] = "sticky";
  doc["solver"]["sph"]["viscosity_operator"] = "laplacian";
  EXPECT_TRUE(parse_scene(doc.dump(), "scene.json", ".").warnings.empty());
}

// surface.every_steps spaces the convex-hull detections; with the colour
// method (the default), which runs every step, a spacing is an error naming the key.
TEST(Scene, SphSurfaceEveryStepsOnlyWithTheConvexHull) {
  json doc = base_scene();
  doc["solver"]["sph"]["surface"] = {{"method", "convex_hull"}, {"every_steps", 5}};
  EXPECT_EQ(parse_scene(doc.dump(), "scene.json", ".").sph.settings.surface_every, 5);
  json colour = base_scene();
  colour["solver"]["sph"]["surface"] = {{"every_steps", 2}};
  expect_error(colour, {"scene.json: solver.sph.surface.every_steps", "convex_hull"});
  colour["solver"]["sph"]["surface"] = {{"every_steps", 1}};
  EXPECT_EQ(parse_scene(colour.dump(), "scene.json", ".").sph.settings.surface_every, 1);
}

// Implicit elasticity rides on the implicit viscosity solve: explicit
// viscosity with it is an error naming the key; the default is explicit.
TEST(Scene, SphImplicitElasticityNeedsTheImplicitViscositySolve) {
  json doc = base_scene();
  EXPECT_FALSE(parse_scene(doc.dump(), "scene.json", ".").sph.settings.implicit_elasticity);
  doc["solver"]["sph"]["elasticity_solver"] = "implicit";
  EXPECT_TRUE(parse_scene(doc.dump(), "scene.json", ".").sph.settings.implicit_elasticity);
  doc["solver"]["sph"]["viscosity_solver"] = "explicit";
  expect_error(doc, {"scene.json: solver.sph.elasticity_solver", "viscosity_solver"});
  doc["solver"]["sph"]["viscosity_solver"] = "auto";
  doc["solver"]["sph"]["elasticity_solver"] = "sometimes";
  expect_error(doc, {"solver.sph.elasticity_solver"});
}

TEST(Scene, SphDivergenceFreePressureRefusesBubblesAndReadsItsTolerances) {
  json doc = base_scene();
  EXPECT_EQ(parse_scene(doc.dump(), "scene.json", ".").sph.settings.pressure_solver,
            sph::PressureSolver::weakly_compressible);
  doc["solver"]["sph"]["pressure_solver"] = "divergence_free";
  doc["solver"]["sph"]["pressure_solve"] = {{"density_tolerance", 2e-4}, {"max_iterations", 40}};
  const Scene s = parse_scene(doc.dump(), "scene.json", ".");
  EXPECT_EQ(s.sph.settings.pressure_solver, sph::PressureSolver::divergence_free);
  EXPECT_DOUBLE_EQ(s.sph.settings.density_tolerance, 2e-4);
  EXPECT_DOUBLE_EQ(s.sph.settings.divergence_tolerance, 1e-3);
  EXPECT_EQ(s.sph.settings.pressure_max_iterations, 40);
  // A gas law's bubbles are not held at a rest density.
  doc["bodies"][0]["bubbles"] = {{"fraction", 0.2}};
  expect_error(doc, {"scene.json: solver.sph.pressure_solver", "bodies[0]", "bubbles", "weakly_compressible"});
  doc["bodies"][0].erase("bubbles");
  doc["solver"]["sph"]["pressure_solve"]["density_tolerance"] = 0;
  expect_error(doc, {"solver.sph.pressure_solve.density_tolerance"});
  doc["solver"]["sph"]["pressure_solve"]["density_tolerance"] = 1e-3;
  doc["solver"]["sph"]["pressure_solver"] = "iisph";
  expect_error(doc, {"solver.sph.pressure_solver"});
}

// Quasi-static mass scaling: one key for both solvers, at least 1, and not
// with the divergence-free pressure (which holds the density by the true inertia).
TEST(Scene, MassScalingIsReadForBothSolversAndRefusedWithTheDivergenceFreePressure) {
  json doc = base_scene();
  EXPECT_DOUBLE_EQ(parse_scene(doc.dump(), "scene.json", ".").sph.mass_scaling.factor, 1.0);
  doc["solver"]["mass_scaling"] = 2.5;
  EXPECT_DOUBLE_EQ(parse_scene(doc.dump(), "scene.json", ".").sph.mass_scaling.factor, 2.5);
  doc["solver"]["mass_scaling"] = 0.5;
  expect_error(doc, {"scene.json: solver.mass_scaling", ">= 1"});
  doc["solver"]["mass_scaling"] = 2.5;
  doc["solver"]["sph"]["pressure_solver"] = "divergence_free";
  expect_error(doc, {"scene.json: solver.mass_scaling", "weakly compressible"});
  json mpm = mpm_scene();
  mpm["solver"]["mass_scaling"] = 4;
  EXPECT_DOUBLE_EQ(parse_scene(mpm.dump(), "scene.json", ".").mpm.mass_scaling.factor, 4.0);
}

// The oven's air pressure (or the altitude, through the standard atmosphere) sets where the
// materials' water boils, unless a material gives its own boiling point.
TEST(Scene, AltitudeOrAirPressureSetsTheBoilingPoint) {
  json d = base_scene();
  d["materials"]["water"]["moisture"] = {{"content", 0.5}};
  EXPECT_DOUBLE_EQ(parse_scene(d.dump(), "scene.json", ".").sph.materials[0].moisture.boiling_point, 100.0);
  d["environment"] = {{"altitude", 2000.0}};
  Scene s = parse_scene(d.dump(), "scene.json", ".");
  EXPECT_NEAR(s.oven.air_pressure, 79495, 3);
  EXPECT_NEAR(s.sph.materials[0].moisture.boiling_point, 93.4, 0.1);
  EXPECT_NEAR(s.sph.materials[0].moisture.air_pressure, 79495, 3);
  d["environment"] = {{"air_pressure", 84609.0}};
  EXPECT_NEAR(parse_scene(d.dump(), "scene.json", ".").sph.materials[0].moisture.boiling_point, 95.0, 0.1);
  d["materials"]["water"]["moisture"]["boiling_point"] = 98.0;
  EXPECT_DOUBLE_EQ(parse_scene(d.dump(), "scene.json", ".").sph.materials[0].moisture.boiling_point, 98.0);
  d["environment"]["altitude"] = 500.0;
  expect_error(d, {"scene.json: environment.altitude", "not both"});
  d["environment"] = {{"altitude", 12000.0}};
  expect_error(d, {"environment.altitude"});
}
