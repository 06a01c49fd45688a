#pragma once
// Scenes of a chosen size for benchmarks and tests (JSON text in the scene
// format): used by `bakesim bench`, the Google benchmarks and the tests.
#include <string>

namespace bakesim {

// The dam break of scenes/dam-break.json with a spacing chosen for about
// `particles` particles and the given neighbour search and Verlet skin
// (fraction of h); used by the benchmark and the tests.
std::string dam_break_scene_json(long particles, const std::string& search, double skin);

// An MPM cube of about `particles` points (8 per cell) dropped onto a floor:
// model "elastic" (Hencky, E = 100 kPa) or "viscoplastic" (von Mises dough,
// yield 200 Pa, η 10 Pa·s, which slumps), or "cam_clay" (the same with porosity).
std::string mpm_cube_scene_json(long particles, const std::string& model);

}  // namespace bakesim
