#pragma once
// Scene loading, the parts both solvers read the same way (internal to io/):
// error context, vectors, shapes, collider geometry and contact, motion,
// curves and schedules, the oven, and the common frame of a scene (material
// names, bodies, domain, gravity). io/scene.cpp reads the document once into
// SceneParts; io/scene_sph.cpp and io/scene_mpm.cpp build each solver's setup.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "core/errors.hpp"
#include "geometry/colliders.hpp"
#include "geometry/shapes.hpp"
#include "mpm/setup.hpp"
#include "physics/curves.hpp"
#include "physics/oven.hpp"
#include "sph/setup.hpp"

namespace bakesim::scene_parts {

using nlohmann::json;

inline Vec3 vec3(const json& j) { return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>()); }

// Everything needed to report an error at a key path of this scene file.
struct Ctx {
  std::string file;
  std::string base_dir;
  [[noreturn]] void fail(const std::string& path, const std::string& msg) const {
    throw InputError(file + ": " + path, msg);
  }
};

void require_box(const Ctx& c, const std::string& path, const Vec3& lo, const Vec3& hi);
Vec3 unit_vector(const Ctx& c, const std::string& path, const json& j);
Shape build_shape(const Ctx& c, const std::string& path, const json& s);
// Mesh colliders index their triangles at `cell`.
ColliderGeometry build_collider_geometry(const Ctx& c, const std::string& path, const json& s, Real cell);
RigidMotion build_motion(const Ctx& c, const std::string& path, const json& m);
// Names (of the scene, bodies, colliders, probes, materials) hold no commas, quotes or control characters.
void check_name_characters(const Ctx& c, const std::string& path, const std::string& name);
void check_unique_names(const Ctx& c, const json& list, const std::string& key);
TemperatureCurve build_curve(const Ctx& c, const std::string& path, const json& j);
PiecewiseLinear build_schedule(const Ctx& c, const std::string& path, const json& j);
Oven build_oven(const Ctx& c, const json& environment);
// friction_model "auto" resolves to the solver's own (SPH velocity share, MPM Coulomb).
FrictionModel friction_model(const json& j, FrictionModel solver_default);
// The collider at colliders[i]: name, geometry, contact law, motion, temperature.
// MPM container and cup walls are at least this many cells thick (thinner ones let material sink in).
inline constexpr double kMinWallCells = 2;

// "temperature": "oven" gives the collider the oven air's schedule (a tray or tin preheated with the oven).
Collider build_collider(const Ctx& c, const json& cj, std::size_t i, Real cell, FrictionModel solver_default,
                        const Oven& oven);
// materials.NAME.moisture (water, vapour and latent heat; physics/water.hpp).
PoreWater build_pore_water(const Ctx& c, const std::string& path, const json& material, const Oven& oven);
// materials.NAME.set_temperature (null: never).
IrreversibleSetting build_setting(const json& material);

// What both solvers read the same way.
struct SceneParts {
  std::vector<std::string> material_names;  // name order (JSON objects iterate sorted)
  std::vector<BodyBase> bodies;
  World world;  // domain and its walls, gravity, oven; each solver adds its colliders
};
// `solver_friction`: what domain.friction_model "auto" means for the chosen solver.
SceneParts read_common(const Ctx& c, const json& doc, FrictionModel solver_friction);

// The friction model "auto" stands for, per solver (velocity share: thesis
// Eq 3.33; Coulomb: the MPM paper).
inline FrictionModel solver_friction_model(const std::string& solver_type) {
  return solver_type == "mpm" ? FrictionModel::coulomb : FrictionModel::velocity_share;
}

// Refuses a scene whose particles and grid nodes would not fit in this
// machine's memory, before anything is allocated, with an estimate of what it
// needs (`what`: "particles at spacing 1e-05 m", ...).
void require_memory(const Ctx& c, const std::string& path, double bytes, const std::string& what);
// Lattice points a body's shape holds at `spacing` (from its bounding box: an upper bound).
double lattice_points(const Shape& shape, Real spacing);

// Each solver's setup, in its own file.
sph::Setup build_sph_setup(const Ctx& c, json& doc, const SceneParts& parts);
mpm::Setup build_mpm_setup(const Ctx& c, const json& doc, const SceneParts& parts);

}  // namespace bakesim::scene_parts
