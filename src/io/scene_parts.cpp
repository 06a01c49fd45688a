#include "io/scene_parts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "core/memory.hpp"
#include "geometry/mesh_io.hpp"
#include "io/scene.hpp"
#include "io/schema.hpp"

namespace bakesim::scene_parts {

namespace fs = std::filesystem;

namespace {

TriangleMesh load_transformed_mesh(const Ctx& c, const std::string& path, const json& s) {
  fs::path file = s["file"].get<std::string>();
  if (file.is_relative()) file = fs::path(c.base_dir) / file;
  TriangleMesh mesh;
  try {
    mesh = load_mesh(file.lexically_normal().string());
  } catch (const InputError& e) {
    c.fail(path + ".file", e.what());
  }
  mesh.apply(s["scale"].get<double>(), vec3(s["rotation_deg"]), vec3(s["translation"]));
  return mesh;
}

BrowningKinetics build_browning(const json& b) {
  return {b["max_colour_difference"].get<double>(), b["rate_constant"].get<double>(),
          b["activation_energy"].get<double>()};
}

}  // namespace

void require_box(const Ctx& c, const std::string& path, const Vec3& lo, const Vec3& hi) {
  for (int k = 0; k < 3; ++k)
    if (!(lo[k] < hi[k]))
      c.fail(path,
             fmt::format("min must be below max on every axis (axis {}: min {} >= max {})", "xyz"[k], lo[k], hi[k]));
}

Vec3 unit_vector(const Ctx& c, const std::string& path, const json& j) {
  const Vec3 v = vec3(j);
  const Real n = v.norm();
  if (!(n > 1e-12)) c.fail(path, "must be a non-zero vector");
  return v / n;
}

Shape build_shape(const Ctx& c, const std::string& path, const json& s) {
  const std::string type = s["type"].get<std::string>();
  if (type == "box") {
    require_box(c, path, vec3(s["min"]), vec3(s["max"]));
    return BoxShape{vec3(s["min"]), vec3(s["max"])};
  }
  if (type == "sphere") return SphereShape{vec3(s["center"]), s["radius"].get<double>()};
  if (type == "cylinder")
    return CylinderShape{vec3(s["center"]), unit_vector(c, path + ".axis", s["axis"]), s["radius"].get<double>(),
                         s["height"].get<double>()};
  if (type == "mesh") {
    TriangleMesh mesh = load_transformed_mesh(c, path, s);
    if (mesh.signed_volume() < 0) mesh.flip_orientation();
    return std::make_shared<const MeshShape>(std::move(mesh));
  }
  if (type == "union") {
    auto u = std::make_shared<ShapeUnion>();
    for (std::size_t i = 0; i < s["shapes"].size(); ++i)
      u->parts.push_back(build_shape(c, fmt::format("{}.shapes[{}]", path, i), s["shapes"][i]));
    return std::shared_ptr<const ShapeUnion>(u);
  }
  auto d = std::make_shared<ShapeDifference>();
  d->base = build_shape(c, path + ".base", s["base"]);
  for (std::size_t i = 0; i < s["subtract"].size(); ++i)
    d->subtract.push_back(build_shape(c, fmt::format("{}.subtract[{}]", path, i), s["subtract"][i]));
  return std::shared_ptr<const ShapeDifference>(d);
}

ColliderGeometry build_collider_geometry(const Ctx& c, const std::string& path, const json& s, Real cell) {
  const std::string type = s["type"].get<std::string>();
  if (type == "plane") return PlaneCollider{vec3(s["point"]), unit_vector(c, path + ".normal", s["normal"])};
  if (type == "box") {
    require_box(c, path, vec3(s["min"]), vec3(s["max"]));
    return BoxCollider{{vec3(s["min"]), vec3(s["max"])}};
  }
  if (type == "container") {
    require_box(c, path, vec3(s["min"]), vec3(s["max"]));
    return ContainerCollider{{vec3(s["min"]), vec3(s["max"])}, s["wall_thickness"].get<double>()};
  }
  if (type == "cylinder")
    return CylinderCollider{vec3(s["center"]), unit_vector(c, path + ".axis", s["axis"]), s["radius"].get<double>(),
                            s["height"].get<double>()};
  if (type == "cup") {
    const Real radius = s["radius"].get<double>(), tube = s["tube_radius"].get<double>();
    if (tube >= radius) c.fail(path + ".tube_radius", "must be smaller than the radius");
    return CupCollider{vec3(s["base"]),           unit_vector(c, path + ".axis", s["axis"]), radius,
                       s["height"].get<double>(), s["wall_thickness"].get<double>(),         tube};
  }
  return MeshCollider::build(load_transformed_mesh(c, path, s), cell);
}

RigidMotion build_motion(const Ctx& c, const std::string& path, const json& m) {
  std::vector<RigidKeyframe> keys;
  const json& kj = m["keyframes"];
  for (std::size_t i = 0; i < kj.size(); ++i) {
    RigidKeyframe k;
    k.time = kj[i]["time"].get<double>();
    if (!keys.empty() && !(k.time > keys.back().time))
      c.fail(fmt::format("{}.keyframes[{}].time", path, i), "keyframe times must increase strictly");
    k.translation = vec3(kj[i]["translation"]);
    k.rotation = rotation_from_degrees(vec3(kj[i]["rotation_deg"]));
    keys.push_back(k);
  }
  return RigidMotion(vec3(m["pivot"]), std::move(keys));
}

void check_name_characters(const Ctx& c, const std::string& path, const std::string& name) {
  // Names head stats.csv columns and reach the terminal and the log: no commas,
  // quotes or control characters (a newline split the header, and a resume lost rows).
  for (const unsigned char ch : name)
    if (ch < 0x20 || ch == 0x7f || ch == ',' || ch == '"')
      c.fail(path,
             "must not contain commas, double quotes or control characters (names head stats.csv columns "
             "and are printed)");
}

void check_unique_names(const Ctx& c, const json& list, const std::string& key) {
  std::set<std::string> seen;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string n = list[i]["name"].get<std::string>();
    check_name_characters(c, fmt::format("{}[{}].name", key, i), n);
    if (!seen.insert(n).second) c.fail(fmt::format("{}[{}].name", key, i), "duplicate name '" + n + "'");
  }
}

TemperatureCurve build_curve(const Ctx& c, const std::string& path, const json& j) {
  if (j.is_number()) return ConstantCurve{j.get<double>()};
  const std::string kind = j["curve"].get<std::string>();
  if (kind == "zhang_arctan")
    return ZhangArctan{j["scale"].get<double>(), j["centre"].get<double>(), j["width"].get<double>(),
                       j["offset"].get<double>()};
  std::vector<std::pair<Real, Real>> pts;
  for (std::size_t i = 0; i < j["points"].size(); ++i) {
    const Real t = j["points"][i][0].get<double>(), v = j["points"][i][1].get<double>();
    if (!pts.empty() && !(t > pts.back().first))
      c.fail(fmt::format("{}.points[{}]", path, i), "temperatures must increase strictly");
    if (v < 0) c.fail(fmt::format("{}.points[{}]", path, i), "values must be >= 0");
    pts.emplace_back(t, v);
  }
  return PiecewiseLinear(pts);
}

PiecewiseLinear build_schedule(const Ctx& c, const std::string& path, const json& j) {
  if (j.is_number()) return PiecewiseLinear::constant(j.get<double>());
  std::vector<std::pair<Real, Real>> pts;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const Real t = j[i][0].get<double>(), v = j[i][1].get<double>();
    if (t < 0) c.fail(fmt::format("{}[{}]", path, i), "schedule times must be >= 0 s");
    if (!pts.empty() && !(t > pts.back().first))
      c.fail(fmt::format("{}[{}]", path, i), "schedule times must increase strictly");
    if (v < -273.15) c.fail(fmt::format("{}[{}]", path, i), "temperature must be >= -273.15 degC");
    pts.emplace_back(t, v);
  }
  return PiecewiseLinear(pts);
}

Oven build_oven(const Ctx& c, const json& env) {
  Oven oven;
  oven.air_temperature = build_schedule(c, "environment.air_temperature", env["air_temperature"]);
  oven.heat_transfer_coefficient = env["heat_transfer_coefficient"].get<double>();
  oven.emissivity = env["emissivity"].get<double>();
  oven.bake_time_scale = env["bake_time_scale"].get<double>();
  oven.browning = build_browning(env["browning"]);
  oven.air_vapour_density = env["air_vapour_density"].get<double>();
  if (!env["mass_transfer_coefficient"].is_null())
    oven.mass_transfer_coefficient = env["mass_transfer_coefficient"].get<double>();
  if (!env["air_pressure"].is_null() && !env["altitude"].is_null())
    c.fail("environment.altitude",
           "give the air pressure or the altitude, not both (environment.air_pressure is set too; a variant that "
           "changes one sets the other to null)");
  if (const auto air = named_air_pressure(env)) oven.air_pressure = air->pascal;
  return oven;
}

PoreWater build_pore_water(const Ctx& c, const std::string& path, const json& material, const Oven& oven) {
  const json& w = material["moisture"];
  PoreWater p;
  p.moisture = w["content"].get<double>();
  p.gas_fraction = w["gas_fraction"].get<double>();
  p.vapour_diffusivity = w["vapour_diffusivity"].get<double>();
  p.tortuosity = w["tortuosity"].get<double>();
  p.liquid_diffusivity = w["liquid_diffusivity"].get<double>();
  p.cell_heat_pipe = w["cell_heat_pipe"].get<double>();
  if (w["surface_evaporation"].get<std::string>() == "supply_limited") {
    p.surface_evaporation = PoreWater::SurfaceEvaporation::supply_limited;
    if (p.moisture > 0 && !(p.liquid_diffusivity > 0))
      c.fail(
          path + ".moisture.surface_evaporation",
          "\"supply_limited\" brings the water to the face by liquid diffusion: give moisture.liquid_diffusivity > 0");
  }
  if (!w["pore_opening_temperature"].is_null())
    p.pore_opening_temperature = w["pore_opening_temperature"].get<double>();
  p.pore_opening_width = w["pore_opening_width"].get<double>();
  if (w["expanded_conductivity"].get<std::string>() == "parallel")
    p.expanded_conductivity = PoreWater::ExpandedConductivity::parallel;
  if (!w["dry_conductivity"].is_null()) p.dry_conductivity = w["dry_conductivity"].get<double>();
  p.latent_heat = w["latent_heat"].get<double>();
  p.air_pressure = oven.air_pressure;
  p.boiling_point = w["boiling_point"].is_null() ? oven.boiling_point() : w["boiling_point"].get<double>();
  const json& s = w["sorption"];
  p.sorption.oswin_a_slope = s["oswin_a_slope"].get<double>();
  p.sorption.oswin_a_offset = s["oswin_a_offset"].get<double>();
  p.sorption.oswin_exponent = s["oswin_exponent"].get<double>();
  return p;
}

FrictionModel friction_model(const json& j, FrictionModel solver_default) {
  const std::string m = j["friction_model"].get<std::string>();
  if (m == "coulomb") return FrictionModel::coulomb;
  if (m == "velocity_share") return FrictionModel::velocity_share;
  return solver_default;
}

Collider build_collider(const Ctx& c, const json& cj, std::size_t i, Real cell, FrictionModel solver_default,
                        const Oven& oven) {
  const std::string path = fmt::format("colliders[{}]", i);
  Collider col;
  col.name = cj["name"].get<std::string>();
  col.geometry = build_collider_geometry(c, path + ".shape", cj["shape"], cell);
  const std::string contact = cj["contact"].get<std::string>();
  col.contact.mode = contact == "sticky" ? ContactMode::sticky
                     : contact == "slip" ? ContactMode::slip
                                         : ContactMode::separate;
  col.contact.friction_model = friction_model(cj, solver_default);
  col.contact.friction = cj["friction"].get<double>();
  col.contact.damping = cj["damping"].get<double>();
  if (cj.contains("motion")) col.motion = build_motion(c, path + ".motion", cj["motion"]);
  if (cj["temperature"].is_string())  // "oven" (the schema admits no other string)
    col.temperature = oven.air_temperature;
  else if (!cj["temperature"].is_null())
    col.temperature = build_schedule(c, path + ".temperature", cj["temperature"]);
  col.heat_transfer_coefficient = cj["heat_transfer_coefficient"].get<double>();
  col.look = parse_collider_look(cj["look"].get<std::string>(), col.geometry, c.file + ": " + path + ".look");
  return col;
}

void require_memory(const Ctx& c, const std::string& path, double bytes, const std::string& what) {
  const double have = physical_memory_bytes();
  if (!(bytes <= (have > 0 ? have : 1e15)))
    c.fail(path, fmt::format("this scene needs about {:.3g} GB for {}; this machine has {:.3g} GB", bytes / 1e9, what,
                             have / 1e9));
}

double lattice_points(const Shape& shape, Real spacing) {
  const Vec3 ext = bounds(shape).extent();
  return (std::floor(ext.x() / spacing) + 1) * (std::floor(ext.y() / spacing) + 1) *
         (std::floor(ext.z() / spacing) + 1);
}

IrreversibleSetting build_setting(const json& material) {
  IrreversibleSetting set;
  if (!material["set_temperature"].is_null()) set.temperature = material["set_temperature"].get<double>();
  return set;
}

SceneParts read_common(const Ctx& c, const json& doc, FrictionModel solver_friction) {
  SceneParts parts;
  for (auto it = doc["materials"].begin(); it != doc["materials"].end(); ++it) {
    check_name_characters(c, "materials." + it.key(), it.key());
    parts.material_names.push_back(it.key());
  }
  check_unique_names(c, doc["bodies"], "bodies");
  check_unique_names(c, doc["colliders"], "colliders");
  check_unique_names(c, doc["probes"], "probes");
  World& world = parts.world;
  world.domain = {vec3(doc["domain"]["min"]), vec3(doc["domain"]["max"])};
  world.domain_contact.friction_model = friction_model(doc["domain"], solver_friction);
  world.domain_contact.friction = doc["domain"]["friction"].get<double>();
  world.domain_contact.damping = doc["domain"]["damping"].get<double>();
  // SPH only for now: an MPM scene does not hold the key.
  const json periodic = doc["domain"].value("periodic", json::array());
  for (std::size_t i = 0; i < periodic.size(); ++i) {
    const int axis = periodic[i].get<std::string>()[0] - 'x';
    if (world.periodic[std::size_t(axis)])
      c.fail(fmt::format("domain.periodic[{}]", i), fmt::format("axis '{}' is listed twice", char('x' + axis)));
    world.periodic[std::size_t(axis)] = true;
  }
  world.gravity = vec3(doc["gravity"]);
  world.mass_scaling.factor = doc["solver"]["mass_scaling"].get<double>();
  world.oven = build_oven(c, doc["environment"]);
  for (std::size_t i = 0; i < doc["bodies"].size(); ++i) {
    const json& b = doc["bodies"][i];
    const std::string path = fmt::format("bodies[{}]", i);
    BodyBase body;
    body.name = b["name"].get<std::string>();  // its characters checked by check_unique_names
    body.source = c.file + ": " + path;
    const std::string mname = b["material"].get<std::string>();
    const auto& names = parts.material_names;
    const auto found = std::find(names.begin(), names.end(), mname);
    if (found == names.end()) {
      const std::string near = closest_match(mname, names);
      c.fail(path + ".material",
             fmt::format("unknown material '{}'{}; defined materials: {}", mname,
                         near.empty() ? "" : "; did you mean '" + near + "'?", fmt::join(names, ", ")));
    }
    body.material = static_cast<int>(found - names.begin());
    body.shape = build_shape(c, path + ".shape", b["shape"]);
    body.temperature = b["temperature"].get<double>();
    body.velocity = vec3(b["velocity"]);
    parts.bodies.push_back(std::move(body));
  }
  return parts;
}

}  // namespace bakesim::scene_parts
