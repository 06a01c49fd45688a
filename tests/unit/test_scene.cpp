// Scene loading: every kind of bad input is answered with its location and
// what is allowed; good input is resolved with every default filled in.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/errors.hpp"
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
  EXPECT_DOUBLE_EQ(s.air_temperature(30), 100.0);
  EXPECT_DOUBLE_EQ(s.air_temperature(600), 180.0);
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
    "materials": {"dough": {"density": 500, "plasticity": {"model": "cam_clay", "initial_porosity": 0.2,
                  "yield_stress": {"curve": "piecewise_linear", "points": [[20, 300], [90, 3000]]}, "set_temperature": 90},
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
  unset["materials"]["dough"]["plasticity"].erase("set_temperature");
  expect_error(unset, {"materials.dough.plasticity.set_softening", "set_temperature"});
  json ramp = d;
  ramp["materials"]["dough"]["plasticity"]["brittle_water_loss"] = 0;
  expect_error(ramp, {"materials.dough.plasticity.brittle_water_loss"});
}
