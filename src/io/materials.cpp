#include "io/materials.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <optional>

#include "core/errors.hpp"
#include "io/schema.hpp"
#include "physics/food_properties.hpp"

namespace bakesim {

extern const std::pair<const char*, const char*> kMaterialPresetFiles[];  // generated from materials/*.json
extern const std::size_t kMaterialPresetCount;

using nlohmann::json;

namespace {

// Enough digits for a material property, few enough to read in scene.json.
double significant(double v, int digits = 4) {
  if (v == 0 || !std::isfinite(v)) return v;
  const double scale = std::pow(10.0, digits - 1 - int(std::floor(std::log10(std::abs(v)))));
  return std::round(v * scale) / scale;
}

const char* kComponentKeys[kFoodComponents] = {"water", "protein", "fat", "carbohydrate", "fibre", "ash"};

// A preset's thermal properties from its composition at 20 °C, rounded as the resolved scene shows them.
ThermalProperties preset_thermal(const FoodComposition& food) {
  const ThermalProperties t = food_properties(food, 20.0);
  return {significant(t.density), significant(t.specific_heat), significant(t.conductivity, 3)};
}

// Divides a number or a piecewise-linear curve's values by `clock`.
void divide_by_clock(json& value, double clock, const std::string& where) {
  if (value.is_number()) {
    value = value.get<double>() / clock;
    return;
  }
  if (value.is_object() && value.contains("curve") && value["curve"] == "piecewise_linear" &&
      value.contains("points") && value["points"].is_array()) {
    for (auto& p : value["points"])
      if (p.is_array() && p.size() == 2 && p[1].is_number()) p[1] = p[1].get<double>() / clock;
    return;
  }
  throw InputError(where,
                   "is a physical time (Pa s) that bakesim divides by the bake clock: give a number or "
                   "{\"curve\": \"piecewise_linear\", \"points\": [...]}");
}

json* at_path(json& doc, const std::string& dotted) {
  json* node = &doc;
  std::size_t at = 0;
  while (at <= dotted.size()) {
    const std::size_t dot = std::min(dotted.find('.', at), dotted.size());
    const std::string key = dotted.substr(at, dot - at);
    if (!node->is_object() || !node->contains(key)) return nullptr;
    node = &(*node)[key];
    at = dot + 1;
  }
  return node;
}

}  // namespace

std::vector<std::string> material_preset_names() {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < kMaterialPresetCount; ++i) names.push_back(kMaterialPresetFiles[i].first);
  return names;
}

FoodComposition preset_composition(const json& c) {
  FoodComposition f;
  for (int i = 0; i < kFoodComponents; ++i) f.mass_fraction[i] = c.value(kComponentKeys[i], 0.0);
  f.porosity = c.value("porosity", 0.0);
  return f;
}

std::vector<std::string> preset_solvers(const json& preset) {
  std::vector<std::string> solvers;
  for (const char* s : {"mpm", "sph"})
    if (preset.contains(s)) solvers.push_back(s);
  return solvers;
}

json material_preset(const std::string& name, const std::string& where) {
  for (std::size_t i = 0; i < kMaterialPresetCount; ++i)
    if (name == kMaterialPresetFiles[i].first) return json::parse(kMaterialPresetFiles[i].second);
  const auto names = material_preset_names();
  const std::string near = closest_match(name, names);
  throw InputError(where, fmt::format("unknown preset '{}'{}; the presets are {} (docs/materials.md)", name,
                                      near.empty() ? "" : "; did you mean '" + near + "'?", fmt::join(names, ", ")));
}

json expand_material_preset(const json& material, const std::string& solver, double clock, const std::string& path,
                            std::string& note) {
  const std::string name = material["preset"].get<std::string>();
  const json preset = material_preset(name, path + ".preset");
  json out = preset.value("common", json::object());
  json user = material;
  user.erase("preset");
  // A solver section may give the porosity its continuum holds (a preset-file key, not a scene key): an SPH
  // dough carries most of its gas as bubble particles, so its particles are the dough between them.
  std::optional<double> section_porosity;
  if (preset.contains(solver)) {
    json section = preset[solver];
    if (section.contains("porosity")) {
      section_porosity = section["porosity"].get<double>();
      section.erase("porosity");
    }
    out.merge_patch(section);
  } else {
    const std::string other = solver == "mpm" ? "sph" : "mpm";
    const bool has_rheology = solver == "mpm" ? user.contains("youngs_modulus") : user.contains("viscosity");
    if (!has_rheology)
      throw InputError(path + ".preset",
                       fmt::format("'{}' has no {} rheology{}: give the material's {} beside the preset (its thermal "
                                   "properties come from the preset), or choose another preset",
                                   name, solver == "mpm" ? "MPM" : "SPH",
                                   preset.contains(other)
                                       ? " (it is for the " + std::string(other == "mpm" ? "MPM" : "SPH") + " solver)"
                                       : "",
                                   solver == "mpm" ? "youngs_modulus (and plasticity)" : "viscosity (and elasticity)"));
  }
  std::optional<FoodComposition> food;
  if (preset.contains("composition")) {
    food = preset_composition(preset["composition"]);
    if (section_porosity) food->porosity = *section_porosity;
    const ThermalProperties t = preset_thermal(*food);
    if (!out.contains("density")) out["density"] = t.density;
    if (!out.contains("specific_heat")) out["specific_heat"] = t.specific_heat;
    if (!out.contains("conductivity")) out["conductivity"] = t.conductivity;
  }
  out.merge_patch(user);
  // The moisture model's water and pores from the composition: X₀ = x_water / (1 − x_water) (dry basis) and the
  // gas fraction φ_g = the porosity, unless the section or the scene gives them.
  if (food && out.contains("moisture") && out["moisture"].is_object()) {
    json& moisture = out["moisture"];
    const double water = (*food)[FoodComponent::water];
    if (!moisture.contains("content") && water < 1) moisture["content"] = significant(water / (1 - water));
    if (!moisture.contains("gas_fraction")) moisture["gas_fraction"] = significant(food->porosity);
  }
  // The water the composition holds, as the MPM mixture carries it: mass = saturation ρ_w V. Where the moisture
  // model carries it (the material has `moisture`), the preset's saturation, surface evaporation rate and
  // saturation diffusivity are left out (the scene check refuses them beside a moisture content; the scene never
  // wrote them), so the water follows the moisture law as in SPH with the same preset; the scene's own are kept,
  // so that the check names them.
  const bool user_water = user.contains("water") && user["water"].is_object();
  const bool moisture_carries_water = out.contains("moisture") && out["moisture"].is_object() &&
                                      out["moisture"].contains("content") && out["moisture"]["content"].is_number() &&
                                      out["moisture"]["content"].get<double>() > 0;
  if (solver == "mpm" && out.contains("water") && out["water"].is_object()) {
    json& water = out["water"];
    if (moisture_carries_water) {
      for (const char* key : {"saturation", "evaporation_rate", "diffusivity"})
        if (!(user_water && user["water"].contains(key))) water.erase(key);
    } else if (food && !(user_water && user["water"].contains("saturation")) && out["density"].is_number()) {
      water["saturation"] = significant((*food)[FoodComponent::water] * out["density"].get<double>() / 1000.0);
    }
  }
  std::vector<std::string> divided;
  for (const auto& p : preset.value("physical_times", json::array())) {
    const std::string key = p.get<std::string>();
    if (json* v = at_path(out, key)) {
      divide_by_clock(*v, clock, path + "." + key);
      divided.push_back(key);
    }
  }
  // The resolved scene must re-run as it is: a preset whose values were divided is not named again.
  out["preset"] = divided.empty() ? json(name) : json("none");
  note = fmt::format("{}: preset {}", path, name);
  if (food)
    note += fmt::format(" (density {:g} kg/m^3, c_p {:g} J/(kg K), k {:g} W/(m K) from its composition)",
                        out["density"].get<double>(), out["specific_heat"].get<double>(),
                        out["conductivity"].get<double>());
  if (!divided.empty()) note += fmt::format("; {} divided by the bake clock {:g}", fmt::join(divided, ", "), clock);
  return out;
}

std::string materials_markdown() {
  std::string md =
      "# Material presets\n\n"
      "Generated by `bakesim materials --markdown` from `materials/*.json` (compiled into bakesim). A scene uses "
      "one with\n\n```json\n\"materials\": {\"dough\": {\"preset\": \"cookie-dough\", \"set_temperature\": "
      "80}}\n```\n\n"
      "Keys beside `preset` override the preset's (objects merge key by key, as `extends`). What a preset gives:\n\n"
      "* **Thermal properties from the composition**: density, specific heat and conductivity at 20 °C from the mass "
      "fractions of water, protein, fat, carbohydrate, fibre and ash and the porosity (the volume share of air), by "
      "Choi & Okos (1986) (`src/physics/food_properties.hpp`; 1/ρ = Σ xᵢ/ρᵢ times 1 − ε, c = Σ xᵢcᵢ, k = Σ vᵢkᵢ "
      "with air in parallel). A scene's own density, specific_heat or conductivity wins.\n"
      "* **Water**: MPM `water.saturation` so the particles carry the composition's water: saturation = "
      "x_water ρ / ρ_w. A material with `moisture` (from its section or the scene, either solver) gets the "
      "composition's water as `moisture.content` X₀ = x_water / (1 − x_water) (dry basis) and its porosity as "
      "`moisture.gas_fraction`, where the section or the scene gives none; its water is then the moisture model's, "
      "and MPM gets none of the section's `water.saturation`, `evaporation_rate` and `diffusivity` "
      "(the moisture law moves that water, as in SPH).\n"
      "* **Porosity per solver**: a solver section may give the porosity its particles hold (`\"porosity\"`, a "
      "preset-file key): the SPH breads' particles are the dough between the gas cells that a scene gives as "
      "bubble particles, so their section says 0.1 and their density, c_p, k and gas fraction follow from it.\n"
      "* **Mechanics** per solver (`mpm`, `sph`); a preset without a section for the scene's solver still gives "
      "its thermal properties when the scene gives the rheology.\n"
      "* **Physical viscosities.** The bake clock (`environment.bake_time_scale`) runs heat S times faster than "
      "the mechanics, so a flow that takes t seconds of bake must take t/S of mechanics: a viscosity η acts as "
      "η/S. Scenes without presets divide by hand (docs/scenes.md); in a preset, the keys listed as "
      "`physical_times` are physical (Pa·s) and bakesim divides them by the scene's clock — the preset's values "
      "and the scene's own values for those keys alike. The resolved scene holds the divided values and "
      "`\"preset\": \"none\"`, so it re-runs as it is.\n\n"
      "The mechanical values come from bakesim's calibrated scenes (each source says which, and where a "
      "measured value differs); compositions from USDA FoodData Central (SR Legacy) by the recipe given. The "
      "literature ranges a source quotes (wheat-dough viscosity, molten chocolate, apple porosity) and the "
      "USDA values were written from the cited works without re-checking them against the texts here; check "
      "them before relying on one.\n\n";
  md +=
      "| preset | solvers | density kg/m³ | c_p J/(kg K) | k W/(m K) | water % | porosity | set °C "
      "|\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& name : material_preset_names()) {
    const json p = material_preset(name, "materials");
    const std::vector<std::string> solvers = preset_solvers(p);
    const json common = p.value("common", json::object());
    double rho = common.value("density", NAN), c = common.value("specific_heat", NAN),
           k = common.value("conductivity", NAN), water = NAN, porosity = NAN;
    if (p.contains("composition")) {
      const FoodComposition f = preset_composition(p["composition"]);
      const ThermalProperties t = preset_thermal(f);
      rho = t.density, c = t.specific_heat, k = t.conductivity;
      water = 100 * f[FoodComponent::water], porosity = f.porosity;
    }
    auto num = [](double v, const char* f) {
      return std::isfinite(v) ? fmt::format(fmt::runtime(f), v) : std::string("–");
    };
    md += fmt::format(
        "| `{}` | {} | {} | {} | {} | {} | {} | {} |\n", name, fmt::join(solvers, ", "), num(rho, "{:.0f}"),
        num(c, "{:.0f}"), num(k, "{:.3g}"), num(water, "{:.1f}"), num(porosity, "{:.2f}"),
        common.contains("set_temperature") ? fmt::format("{:g}", common["set_temperature"].get<double>()) : "–");
  }
  for (const auto& name : material_preset_names()) {
    const json p = material_preset(name, "materials");
    md += fmt::format("\n## `{}`\n\n{}\n\n", name, p.value("description", ""));
    if (p.contains("recipe")) md += fmt::format("Recipe: {}.\n\n", p["recipe"].get<std::string>());
    if (p.contains("composition")) {
      md += "Composition (mass fractions):";
      for (const auto& [k, v] : p["composition"].items()) md += fmt::format(" {} {:g};", k, v.get<double>());
      md.back() = '.';
      md += "\n\n";
    }
    for (const char* section : {"common", "mpm", "sph"})
      if (p.contains(section)) md += fmt::format("`{}`: `{}`\n\n", section, p[section].dump());
    if (!p.value("physical_times", json::array()).empty())
      md += fmt::format("Divided by the bake clock: {}.\n\n",
                        fmt::join(p["physical_times"].get<std::vector<std::string>>(), ", "));
    md += "Sources:\n\n";
    for (const auto& [k, v] : p["sources"].items()) md += fmt::format("* {}: {}\n", k, v.get<std::string>());
  }
  return md;
}

}  // namespace bakesim
