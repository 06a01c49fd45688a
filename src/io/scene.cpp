#include "io/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "core/errors.hpp"
#include "core/quantity.hpp"
#include "geometry/shapes.hpp"
#include "physics/oven.hpp"
#include "io/files.hpp"
#include "io/materials.hpp"
#include "io/scene_parts.hpp"
#include "io/schema.hpp"

namespace bakesim {

using nlohmann::json;
namespace fs = std::filesystem;
using namespace scene_parts;

namespace {

std::pair<int, int> line_column(const std::string& text, std::size_t byte) {
  int line = 1, col = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

// materials.NAME.preset: the preset's values with the material's own over
// them (io/materials.hpp), before the schema fills the defaults.
std::vector<std::string> apply_material_presets(json& doc, const std::string& file) {
  std::vector<std::string> notes;
  if (!doc.contains("materials") || !doc["materials"].is_object()) return notes;
  std::string solver = "sph";
  if (doc.contains("solver") && doc["solver"].is_object() && doc["solver"].value("type", json()).is_string())
    solver = doc["solver"]["type"].get<std::string>();
  double clock = 1;
  if (doc.contains("environment") && doc["environment"].is_object() &&
      doc["environment"].value("bake_time_scale", json()).is_number())
    clock = doc["environment"]["bake_time_scale"].get<double>();
  if (!(clock > 0)) return notes;  // the schema refuses it, naming the key
  for (auto& [name, m] : doc["materials"].items()) {
    if (!m.is_object() || !m.contains("preset") || !m["preset"].is_string() || m["preset"] == "none") continue;
    require_nesting_within(m, kMaxSceneNesting, file + ": materials." + name);  // the expansion copies it
    std::string note;
    m = expand_material_preset(m, solver, clock, file + ": materials." + name, note);
    notes.push_back(note);
  }
  return notes;
}

// materials.NAME.herschel_bulkley.form "elastoviscoplastic" reads neither the
// regularisation rate nor the material's Maxwell relaxation time (its stress
// relaxes only by the yield flow). Given in the scene, they are refused with
// their key path; this runs before the presets and the schema's defaults,
// which fill both. Those (a dough preset's relaxation time, the defaults) are
// dropped after the schema has filled them, so the resolved scene holds what
// is read and re-runs as it is.
bool elastoviscoplastic_form(const json& m) {
  return m.is_object() && m.contains("herschel_bulkley") && m["herschel_bulkley"].is_object() &&
         m["herschel_bulkley"].value("form", json()) == "elastoviscoplastic";
}

void refuse_keys_the_yield_form_does_not_read(const json& doc, const std::string& file) {
  if (!doc.contains("materials") || !doc["materials"].is_object()) return;
  for (const auto& [name, m] : doc["materials"].items()) {
    if (!elastoviscoplastic_form(m)) continue;
    const json& hb = m["herschel_bulkley"];
    const std::string path = file + ": materials." + name;
    // A base file ("extends") that gives the key is named by parse_scene; the variant removes it with null.
    if (hb.contains("regularisation_rate"))
      throw InputError(path + ".herschel_bulkley.regularisation_rate",
                       "is not read with form \"elastoviscoplastic\" (the stress is elastic below the yield stress; "
                       "only the regularised form has an apparent viscosity to cap): remove it, or write it as null "
                       "in a scene that extends the file giving it");
    if (m.contains("relaxation_time"))
      throw InputError(path + ".relaxation_time",
                       "is not read with herschel_bulkley.form \"elastoviscoplastic\" (the Maxwell stress relaxes "
                       "only by the yield flow, at the consistency K the material's viscosity gives): remove it, or "
                       "write it as null in a scene that extends the file giving it");
  }
}

void drop_filled_keys_the_yield_form_does_not_read(json& doc) {
  if (!doc.contains("materials") || !doc["materials"].is_object()) return;
  for (auto& [name, m] : doc["materials"].items())
    if (elastoviscoplastic_form(m)) {
      m.erase("relaxation_time");
      m["herschel_bulkley"].erase("regularisation_rate");
    }
}

// environment.oven: the air coefficient of a kind of oven and its walls' radiation, each where
// the scene gives none. The coefficients are the midpoints of the ranges in
// shared/spec/water-and-latent-heat.md (natural convection 10-20, forced 25-40 W/(m² K); Zhang
// et al. 2005 set up their loaf with 10); they are convective, and the walls of every kind of
// oven stand at about its temperature and radiate besides, to a food surface of emissivity
// about 0.9 (docs/physics.md, "Oven radiation").
void apply_oven_preset(json& doc) {
  if (!doc.contains("environment") || !doc["environment"].is_object()) return;
  json& env = doc["environment"];
  if (!env.contains("oven") || !env["oven"].is_string()) return;
  const std::string oven = env["oven"].get<std::string>();
  if (oven != "conventional" && oven != "deck" && oven != "fan") return;  // "none"; any other name: the schema
  if (!env.contains("heat_transfer_coefficient")) env["heat_transfer_coefficient"] = oven == "fan" ? 30.0 : 15.0;
  if (!env.contains("emissivity")) env["emissivity"] = 0.9;
}

// Duplicate keys in one object are refused with their key path (nlohmann keeps
// the last silently, so a value typed twice would quietly lose the first).
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(std::string file) : file_(std::move(file)) {}
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        next_element();
        stack_.push_back({event == json::parse_event_t::object_start, {}, -1, {}});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!stack_.empty()) stack_.pop_back();
        break;
      case json::parse_event_t::key:
        if (!stack_.empty()) {
          Level& top = stack_.back();
          top.key = parsed.get<std::string>();
          if (!top.keys.insert(top.key).second)
            throw InputError(file_, path() +
                                        ": duplicate key (each key may appear once in an object; the "
                                        "second would silently replace the first)");
        }
        break;
      case json::parse_event_t::value: next_element(); break;
    }
    return true;
  }

 private:
  struct Level {
    bool object;
    std::string key;  // objects: the current key
    long index;       // arrays: the current element
    std::set<std::string> keys;
  };
  void next_element() {
    if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
  }
  std::string path() const {
    std::string p;
    for (const Level& l : stack_) p += l.object ? (p.empty() ? "" : ".") + l.key : fmt::format("[{}]", l.index);
    return p;
  }
  std::string file_;
  std::vector<Level> stack_;
};

// Mesh files named relative to the scene file become absolute in the
// resolved scene, so the run's scene.json re-runs from its run directory (and
// a copied run resumes). Shapes nest at most 64 deep (the schema's limit).
void absolute_mesh_paths(json& shape, const fs::path& base_dir, int depth = 0) {
  if (!shape.is_object() || depth > 64) return;
  // Before the schema: "type" may be anything (found by fuzzing: a number threw from value()).
  if (shape.contains("type") && shape["type"] == "mesh" && shape.contains("file") && shape["file"].is_string()) {
    const fs::path file = shape["file"].get<std::string>();
    if (file.is_relative() && !file.empty()) shape["file"] = fs::absolute(base_dir / file).lexically_normal().string();
  }
  for (const char* nested : {"shapes", "subtract"})
    if (shape.contains(nested) && shape[nested].is_array())
      for (auto& s : shape[nested]) absolute_mesh_paths(s, base_dir, depth + 1);
  if (shape.contains("base")) absolute_mesh_paths(shape["base"], base_dir, depth + 1);
}

// Temperatures of an oven, a tray or a hob above this look typed in kelvin or
// °F (a pizza oven reaches 450 °C, so they are warnings, not errors).
constexpr double kPlausibleHotDegC = 300;
// An oven at least this hot bakes (below it, a scene may well simulate water).
constexpr double kBakingAirDegC = 100;
// Bodies larger than this look typed in millimetres.
constexpr double kPlausibleBodyMetres = 2;

// The highest temperature of a schedule, read by the one schedule parser.
double highest_temperature(const PiecewiseLinear& schedule) {
  double hottest = -273.15;
  for (const auto& [time, temperature] : schedule.points()) hottest = std::max(hottest, double(temperature));
  return hottest;
}

// From what the loader built: the oven's schedule, each collider's, each body's shape bounds (meshes included).
std::vector<std::string> plausibility_warnings(const Ctx& c, const json& doc, const SceneParts& parts) {
  std::vector<std::string> out;
  auto hot = [&](const std::string& path, const PiecewiseLinear& schedule) {
    const double t = highest_temperature(schedule);
    if (t > kPlausibleHotDegC)
      out.push_back(
          fmt::format("{} reaches {:g} degC: bakesim reads degrees Celsius ({:g} K would be {:.0f} degC, "
                      "{:g} degF {:.0f} degC)",
                      path, t, t, t - 273.15, t, (t - 32) / 1.8));
  };
  hot("environment.air_temperature", parts.world.oven.air_temperature);
  for (std::size_t i = 0; i < doc["colliders"].size(); ++i)
    if (const json& t = doc["colliders"][i]["temperature"]; t.is_number() || t.is_array()) {
      const std::string path = fmt::format("colliders[{}].temperature", i);
      hot(path, build_schedule(c, path, t));
    }
  for (std::size_t i = 0; i < parts.bodies.size(); ++i) {
    const double size = bounds(parts.bodies[i].shape).extent().maxCoeff();
    if (size > kPlausibleBodyMetres)
      out.push_back(
          fmt::format("bodies[{}].shape is about {:g} m across: bakesim reads metres ({:g} mm would be "
                      "{:g} m)",
                      i, size, size, size / 1000));
  }
  return out;
}

}  // namespace

// A scene is read in three steps: the schema validates the document and fills
// its defaults (refusing keys the chosen solver does not read); the parts both
// solvers read the same way are read once (scene_parts.cpp); the chosen
// solver's setup is built from them in its own file (scene_sph.cpp, scene_mpm.cpp).
namespace {

// "key", "key[0]", "key[0][1]" separated by dots: object keys, and array indices as "[N]".
std::vector<std::string> split_key_path(const std::string& path, const std::string& where) {
  std::vector<std::string> keys;
  std::size_t at = 0;
  while (at <= path.size()) {
    const std::size_t dot = std::min(path.find('.', at), path.size());
    std::string part = path.substr(at, dot - at);
    const std::size_t bracket = part.find('[');
    const std::string key = part.substr(0, bracket);
    if (key.empty()) throw InputError(where, "an empty key in '" + path + "'");
    keys.push_back(key);
    for (std::size_t b = bracket; b != std::string::npos; b = part.find('[', b + 1)) {
      const std::size_t close = part.find(']', b);
      const std::string digits = close == std::string::npos ? "" : part.substr(b + 1, close - b - 1);
      if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos ||
          (close + 1 < part.size() && part[close + 1] != '['))
        throw InputError(where, "a malformed array index in '" + path + "' (write bodies[0].temperature)");
      keys.push_back("[" + digits + "]");
    }
    at = dot + 1;
  }
  return keys;
}

}  // namespace

SceneOverride parse_override(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set", "expects KEY.PATH=VALUE (e.g. environment.air_temperature=200), got '" + text + "'");
  SceneOverride o;
  o.path = text.substr(0, eq);
  const std::string value = text.substr(eq + 1);
  o.keys = split_key_path(o.path, "--set");
  try {
    o.value = json::parse(value);
  } catch (const json::exception&) {
    o.value = value;  // a plain word: a string ("sph", "implicit")
  }
  require_nesting_within(o.value, kMaxSceneNesting, "--set " + o.path);  // applying it copies it
  return o;
}

namespace {

void apply_override(json& doc, const SceneOverride& o) {
  json* node = &doc;
  std::string where;
  for (std::size_t k = 0; k < o.keys.size(); ++k) {
    const std::string& key = o.keys[k];
    const bool last = k + 1 == o.keys.size();
    if (key[0] == '[') {
      const std::size_t index = std::stoul(key.substr(1, key.size() - 2));  // digits only (parse_override)
      if (!node->is_array()) throw InputError("--set " + o.path, where + " is not a list in the scene");
      if (index >= node->size())
        throw InputError("--set " + o.path, fmt::format("{} has {} entries", where, node->size()));
      node = &(*node)[index];
    } else {
      if (node->is_null()) *node = json::object();
      if (!node->is_object())
        throw InputError("--set " + o.path, (where.empty() ? "the scene" : where) + " is not an object");
      node = &(*node)[key];
    }
    where += key[0] == '[' || where.empty() ? key : "." + key;
    if (last) *node = o.value;
  }
}

json parse_document(const std::string& text, const std::string& file) {
  json doc;
  try {
    doc = json::parse(text, DuplicateKeyCheck(file), true, /*ignore_comments=*/true);
  } catch (const json::parse_error& e) {
    const auto [line, col] = line_column(text, e.byte);
    std::string msg = e.what();
    // Keep nlohmann's explanation, drop its own prefix and position.
    const auto pos = msg.find(": ", msg.find("parse error"));
    if (pos != std::string::npos) msg = msg.substr(pos + 2);
    throw InputError(fmt::format("{}:{}:{}", file, line, col), "JSON syntax error: " + msg);
  } catch (const json::exception& e) {
    // A number too large for a double (found by fuzzing: 1e999).
    throw InputError(file, std::string("JSON error: ") + e.what());
  }
  if (!doc.is_object()) throw InputError(file, "a scene must be a JSON object");
  return doc;
}

void absolute_mesh_paths_of_scene(json& doc, const fs::path& base_dir) {
  for (const char* list : {"bodies", "colliders"})
    if (doc.contains(list) && doc[list].is_array())
      for (auto& item : doc[list])
        if (item.is_object()) {
          if (item.contains("shape")) absolute_mesh_paths(item["shape"], base_dir);
          if (item.contains("bubbles") && item["bubbles"].is_object() && item["bubbles"].contains("region"))
            absolute_mesh_paths(item["bubbles"]["region"], base_dir);
        }
}

// A chain of scene files, each extending the next: deeper than this is a mistake.
constexpr int kMaxExtendsDepth = 16;

// One file of an "extends" chain as it was read, to tell which file a key came from.
struct SceneLayer {
  std::string file;
  json doc;
};

// "extends": "base.json" reads the base (relative to the extending file) and
// lays this document over it as a JSON merge patch (RFC 7386): objects merge
// key by key, any other value (a number, a list) replaces the base's, null
// removes the base's key. Mesh paths are made absolute against the file that
// names them before merging. The base's name is not inherited.
json resolve_extends(json doc, const std::string& file, const fs::path& base_dir, std::vector<SceneLayer>& layers,
                     std::vector<fs::path>& chain) {
  absolute_mesh_paths_of_scene(doc, base_dir);
  // A scene without "extends" is not copied (the schema judges its nesting later); the files of a
  // chain are kept to tell which gave a key, so they are checked before they are copied.
  if (!doc.contains("extends")) {
    if (!layers.empty()) {
      require_nesting_within(doc, kMaxSceneNesting, file);
      layers.push_back({file, doc});
    }
    return doc;
  }
  require_nesting_within(doc, kMaxSceneNesting, file);
  const json extends = doc["extends"];
  doc.erase("extends");
  layers.push_back({file, doc});
  if (!extends.is_string() || extends.get<std::string>().empty())
    throw InputError(file + ": extends", "must be the path of the scene file this one builds on (relative to " +
                                             std::string("this file), got ") + extends.dump());
  const fs::path base_file = base_dir / fs::path(extends.get<std::string>());
  std::error_code ec;
  if (!fs::exists(base_file, ec)) throw InputError(file + ": extends", "no such scene file: " + base_file.string());
  const fs::path key = fs::weakly_canonical(base_file, ec);
  std::string route;
  for (const auto& f : chain) route += f.filename().string() + " -> ";
  if (std::find(chain.begin(), chain.end(), key) != chain.end())
    throw InputError(file + ": extends", "the files extend each other in a circle: " + route + key.filename().string());
  if (static_cast<int>(chain.size()) > kMaxExtendsDepth)
    throw InputError(file + ": extends", fmt::format("more than {} files extend each other", kMaxExtendsDepth));
  chain.push_back(key);
  if (fs::is_directory(base_file, ec)) throw InputError(file + ": extends", base_file.string() + " is a directory");
  json base = parse_document(read_file(base_file, std::uintmax_t(64) << 20), base_file.string());
  const std::string parent = base_file.parent_path().string();
  base = resolve_extends(std::move(base), base_file.string(), parent.empty() ? "." : parent, layers, chain);
  base.erase("name");  // a variant is a scene of its own: its name, or its file's
  base.merge_patch(doc);
  return base;
}

// The file of an "extends" chain that gave the value at a key path: the first,
// from the extending file down, that holds the path (or a list or value on the
// way to it, which it replaces whole). Values none holds are defaults: the top file.
const std::string& file_of_key(const std::vector<SceneLayer>& layers, const std::string& path) {
  std::vector<std::string> keys;
  try {
    keys = split_key_path(path, "");
  } catch (const InputError&) {
    return layers.front().file;
  }
  for (const SceneLayer& layer : layers) {
    const json* node = &layer.doc;
    bool held = true;
    for (const std::string& k : keys) {
      if (!node->is_object()) break;  // a list or a value that replaces the base's whole
      if (k[0] == '[' || !node->contains(k)) {
        held = false;
        break;
      }
      node = &(*node)[k];
    }
    if (held) return layer.file;
  }
  return layers.front().file;
}

Scene build_scene(json doc, const std::string& file, const std::string& base_dir,
                  const std::vector<SceneOverride>& overrides, std::vector<std::string> extends) {
  for (const SceneOverride& o : overrides) apply_override(doc, o);
  absolute_mesh_paths_of_scene(doc, base_dir);
  apply_oven_preset(doc);
  refuse_keys_the_yield_form_does_not_read(doc, file);
  std::vector<std::string> preset_notes = apply_material_presets(doc, file);
  // Materials that leave their thermal properties to the schema's defaults (water's), before it fills them.
  std::vector<std::string> water_defaults;
  if (doc.contains("materials") && doc["materials"].is_object())
    for (const auto& [name, m] : doc["materials"].items()) {
      if (!m.is_object()) continue;
      std::vector<std::string> missing;
      for (const char* key : {"density", "specific_heat", "conductivity"})
        if (!m.contains(key)) missing.push_back(key);
      if (!missing.empty()) water_defaults.push_back(fmt::format("materials.{} ({})", name, fmt::join(missing, ", ")));
    }
  scene_schema().validate(doc, file);
  drop_filled_keys_the_yield_form_does_not_read(doc);

  const Ctx c{file, base_dir};
  Scene sc;
  sc.file = file;
  sc.name = doc["name"].get<std::string>();
  if (sc.name.empty()) {
    sc.name = fs::path(file).stem().string();
    doc["name"] = sc.name;
  }
  for (const unsigned char ch : sc.name)
    if (ch < 0x20 || ch == 0x7f) c.fail("name", "must not contain control characters (the name is printed)");
  sc.description = doc["description"].get<std::string>();
  sc.solver_type = doc["solver"]["type"].get<std::string>();
  if (!doc["solver"].contains(sc.solver_type))
    c.fail("solver",
           fmt::format("missing section '{0}' (required when solver.type is \"{0}\"; it needs at least '{1}')",
                       sc.solver_type, sc.solver_type == "sph" ? "spacing" : "cell_size"));
  if (doc["solver"]["min_dt"].get<double>() >= doc["solver"]["max_dt"].get<double>())
    c.fail("solver.min_dt", fmt::format("must be below solver.max_dt ({:g} s)", doc["solver"]["max_dt"].get<double>()));
  sc.end_time = doc["time"]["end"].get<double>();
  sc.fps = doc["time"]["fps"].get<double>();
  if (sc.end_time * sc.fps > 1e6) c.fail("time", "more than a million frames: lower time.fps or time.end");
  require_box(c, "domain", vec3(doc["domain"]["min"]), vec3(doc["domain"]["max"]));
  for (const auto& [name, m] : doc["materials"].items())
    if (m["raw_colour"].is_array() &&
        !(m["raw_colour"][0].get<double>() >= 0 && m["raw_colour"][0].get<double>() <= 100))
      c.fail(
          "materials." + name + ".raw_colour[0]",
          fmt::format("L* is {:g}: a lightness runs from 0 (black) to 100 (white)", m["raw_colour"][0].get<double>()));

  const SceneParts parts = read_common(c, doc, solver_friction_model(sc.solver_type));
  sc.warnings = plausibility_warnings(c, doc, parts);
  // In a bake, water's thermal properties for a dough are a forgotten key, not a choice.
  if (highest_temperature(parts.world.oven.air_temperature) >= kBakingAirDegC && parts.world.oven.bake_time_scale > 1)
    for (const auto& m : water_defaults)
      sc.warnings.push_back(m +
                            " not given: water's are used (1000 kg/m^3, 4181 J/(kg K), 0.6 W/(m K)); name a "
                            "preset (bakesim materials) or give them");
  sc.oven = parts.world.oven;
  sc.gravity = parts.world.gravity;
  // The bodies as the stats columns need them, from the chosen solver's setup
  // (only SPH holds a body at its temperature).
  try {
    if (sc.solver_type == "mpm") {
      sc.mpm = build_mpm_setup(c, doc, parts);
      for (const auto& b : sc.mpm.bodies)
        sc.bodies.push_back({b.name, false, sc.mpm.materials[b.material].moisture.boiling_point});
    } else {
      sc.sph = build_sph_setup(c, doc, parts);
      for (const auto& b : sc.sph.bodies)
        sc.bodies.push_back({b.name, b.hold_temperature, sc.sph.materials[b.material].moisture.boiling_point});
      // The elastoviscoplastic form holds a body at rest with the settings its
      // tests use (docs/physics.md, "Elastoviscoplastic form in SPH").
      for (const auto& m : sc.sph.materials) {
        if (!sph::elastoviscoplastic(m)) continue;
        const std::string key = file + ": materials." + m.name + ".herschel_bulkley.form";
        if (!sc.sph.settings.stress_viscosity)
          sc.warnings.push_back(key +
                                ": elastoviscoplastic with solver.sph.viscosity_operator laplacian: the Maxwell stress "
                                "then takes the uncorrected gradient and Eq 2.18's force, with which an elastic column "
                                "keeps sinking; set viscosity_operator to stress");
        if (sc.sph.settings.clamp_negative_pressure)
          sc.warnings.push_back(key +
                                ": elastoviscoplastic with solver.sph.negative_pressure clamp: a solid's floor layer "
                                "carries tension, and clamped it slides out from under the body; set "
                                "negative_pressure to keep");
        if (sc.sph.settings.smoothing_ratio < sph::kElastoviscoplasticSupport)
          sc.warnings.push_back(key + fmt::format(": elastoviscoplastic with solver.sph.smoothing_ratio {0:g}: with a "
                                                  "support under {1:g} spacings the particles' stresses drift apart "
                                                  "in plastic flow and a yielding body spreads further the finer it "
                                                  "is sampled (docs/validation.md, Cylinder slump); set "
                                                  "smoothing_ratio to {1:g}",
                                                  sc.sph.settings.smoothing_ratio, sph::kElastoviscoplasticSupport));
      }
      // The stress form's known defect beside sticky walls (docs/validation.md, "The stress form
      // beside sticky walls"; StressViscosity.DISABLED_*Study).
      if (sc.sph.settings.stress_viscosity)
        for (std::size_t i = 0; i < sc.sph.colliders.size(); ++i) {
          if (!sph::no_slip_wall(sc.sph.colliders[i])) continue;
          sc.warnings.push_back(fmt::format(
              "{}: solver.sph.viscosity_operator: \"stress\" beside the sticky collider '{}' (colliders[{}]): the "
              "stress form's gradient does not see a sticky wall's velocity and leaves a layer-by-layer mode beside "
              "it undamped (between sticky plates a Poiseuille flow's layers run at 0.71-1.03 of their speed, an "
              "elastoviscoplastic Bingham channel at 2.6-2.9 times its plug; docs/validation.md); for flows along "
              "sticky walls use viscosity_operator laplacian",
              file, sc.sph.colliders[i].name, i));
          break;
        }
    }
  } catch (const InputError& e) {
    // "The bodies would hold 1e11 particles" is, most often, a size typed in millimetres: say so.
    if (sc.warnings.empty()) throw;
    throw InputError(e.where(), e.detail() + " (note: " + sc.warnings.front() + ")");
  }

  for (std::size_t i = 0; i < doc["probes"].size(); ++i) {
    const json& pj = doc["probes"][i];
    ProbeSpec p{pj["name"].get<std::string>(), vec3(pj["position"]), pj["quantities"].get<std::vector<std::string>>(),
                pj["follow"].get<bool>()};
    if (!parts.world.domain.contains(p.position))
      c.fail(fmt::format("probes[{}].position", i), "lies outside the domain");
    sc.probes.push_back(std::move(p));
  }
  sc.output.particle_formats = doc["output"]["particles"].get<std::vector<std::string>>();
  sc.output.every_frames = doc["output"]["every_frames"].get<int>();
  sc.extends = std::move(extends);
  sc.notes = std::move(preset_notes);
  sc.resolved = std::move(doc);
  return sc;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file, const std::string& base_dir,
                  const std::vector<SceneOverride>& overrides) {
  std::vector<SceneLayer> layers;
  std::vector<fs::path> chain{fs::weakly_canonical(fs::path(file))};
  json doc = resolve_extends(parse_document(text, file), file, base_dir, layers, chain);
  if (layers.empty()) return build_scene(std::move(doc), file, base_dir, overrides, {});  // no "extends"
  std::vector<std::string> extends;
  for (std::size_t i = 1; i < layers.size(); ++i) extends.push_back(layers[i].file);
  try {
    return build_scene(std::move(doc), file, base_dir, overrides, extends);
  } catch (const InputError& e) {
    // An error at a key the base file gave names the base file.
    const std::string prefix = file + ": ";
    if (!e.where().starts_with(prefix)) throw;
    const std::string path = e.where().substr(prefix.size());
    const std::string& from = file_of_key(layers, path);
    if (from == file) throw;
    throw InputError(from + ": " + path, e.detail() + " (in " + file + ", which extends " + from + ")");
  }
}

Scene load_scene(const std::string& path, const std::vector<SceneOverride>& overrides) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "scene file not found");
  if (fs::is_directory(path, ec)) {
    if (fs::is_regular_file(fs::path(path) / "scene.json", ec) && fs::is_directory(fs::path(path) / "frames", ec))
      throw InputError(path, "is a run directory, not a scene file: to go on with that run, bakesim run --resume " +
                                 path + "; to run its scene again, bakesim run " +
                                 (fs::path(path) / "scene.json").string() + " --out NEW_DIR");
    throw InputError(path, "is a directory, not a scene file");
  }
  // A scene is text written by hand or by a script: 64 MiB is far beyond any real one.
  const std::string text = read_file(path, std::uintmax_t(64) << 20);
  const std::string dir = fs::path(path).parent_path().string();
  return parse_scene(text, path, dir.empty() ? "." : dir, overrides);
}

namespace {

// A coarser lattice loses more of a thin body (the cookie, 14 mm thick, holds
// 4 layers of 3 mm: 12 mm, 85% of it): where `spacing` samples a body more
// than kSamplingFillTolerance off its shape, the spacing fitting_spacing finds
// for the worst of them, if it is no coarser than `largest` and samples every
// body within the tolerance; else `spacing`.
template <class Bodies>
double fitted_preview_spacing(const Bodies& bodies, double spacing, double largest) {
  std::vector<double> volumes;  // each shape's, once (a union's comes from a fine lattice)
  for (const auto& b : bodies) volumes.push_back(shape_volume(b.shape, spacing));
  // How far the spacing samples its worst body off its shape, and which body that is.
  auto worst_at = [&](double s) {
    std::pair<double, std::size_t> worst{0, 0};
    for (std::size_t i = 0; i < bodies.size(); ++i)
      worst = std::max(worst, {std::abs(volume_estimate(bodies[i].shape, s) / volumes[i] - 1), i});
    return worst;
  };
  const auto [error, body] = worst_at(spacing);
  if (!(error > kSamplingFillTolerance)) return spacing;
  const FittingSpacing fitted = fitting_spacing(bodies[body].shape, spacing, volumes[body]);
  if (!(fitted.spacing > 0) || fitted.spacing > largest) return spacing;
  return worst_at(fitted.spacing).first <= kSamplingFillTolerance ? fitted.spacing : spacing;
}

}  // namespace

std::vector<SceneOverride> preview_overrides(const Scene& scene) {
  auto set = [](const std::string& path, json value) {
    SceneOverride o = parse_override(path + "=0");
    o.value = std::move(value);
    return o;
  };
  std::vector<SceneOverride> out;
  const json& solver = scene.resolved["solver"];
  if (scene.solver_type == "mpm") {
    // Container and cup walls must stay two cells thick (scene_mpm.cpp): they may limit the coarsening.
    const double cell = solver["mpm"]["cell_size"].get<double>();
    double factor = kPreviewCoarsening;
    for (const json& c : scene.resolved["colliders"])
      if (c["shape"].contains("wall_thickness"))
        factor = std::min(factor, c["shape"]["wall_thickness"].get<double>() / (kMinWallCells * cell));
    if (factor > 1) {
      const double per_cell = mpm::points_per_cell_axis(solver["mpm"]["particles_per_cell"].get<double>());
      const double spacing =
          fitted_preview_spacing(scene.mpm.bodies, cell * factor / per_cell, cell * factor / per_cell);
      out.push_back(set("solver.mpm.cell_size", spacing * per_cell));
    }
  } else {
    const double spacing = solver["sph"]["spacing"].get<double>() * kPreviewCoarsening;
    out.push_back(set("solver.sph.spacing", fitted_preview_spacing(scene.sph.bodies, spacing, spacing)));
  }
  const double fps = std::min(scene.fps, kPreviewFrames / scene.end_time);
  if (fps < scene.fps) out.push_back(set("time.fps", fps));
  out.push_back(set("name", scene.name + "-preview"));
  return out;
}

Scene load_scene(const std::string& path, std::vector<SceneOverride> overrides, bool preview) {
  Scene scene = load_scene(path, overrides);
  if (!preview) return scene;
  for (SceneOverride& o : preview_overrides(scene)) overrides.push_back(std::move(o));
  return load_scene(path, overrides);
}

void set_end_time(Scene& scene, double end_time) {
  if (!(end_time <= 1e6)) throw InputError("--end-time", fmt::format("must be <= 1e6 s, got {:g}", end_time));
  if (end_time * scene.fps > 1e6)
    throw InputError("--end-time",
                     fmt::format("{:g} s at {:g} fps is more than a million frames", end_time, scene.fps));
  scene.end_time = end_time;
  scene.resolved["time"]["end"] = end_time;
}

std::unique_ptr<Solver> make_solver(const Scene& scene) {
  std::unique_ptr<Solver> solver;
  if (scene.solver_type == "mpm")
    solver = std::make_unique<mpm::MpmSolver>(scene.mpm);
  else
    solver = std::make_unique<sph::SphSolver>(scene.sph);
  // Probe quantities are the solver's particle attributes: a name it does not
  // have is an error at the probe's key path, before the run starts.
  for (std::size_t i = 0; i < scene.probes.size(); ++i)
    for (std::size_t k = 0; k < scene.probes[i].quantities.size(); ++k)
      ParticleQuantity::resolve(solver->particles(), scene.probes[i].quantities[k],
                                fmt::format("{}: probes[{}].quantities[{}]", scene.file, i, k));
  return solver;
}

std::optional<NamedAirPressure> named_air_pressure(const nlohmann::json& environment) {
  if (environment.contains("altitude") && environment["altitude"].is_number()) {
    const double altitude = environment["altitude"].get<double>();
    return NamedAirPressure{standard_atmosphere_pressure(altitude), altitude};
  }
  if (environment.contains("air_pressure") && environment["air_pressure"].is_number())
    return NamedAirPressure{environment["air_pressure"].get<double>(), std::nullopt};
  return std::nullopt;
}

std::string describe(const Scene& scene, Solver& solver) {
  std::string out;
  out += fmt::format("scene      {} ({})\n", scene.name, scene.file);
  if (!scene.description.empty()) out += fmt::format("           {}\n", scene.description);
  for (const auto& base : scene.extends) out += fmt::format("extends    {}\n", base);
  for (const auto& note : scene.notes) out += fmt::format("material   {}\n", note);
  out += fmt::format("solver     {}\n", scene.solver_type);
  const int frames = static_cast<int>(std::ceil(scene.end_time * scene.fps - 1e-9));
  out += fmt::format("time       {} s at {} fps: {} frames\n", scene.end_time, scene.fps, frames);
  if (scene.oven.bake_time_scale != 1.0)
    out += fmt::format("bake clock {} bake seconds per simulated second: {} s simulate {:.1f} min of baking\n",
                       scene.oven.bake_time_scale, scene.end_time, scene.oven.bake_time(scene.end_time) / 60.0);
  // The oven the surfaces exchange heat with: the air (a number or a schedule), its coefficient, wall radiation.
  const auto& air = scene.oven.air_temperature.points();
  Real air_lo = air.empty() ? 20.0 : air.front().second, air_hi = air_lo;
  for (const auto& point : air) air_lo = std::min(air_lo, point.second), air_hi = std::max(air_hi, point.second);
  const std::string air_text =
      air_lo == air_hi ? fmt::format("{:g} degC", air_lo)
                       : fmt::format("{:g} to {:g} degC (a schedule of {} points)", air_lo, air_hi, air.size());
  out += fmt::format(
      "oven       air {}, h {:g} W/(m^2 K){}\n", air_text, scene.oven.heat_transfer_coefficient,
      scene.oven.emissivity > 0
          ? fmt::format(", wall radiation at emissivity {:g} (walls at the air's temperature)", scene.oven.emissivity)
          : std::string(", no wall radiation"));
  if (scene.oven.air_pressure != kAtmosphere)
    out += fmt::format("           air pressure {:.1f} kPa: free water boils at {:.1f} degC\n",
                       scene.oven.air_pressure / 1000, scene.oven.boiling_point());
  out += solver.summary();
  out += fmt::format("probes     {}\n", scene.probes.size());
  const Real dt = solver.max_stable_dt();
  out += fmt::format("time step  {:.3e} s at t = 0 ({}), about {:.0f} steps for the whole run at this rate\n", dt,
                     solver.active_dt_bound(), scene.end_time / dt);
  return out;
}

}  // namespace bakesim
