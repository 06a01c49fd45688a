#include "io/scene.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/errors.hpp"
#include "geometry/mesh_io.hpp"
#include "io/schema.hpp"

namespace bakesim {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

Vec3 vec3(const json& j) { return Vec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>()); }

// Everything needed to report an error at a key path of this scene file.
struct Ctx {
  std::string file;
  std::string base_dir;
  [[noreturn]] void fail(const std::string& path, const std::string& msg) const {
    throw InputError(file + ": " + path, msg);
  }
};

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

void check_unique_names(const Ctx& c, const json& list, const std::string& key) {
  std::set<std::string> seen;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string n = list[i]["name"].get<std::string>();
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

BrowningKinetics build_browning(const json& b) {
  return {b["max_colour_difference"].get<double>(), b["rate_constant"].get<double>(),
          b["activation_energy"].get<double>()};
}

Oven build_oven(const Ctx& c, const json& env) {
  Oven oven;
  oven.air_temperature = build_schedule(c, "environment.air_temperature", env["air_temperature"]);
  oven.heat_transfer_coefficient = env["heat_transfer_coefficient"].get<double>();
  oven.bake_time_scale = env["bake_time_scale"].get<double>();
  oven.browning = build_browning(env["browning"]);
  return oven;
}

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

// Thesis Table 4.1 with Eq 4.1–4.4 (two-segment curves through T0, Tc, Tf)
// and bread-dough thermal properties; keys the scene gives win.
json dough_preset() {
  return json{{"density", 1100.0},
              {"specific_heat", 2800.0},
              {"conductivity", 0.4},
              {"viscosity", {{"curve", "piecewise_linear"}, {"points", {{26, 0.1}, {45, 1.0}, {120, 5e3}}}}},
              {"elasticity", {{"curve", "piecewise_linear"}, {"points", {{26, 1.0}, {45, 10.0}, {120, 5e4}}}}},
              {"relaxation_time",
               {{"curve", "zhang_arctan"}, {"scale", 450.0}, {"centre", 65.0}, {"width", 2.0}, {"offset", 2.0}}},
              {"xsph", {{"curve", "piecewise_linear"}, {"points", {{26, 0.05}, {120, 5.0}}}}}};
}

void apply_material_presets(json& doc) {
  if (!doc.contains("materials") || !doc["materials"].is_object()) return;
  const json preset = dough_preset();
  for (auto& [name, m] : doc["materials"].items()) {
    if (!m.is_object() || !m.contains("preset") || m["preset"] != "dough") continue;
    for (const auto& [key, value] : preset.items())
      if (!m.contains(key)) m[key] = value;
  }
}

sph::BubbleDistribution parse_distribution(const std::string& s) {
  if (s == "centred") return sph::BubbleDistribution::centred;
  if (s == "layered") return sph::BubbleDistribution::layered;
  if (s == "region") return sph::BubbleDistribution::region;
  return sph::BubbleDistribution::uniform;
}

// The MPM setup from the same document: materials by name order, bodies and
// colliders as for SPH (bodies already parsed into `sph` give the shapes).
mpm::Setup build_mpm_setup(const Ctx& c, const json& doc, const sph::Setup& sph) {
  mpm::Setup setup;
  const json& mj = doc["solver"]["mpm"];
  mpm::Settings& st = setup.settings;
  st.cell_size = mj["cell_size"].get<double>();
  st.particles_per_cell = mj["particles_per_cell"].get<int>();
  st.reorder_every = mj["reorder_every"].get<int>();
  st.cfl = doc["solver"]["cfl"].get<double>();
  st.max_dt = doc["solver"]["max_dt"].get<double>();
  for (auto it = doc["materials"].begin(); it != doc["materials"].end(); ++it) {
    const json& m = it.value();
    mpm::Material mat;
    mat.name = it.key();
    mat.density = m["density"].get<double>();
    mat.lame = mpm::Lame::from_young(m["youngs_modulus"].get<double>(), m["poisson_ratio"].get<double>());
    if (m["elastic_model"].get<std::string>() == "fixed_corotated")
      mat.elastic = mpm::FixedCorotated{mat.lame};
    else
      mat.elastic = mpm::Hencky{mat.lame};
    const json& pj = m["plasticity"];
    const std::string model = pj["model"].get<std::string>();
    if (model != "none" && std::holds_alternative<mpm::FixedCorotated>(mat.elastic))
      c.fail("materials." + it.key() + ".plasticity", model + " plasticity needs elastic_model \"hencky\"");
    const std::string mpath = "materials." + it.key();
    // Temperature-dependent τ_y(θ), η(θ) (spec 3.2, paper Fig 8): piecewise-linear curves.
    auto plastic_curve = [&](const std::string& key) {
      const TemperatureCurve curve = build_curve(c, mpath + ".plasticity." + key, pj[key]);
      if (const auto* k = std::get_if<ConstantCurve>(&curve)) return PiecewiseLinear::constant(k->value);
      if (const auto* pl = std::get_if<PiecewiseLinear>(&curve)) return *pl;
      c.fail(mpath + ".plasticity." + key, "MPM plasticity takes a number or a piecewise_linear curve");
    };
    const PiecewiseLinear yield = plastic_curve("yield_stress"), viscosity = plastic_curve("viscosity");
    const bool curved =
        !pj["yield_stress"].is_number() || !pj["viscosity"].is_number() || !pj["set_temperature"].is_null();
    if (model != "none" && curved) {
      SettingCurves sc{yield, viscosity};
      if (!pj["set_temperature"].is_null()) sc.set_temperature = pj["set_temperature"].get<double>();
      sc.set_softening = pj["set_softening"].get<double>();
      sc.brittle_water_loss = pj["brittle_water_loss"].get<double>();
      if (sc.set_softening > 0 &&
          (model != "cam_clay" || pj["set_temperature"].is_null() || !(m["water"]["saturation"].get<double>() > 0)))
        c.fail(mpath + ".plasticity.set_softening",
               "softens the set material as it dries: needs model \"cam_clay\", a set_temperature and water.saturation "
               "> 0");
      mat.setting = sc;
    }
    const Real yield0 = yield(20.0), viscosity0 = viscosity(20.0);
    mat.initial_porosity = pj["initial_porosity"].get<double>();
    if (model == "von_mises") mat.plastic = mpm::VonMises{yield0, viscosity0};
    if (model == "cam_clay")
      mat.plastic = mpm::CamClay{yield0, viscosity0, pj["cohesion_slope"].get<double>(), mat.initial_porosity};
    mat.specific_heat = m["specific_heat"].get<double>();
    mat.conductivity = m["conductivity"].get<double>();
    mat.thermal_expansion = m["thermal_expansion"].get<double>();
    const json& wj = m["water"];
    mat.water.saturation = wj["saturation"].get<double>();
    mat.water.diffusivity = wj["diffusivity"].get<double>();
    mat.water.evaporation_rate = wj["evaporation_rate"].get<double>();
    mat.water.stiffness = wj["stiffness"].get<double>();
    const json& lj = m["leavening"];
    mat.gas.rate = lj["rate"].get<double>();
    mat.gas.peak_temperature = lj["peak_temperature"].get<double>();
    if (!lj["amount"].is_null()) mat.gas.amount = lj["amount"].get<double>();
    mat.gas.width = lj["width"].get<double>();
    if (mat.gas.active() && model != "cam_clay" && mat.initial_porosity <= 0)
      c.fail(mpath + ".leavening",
             "the gas needs pores: give plasticity.initial_porosity > 0 (and cam_clay so the dough can expand)");
    setup.materials.push_back(mat);
  }
  for (std::size_t i = 0; i < sph.bodies.size(); ++i) {
    const sph::Body& b = sph.bodies[i];
    mpm::Body body;
    body.name = b.name;
    body.material = b.material;
    body.shape = b.shape;
    body.temperature = b.temperature;
    body.velocity = b.velocity;
    body.angular_velocity = vec3(doc["bodies"][i]["angular_velocity"]);
    setup.bodies.push_back(std::move(body));
  }
  for (std::size_t i = 0; i < doc["colliders"].size(); ++i) {
    const json& cj = doc["colliders"][i];
    const std::string path = fmt::format("colliders[{}]", i);
    Collider g;
    g.name = cj["name"].get<std::string>();
    g.geometry = build_collider_geometry(c, path + ".shape", cj["shape"], st.cell_size);
    // A cup or container wall under two cells thick has grid nodes inside it
    // that are nearer its far face: their contact normal points the wrong way
    // and material sinks into the wall (the muffin cups did).
    if (cj["shape"].contains("wall_thickness") &&
        cj["shape"]["wall_thickness"].get<double>() < 2 * st.cell_size - 1e-12)
      c.fail(path + ".shape.wall_thickness",
             fmt::format(
                 "{} m is thinner than two MPM cells ({} m): material would sink into the wall; make it at least {} m",
                 cj["shape"]["wall_thickness"].get<double>(), st.cell_size, 2 * st.cell_size));
    // Meshes act through a signed distance grid at half the MPM cell size.
    if (const auto* mesh = std::get_if<MeshCollider>(&g.geometry))
      g.geometry = mesh->with_signed_distance(0.5 * st.cell_size, 3 * st.cell_size);
    if (cj.contains("motion")) g.motion = build_motion(c, path + ".motion", cj["motion"]);
    const std::string contact = cj["contact"].get<std::string>();
    g.contact.mode = contact == "sticky" ? ContactMode::sticky
                     : contact == "slip" ? ContactMode::slip
                                         : ContactMode::separate;
    g.contact.friction_model = FrictionModel::coulomb;
    g.contact.friction = cj["friction"].get<double>();
    if (!cj["temperature"].is_null()) g.temperature = build_schedule(c, path + ".temperature", cj["temperature"]);
    g.heat_transfer_coefficient = cj["heat_transfer_coefficient"].get<double>();
    setup.colliders.push_back(std::move(g));
  }
  setup.domain = {vec3(doc["domain"]["min"]), vec3(doc["domain"]["max"])};
  setup.domain_contact.friction = doc["domain"]["friction"].get<double>();
  setup.gravity = vec3(doc["gravity"]);
  setup.oven = build_oven(c, doc["environment"]);
  st.baseline = mj["model"].get<std::string>() == "baseline";
  st.heat_tolerance = mj["heat_tolerance"].get<double>();
  st.heat_max_iterations = mj["heat_max_iterations"].get<int>();
  const std::string heat = mj["heat"].get<std::string>();
  if (heat == "explicit")
    st.heat = mpm::HeatMethod::explicit_;
  else if (heat == "implicit")
    st.heat = mpm::HeatMethod::implicit;
  else if (heat == "off")
    st.heat = mpm::HeatMethod::off;
  else {
    // auto: heat when anything thermal can happen.
    bool thermal = false;
    const auto& air = setup.oven.air_temperature.points();
    for (const auto& b : setup.bodies)
      for (const auto& [t, v] : air) thermal |= setup.oven.heat_transfer_coefficient > 0 && v != b.temperature;
    for (const auto& b : setup.bodies) thermal |= b.temperature != setup.bodies.front().temperature;
    for (const auto& g : setup.colliders) thermal |= g.temperature.has_value();
    for (const auto& m : setup.materials) thermal |= m.water.active() || m.gas.active() || m.setting.has_value();
    st.heat = thermal ? mpm::HeatMethod::explicit_ : mpm::HeatMethod::off;
  }
  return setup;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file, const std::string& base_dir) {
  json doc;
  try {
    doc = json::parse(text, nullptr, true, /*ignore_comments=*/true);
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
  apply_material_presets(doc);
  scene_schema().validate(doc, file);

  const Ctx c{file, base_dir};
  Scene sc;
  sc.file = file;
  sc.name = doc["name"].get<std::string>();
  if (sc.name.empty()) {
    sc.name = fs::path(file).stem().string();
    doc["name"] = sc.name;
  }
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

  const Vec3 dmin = vec3(doc["domain"]["min"]), dmax = vec3(doc["domain"]["max"]);
  require_box(c, "domain", dmin, dmax);

  sc.air_temperature = build_schedule(c, "environment.air_temperature", doc["environment"]["air_temperature"]);
  sc.heat_transfer_coefficient = doc["environment"]["heat_transfer_coefficient"].get<double>();
  sc.bake_time_scale = doc["environment"]["bake_time_scale"].get<double>();

  // Materials, in name order (json objects iterate sorted by key).
  sph::Setup& setup = sc.sph;
  std::vector<std::string> material_names;
  for (auto it = doc["materials"].begin(); it != doc["materials"].end(); ++it) {
    const json& m = it.value();
    sph::Material mat;
    mat.name = it.key();
    mat.rest_density = m["density"].get<double>();
    mat.viscosity = build_curve(c, "materials." + it.key() + ".viscosity", m["viscosity"]);
    mat.surface_tension = m["surface_tension"].get<double>();
    mat.properties_follow_peak = m["property_temperature"].get<std::string>() == "peak";
    mat.xsph = build_curve(c, "materials." + it.key() + ".xsph", m["xsph"]);
    mat.specific_heat = m["specific_heat"].get<double>();
    mat.conductivity = m["conductivity"].get<double>();
    mat.elasticity = build_curve(c, "materials." + it.key() + ".elasticity", m["elasticity"]);
    mat.relaxation_time = build_curve(c, "materials." + it.key() + ".relaxation_time", m["relaxation_time"]);
    if (std::visit([](const auto& curve) { return curve(-273.15) <= 0 || curve(2000.0) <= 0; }, mat.relaxation_time))
      c.fail("materials." + it.key() + ".relaxation_time", "must stay above 0 s at every temperature");
    setup.materials.push_back(mat);
    material_names.push_back(it.key());
  }

  check_unique_names(c, doc["bodies"], "bodies");
  check_unique_names(c, doc["colliders"], "colliders");
  check_unique_names(c, doc["probes"], "probes");

  Real max_initial_speed = 0;
  for (std::size_t i = 0; i < doc["bodies"].size(); ++i) {
    const json& b = doc["bodies"][i];
    const std::string path = fmt::format("bodies[{}]", i);
    sph::Body body;
    body.name = b["name"].get<std::string>();
    body.source = file + ": " + path;
    const std::string mname = b["material"].get<std::string>();
    const auto found = std::find(material_names.begin(), material_names.end(), mname);
    if (found == material_names.end()) {
      const std::string near = closest_match(mname, material_names);
      c.fail(path + ".material",
             fmt::format("unknown material '{}'{}; defined materials: {}", mname,
                         near.empty() ? "" : "; did you mean '" + near + "'?", fmt::join(material_names, ", ")));
    }
    body.material = static_cast<int>(found - material_names.begin());
    body.shape = build_shape(c, path + ".shape", b["shape"]);
    body.temperature = b["temperature"].get<double>();
    body.velocity = vec3(b["velocity"]);
    body.hold_temperature = b["hold_temperature"].get<bool>();
    const json& bj = b["bubbles"];
    sph::BubbleSpec& bs = body.bubbles;
    bs.fraction = bj["fraction"].get<double>();
    bs.distribution = parse_distribution(bj["distribution"].get<std::string>());
    bs.seed = bj["seed"].get<std::uint64_t>();
    bs.layers = bj["layers"].get<int>();
    if (bj.contains("region"))
      bs.region = build_shape(c, path + ".bubbles.region", bj["region"]);
    else if (bs.distribution == sph::BubbleDistribution::region && bs.fraction > 0)
      c.fail(path + ".bubbles", "distribution \"region\" needs a region shape");
    if (!bj["pressure_scale"].is_null()) bs.pressure_scale = bj["pressure_scale"].get<double>();
    bs.max_expansion = bj["max_expansion"].get<double>();
    bs.end_temperature = bj["end_temperature"].get<double>();
    bs.contract_on_cooling = bj["contract_on_cooling"].get<bool>();
    max_initial_speed = std::max(max_initial_speed, body.velocity.norm());
    setup.bodies.push_back(std::move(body));
  }

  if (sc.solver_type == "mpm") {
    sc.mpm = build_mpm_setup(c, doc, setup);
  } else {
    const json& sj = doc["solver"]["sph"];
    sph::Settings& st = setup.settings;
    st.spacing = sj["spacing"].get<double>();
    st.smoothing_ratio = sj["smoothing_ratio"].get<double>();
    st.search = sph::parse_neighbour_method(sj["neighbour_search"].get<std::string>());
    st.clamp_negative_pressure = sj["negative_pressure"].get<std::string>() == "clamp";
    st.wall_density_correction = sj["wall_correction"].get<bool>();
    st.av_alpha = sj["artificial_viscosity"]["alpha"].get<double>();
    st.av_beta = sj["artificial_viscosity"]["beta"].get<double>();
    st.av_epsilon = sj["artificial_viscosity"]["epsilon"].get<double>();
    st.surface_threshold = sj["surface_threshold"].get<double>();
    st.heat_conduction = sj["heat_conduction"].get<bool>();
    st.conduction_factor = sj["conduction_factor"].get<double>();
    st.viscous_factor = sj["viscous_factor"].get<double>();
    st.force_factor = sj["force_factor"].get<double>();
    st.surface_method = sph::parse_surface_method(sj["surface"]["method"].get<std::string>());
    st.surface_colour_threshold = sj["surface"]["colour_threshold"].get<double>();
    st.surface_hull_threshold = sj["surface"]["hull_threshold"].get<double>();
    st.surface_every = sj["surface"]["every_steps"].get<int>();
    st.viscosity_solver = sph::parse_viscosity_solver(sj["viscosity_solver"].get<std::string>());
    {
      const json& aj = sj["adaptive_smoothing"];
      st.adaptive.enabled = aj["enabled"].get<bool>();
      st.adaptive.geometric_mean = aj["reference"].get<std::string>() == "geometric_mean";
      st.adaptive.sensitivity = aj["sensitivity"].get<double>();
      st.adaptive.scale = aj["scale"].get<double>();
      st.adaptive.min_ratio = aj["range"][0].get<double>();
      st.adaptive.max_ratio = aj["range"][1].get<double>();
      if (st.adaptive.min_ratio > st.adaptive.max_ratio)
        throw InputError("solver.sph.adaptive_smoothing.range", "the lower limit exceeds the upper one");
    }
    st.artificial_stress = sj["artificial_stress"]["epsilon"].get<double>();
    st.artificial_stress_exponent = sj["artificial_stress"]["exponent"].get<double>();
    st.implicit_tolerance = sj["implicit_viscosity"]["tolerance"].get<double>();
    st.implicit_max_iterations = sj["implicit_viscosity"]["max_iterations"].get<int>();
    st.cfl = doc["solver"]["cfl"].get<double>();
    st.max_dt = doc["solver"]["max_dt"].get<double>();

    setup.gravity = vec3(doc["gravity"]);
    setup.domain = {dmin, dmax};
    setup.oven = build_oven(c, doc["environment"]);
    setup.domain_contact.friction = doc["domain"]["friction"].get<double>();
    setup.domain_contact.damping = doc["domain"]["damping"].get<double>();

    if (sj["speed_of_sound"].is_string()) {
      // auto: ten times the fastest flow expected, so density varies ~1%.
      const Real g = setup.gravity.norm();
      const Real height = g > 0 ? std::abs((dmax - dmin).dot(setup.gravity / g)) : 0.0;
      const Real v = std::max({std::sqrt(2.0 * g * height), max_initial_speed, 0.1});
      st.speed_of_sound = 10.0 * v;
      doc["solver"]["sph"]["speed_of_sound"] = st.speed_of_sound;
    } else {
      st.speed_of_sound = sj["speed_of_sound"].get<double>();
    }

    const Real h = st.spacing * st.smoothing_ratio;
    for (std::size_t i = 0; i < doc["colliders"].size(); ++i) {
      const json& cj = doc["colliders"][i];
      const std::string path = fmt::format("colliders[{}]", i);
      Collider col;
      col.name = cj["name"].get<std::string>();
      col.geometry = build_collider_geometry(c, path + ".shape", cj["shape"], h);
      col.contact = {ContactMode::separate, FrictionModel::velocity_share, cj["friction"].get<double>(),
                     cj["damping"].get<double>()};
      if (cj.contains("motion") && doc["solver"]["type"].get<std::string>() == "sph")
        c.fail(path + ".motion", "moving colliders are available for the MPM solver only");
      if (!cj["temperature"].is_null())
        col.temperature = build_schedule(c, fmt::format("colliders[{}].temperature", i), cj["temperature"]);
      col.heat_transfer_coefficient = cj["heat_transfer_coefficient"].get<double>();
      setup.colliders.push_back(std::move(col));
    }
  }  // sph

  for (std::size_t i = 0; i < doc["probes"].size(); ++i) {
    const json& pj = doc["probes"][i];
    ProbeSpec p{pj["name"].get<std::string>(), vec3(pj["position"]), pj["quantities"].get<std::vector<std::string>>(),
                pj["follow"].get<bool>()};
    if (!Aabb{dmin, dmax}.contains(p.position))
      c.fail(fmt::format("probes[{}].position", i), "lies outside the domain");
    sc.probes.push_back(std::move(p));
  }

  const auto formats = doc["output"]["particles"].get<std::vector<std::string>>();
  sc.output.ply = std::find(formats.begin(), formats.end(), "ply") != formats.end();
  sc.output.vtu = std::find(formats.begin(), formats.end(), "vtu") != formats.end();
  sc.output.every_frames = doc["output"]["every_frames"].get<int>();
  sc.resolved = std::move(doc);
  return sc;
}

Scene load_scene(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, "scene file not found");
  if (fs::is_directory(path, ec)) throw InputError(path, "is a directory, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "scene file cannot be opened for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string dir = fs::path(path).parent_path().string();
  return parse_scene(ss.str(), path, dir.empty() ? "." : dir);
}

std::unique_ptr<Solver> make_solver(const Scene& scene) {
  if (scene.solver_type == "mpm") return std::make_unique<mpm::MpmSolver>(scene.mpm);
  return std::make_unique<sph::SphSolver>(scene.sph);
}

std::string describe(const Scene& scene, Solver& solver) {
  std::string out;
  out += fmt::format("scene      {} ({})\n", scene.name, scene.file);
  if (!scene.description.empty()) out += fmt::format("           {}\n", scene.description);
  out += fmt::format("solver     {}\n", scene.solver_type);
  const int frames = static_cast<int>(std::ceil(scene.end_time * scene.fps - 1e-9));
  out += fmt::format("time       {} s at {} fps: {} frames\n", scene.end_time, scene.fps, frames);
  if (scene.solver_type == "mpm") {
    const auto& ms = scene.mpm.settings;
    const auto& mpm_solver = dynamic_cast<const mpm::MpmSolver&>(solver);
    out += fmt::format("grid       cell {} m, {} particles per cell\n", ms.cell_size, ms.particles_per_cell);
    out += fmt::format("particles  {} in total, mass {:.4g} kg\n", solver.particles().size(), mpm_solver.total_mass());
    for (const auto& mat : scene.mpm.materials)
      out += fmt::format("  material {:<12} rho {} kg/m^3, mu {:.4g} Pa, lambda {:.4g} Pa, {}, {}\n", mat.name,
                         mat.density, mat.lame.mu, mat.lame.lambda,
                         std::holds_alternative<mpm::Hencky>(mat.elastic) ? "hencky" : "fixed corotated",
                         std::holds_alternative<mpm::VonMises>(mat.plastic)  ? "von Mises plasticity"
                         : std::holds_alternative<mpm::CamClay>(mat.plastic) ? "Cam-clay plasticity"
                                                                             : "elastic");
    const Real dt = solver.max_stable_dt();
    out += fmt::format("time step  {:.3e} s at t = 0 ({}), about {:.0f} steps for the whole run at this rate\n", dt,
                       solver.active_dt_bound(), scene.end_time / dt);
    return out;
  }
  const auto& st = scene.sph.settings;
  out += fmt::format("spacing    {} m, support h = {} m, speed of sound {:.3g} m/s, neighbour search {}\n", st.spacing,
                     st.spacing * st.smoothing_ratio, st.speed_of_sound, sph::to_string(st.search));
  const auto& sph_solver = dynamic_cast<const sph::SphSolver&>(solver);
  out += fmt::format("viscosity  {} (setting: {})\n", sph_solver.implicit_viscosity() ? "implicit" : "explicit",
                     sph::to_string(st.viscosity_solver));
  out += fmt::format("surface    {} test\n", sph::to_string(st.surface_method));
  if (scene.bake_time_scale != 1.0)
    out += fmt::format("bake clock {} bake seconds per simulated second: {} s simulate {:.1f} min of baking\n",
                       scene.bake_time_scale, scene.end_time, scene.end_time * scene.bake_time_scale / 60.0);
  out += fmt::format("particles  {} in total\n", solver.particles().size());
  for (std::size_t b = 0; b < scene.sph.bodies.size(); ++b) {
    const auto& body = scene.sph.bodies[b];
    out +=
        fmt::format("  body {:<16} {:>9} particles  material {:<10} mass {:.4g} kg each, {:.1f} degC\n",
                    "'" + body.name + "'", sph_solver.body_particle_count(b), scene.sph.materials[body.material].name,
                    sph_solver.particle_mass(body.material), body.temperature);
    if (body.bubbles.fraction > 0) {
      const auto& bubble = solver.particles().integer("bubble");
      const auto& owner = solver.particles().integer("body_id");
      std::size_t count = 0;
      for (std::size_t i = 0; i < bubble.size(); ++i) count += owner[i] == int(b) && bubble[i];
      out +=
          fmt::format("    {} bubble particles ({:.1f}%)\n", count, 100.0 * count / sph_solver.body_particle_count(b));
    }
  }
  out += fmt::format("colliders  {}\n", scene.sph.colliders.size());
  for (const auto& c : scene.sph.colliders)
    out += fmt::format("  '{}' friction {} damping {}\n", c.name, c.contact.friction, c.contact.damping);
  out += fmt::format("probes     {}\n", scene.probes.size());
  const Real dt = solver.max_stable_dt();
  out += "time step  bounds at t = 0:\n";
  for (const auto& [name, value] : sph_solver.time_step_bounds())
    out += fmt::format("  {:<10} {:.3e} s\n", name, value);
  out += fmt::format("  active: {} -> dt = {:.3e} s (about {:.0f} steps for the whole run at this rate)\n",
                     solver.active_dt_bound(), dt, scene.end_time / dt);
  return out;
}

}  // namespace bakesim
