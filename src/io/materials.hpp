#pragma once
// Material presets ("recipes"): materials/*.json, compiled into the library.
// A scene names one with `"materials": {"NAME": {"preset": "cookie-dough", ...}}`;
// the keys it gives beside the preset override the preset's (a JSON merge
// patch). A preset file holds:
//   composition     mass fractions of water, protein, fat, carbohydrate, fibre,
//                   ash and the porosity: density, specific heat and
//                   conductivity follow from it (physics/food_properties.hpp),
//                   for MPM the water's saturation (water mass / ρ_w volume),
//                   and for a section with `moisture` its content (dry basis)
//                   and gas fraction (the porosity)
//   common          keys for both solvers (e.g. set_temperature)
//   mpm, sph        each solver's keys (a preset without one is not for that
//                   solver); `porosity` there replaces the composition's for
//                   that solver (SPH breads: their gas is bubble particles)
//   physical_times  key paths whose values are physical (viscosities in Pa s):
//                   bakesim divides them by the scene's bake clock, as scenes
//                   without presets must do by hand (docs/materials.md)
//   sources         where every value comes from
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "physics/food_properties.hpp"

namespace bakesim {

std::vector<std::string> material_preset_names();
// The preset file, parsed; InputError(where, ...) naming the presets when there is none of that name.
nlohmann::json material_preset(const std::string& name, const std::string& where);

// A preset's "composition" object as mass fractions and porosity (absent components are 0).
FoodComposition preset_composition(const nlohmann::json& composition);

// The solvers a preset has mechanics for ("mpm", "sph").
std::vector<std::string> preset_solvers(const nlohmann::json& preset);

// materials.NAME as `solver` reads it: the preset's values with the
// material's own laid over them, the physical times divided by the bake clock.
// `path` is "FILE: materials.NAME" for messages; `note` says what was done (for the log).
nlohmann::json expand_material_preset(const nlohmann::json& material, const std::string& solver, double bake_time_scale,
                                      const std::string& path, std::string& note);

// docs/materials.md: every preset with its values and sources (`bakesim materials --markdown`).
std::string materials_markdown();

}  // namespace bakesim
