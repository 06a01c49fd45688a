#include "io/bench_scenes.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"

namespace bakesim {

std::string dam_break_scene_json(long particles, const std::string& search, double skin) {
  // Column a × 2a × depth, depth = a/2 (thin 3D slab of the 2D experiment).
  const double a = 0.146;
  const double depth = 0.5 * a;
  const double volume = a * 2 * a * depth;
  const double spacing = std::cbrt(volume / double(particles));
  return fmt::format(R"({{
  "name": "dam-break-bench",
  "solver": {{"type": "sph", "sph": {{"spacing": {spacing}, "neighbour_search": "{search}", "neighbour_skin": {skin}}}}},
  "time": {{"end": 1.0, "fps": 1}},
  "domain": {{"min": [0, 0, 0], "max": [{lx}, {ly}, {depth}]}},
  "materials": {{"water": {{"density": 1000, "viscosity": 0.001, "xsph": 0.1}}}},
  "bodies": [{{"name": "column", "material": "water",
              "shape": {{"type": "box", "min": [0, 0, 0], "max": [{a}, {h}, {depth}]}}}}]
}})",
                     fmt::arg("spacing", spacing), fmt::arg("search", search), fmt::arg("skin", skin),
                     fmt::arg("lx", 4 * a), fmt::arg("ly", 3 * a), fmt::arg("depth", depth), fmt::arg("a", a),
                     fmt::arg("h", 2 * a));
}

std::string mpm_cube_scene_json(long particles, const std::string& model) {
  const double side = 0.2;
  const double cell = side / std::cbrt(double(particles) / 8.0);
  std::string material;
  if (model == "elastic")
    material = R"("density": 1000, "youngs_modulus": 1e5, "poisson_ratio": 0.3)";
  else if (model == "viscoplastic")
    material =
        R"("density": 1000, "youngs_modulus": 1e5, "poisson_ratio": 0.3, "plasticity": {"model": "von_mises", "yield_stress": 200, "viscosity": 10})";
  else if (model == "full")
    // The thermomechanical dough of the bread scenes: heat, water, gas, temperature-dependent Cam-clay.
    material =
        R"("density": 500, "youngs_modulus": 1e5, "poisson_ratio": 0.3, "specific_heat": 2800, "conductivity": 0.4, "set_temperature": 90,
      "plasticity": {"model": "cam_clay", "initial_porosity": 0.2,
                     "yield_stress": {"curve": "piecewise_linear", "points": [[5, 900], [25, 600], [40, 300], [90, 4000]]},
                     "viscosity": {"curve": "piecewise_linear", "points": [[5, 5000], [25, 2000], [40, 1000]]}},
      "water": {"saturation": 0.4, "diffusivity": 2e-8, "evaporation_rate": 1e-3, "stiffness": 2e3},
      "leavening": {"rate": 2e-6})";
  else
    throw InputError("bench --model", "unknown MPM benchmark model '" + model + "' (elastic, viscoplastic, full)");
  const std::string environment =
      model == "full"
          ? R"("environment": {"air_temperature": 200, "heat_transfer_coefficient": 25, "bake_time_scale": 600},)"
          : "";
  // The cube moves down at 1 m/s onto the floor: the timed steps squash it.
  return fmt::format(
      R"({{
  "name": "mpm-cube-bench",
  "solver": {{"type": "mpm", "mpm": {{"cell_size": {cell}, "particles_per_cell": 8}}}},
  "time": {{"end": 1.0, "fps": 1}},{environment}
  "domain": {{"min": [-0.2, 0, -0.2], "max": [0.2, 0.4, 0.2]}},
  "materials": {{"dough": {{{material}}}}},
  "bodies": [{{"name": "cube", "material": "dough", "velocity": [0, -1, 0],
              "shape": {{"type": "box", "min": [-0.1, 0.03, -0.1], "max": [0.1, 0.23, 0.1]}}}}],
  "colliders": [{{"name": "floor", "shape": {{"type": "plane", "point": [0, 0.03, 0], "normal": [0, 1, 0]}}, "contact": "separate", "friction": 0.3{floor_heat}}}]
}})",
      fmt::arg("cell", cell), fmt::arg("material", material), fmt::arg("environment", environment),
      fmt::arg("floor_heat", model == "full" ? R"(, "temperature": 200, "heat_transfer_coefficient": 100)" : ""));
}

}  // namespace bakesim
