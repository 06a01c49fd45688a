// The MPM solver's setup from a validated scene (docs/scene-reference.md).
#include <fmt/format.h>

#include "io/scene_parts.hpp"
#include "mpm/solver.hpp"

namespace bakesim::scene_parts {

namespace {

mpm::Material build_material(const Ctx& c, const std::string& name, const json& m, const Oven& oven) {
  const std::string mpath = "materials." + name;
  mpm::Material mat;
  mat.name = name;
  mat.density = m["density"].get<double>();
  mat.lame = mpm::Lame::from_young(m["youngs_modulus"].get<double>(), m["poisson_ratio"].get<double>());
  if (m["elastic_model"].get<std::string>() == "fixed_corotated")
    mat.elastic = mpm::FixedCorotated{mat.lame};
  else
    mat.elastic = mpm::Hencky{mat.lame};
  const json& pj = m["plasticity"];
  const std::string model = pj["model"].get<std::string>();
  if (model != "none" && std::holds_alternative<mpm::FixedCorotated>(mat.elastic))
    c.fail(mpath + ".plasticity", model + " plasticity needs elastic_model \"hencky\"");
  // Temperature-dependent τ_y(θ), η(θ) (spec 3.2, paper Fig 8): piecewise-linear curves.
  auto plastic_curve = [&](const std::string& key) {
    const TemperatureCurve curve = build_curve(c, mpath + ".plasticity." + key, pj[key]);
    if (const auto* k = std::get_if<ConstantCurve>(&curve)) return PiecewiseLinear::constant(k->value);
    if (const auto* pl = std::get_if<PiecewiseLinear>(&curve)) return *pl;
    c.fail(mpath + ".plasticity." + key, "MPM plasticity takes a number or a piecewise_linear curve");
  };
  const PiecewiseLinear yield = plastic_curve("yield_stress"), viscosity = plastic_curve("viscosity");
  mat.set = build_setting(m);
  const bool curved = !pj["yield_stress"].is_number() || !pj["viscosity"].is_number() || mat.set.ever();
  if (model != "none" && curved) {
    SettingCurves sc{yield, viscosity};
    sc.set_softening = pj["set_softening"].get<double>();
    sc.brittle_water_loss = pj["brittle_water_loss"].get<double>();
    if (sc.set_softening > 0 &&
        (model != "cam_clay" || !mat.set.ever() ||
         !(m["water"]["saturation"].get<double>() > 0 || m["moisture"]["content"].get<double>() > 0)))
      c.fail(mpath + ".plasticity.set_softening",
             "softens the set material as it dries: needs model \"cam_clay\", the material's set_temperature and "
             "water (water.saturation > 0 or moisture.content > 0)");
    mat.setting = sc;
  }
  const Real yield0 = yield(20.0), viscosity0 = viscosity(20.0);
  mat.initial_porosity = pj["initial_porosity"].get<double>();
  if (model == "von_mises") mat.plastic = mpm::VonMises{yield0, viscosity0};
  if (model == "herschel_bulkley")
    mat.plastic = mpm::HerschelBulkleyFlow{yield0, viscosity0, pj["flow_index"].get<double>()};
  else if (pj["flow_index"].get<double>() != 1)
    c.fail(mpath + ".plasticity.flow_index",
           "is read by model \"herschel_bulkley\" only (got model \"" + model + "\")");
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
  mat.moisture = build_pore_water(c, mpath, m, oven);
  if (mat.moisture.active()) {
    // One water per material: moisture's liquid is carried as the paper's water
    // (its pressure, its Fick diffusion), its vapour and latent heat come in addition.
    for (const char* key : {"saturation", "evaporation_rate"})
      if (wj[key].get<double>() != 0)
        c.fail(mpath + ".water." + key,
               "with moisture.content the water comes from the moisture and leaves as vapour: leave water." +
                   std::string(key) + " out (water.stiffness still applies)");
    if (wj["diffusivity"].get<double>() != 1e-8)
      c.fail(mpath + ".water.diffusivity", "with moisture.content the liquid diffuses by moisture.liquid_diffusivity");
    const PoreWater& pw = mat.moisture;
    mat.water.saturation = pw.initial_water(mat.density) / mat.water.water_density;
    if (mat.water.saturation > 1)
      c.fail(
          mpath + ".moisture.content",
          fmt::format("{} kg/kg at density {} kg/m^3 is more water than the volume holds", pw.moisture, mat.density));
    mat.water.diffusivity = pw.liquid_diffusivity;
    mat.water.evaporation_rate = 0;
  }
  const json& lj = m["leavening"];
  mat.gas.rate = lj["rate"].get<double>();
  mat.gas.peak_temperature = lj["peak_temperature"].get<double>();
  if (!lj["amount"].is_null()) mat.gas.amount = lj["amount"].get<double>();
  mat.gas.width = lj["width"].get<double>();
  if (mat.gas.active() && model != "cam_clay" && mat.initial_porosity <= 0)
    c.fail(mpath + ".leavening",
           "the gas needs pores: give plasticity.initial_porosity > 0 (and cam_clay so the dough can expand)");
  return mat;
}

Collider build_grid_collider(const Ctx& c, const json& cj, std::size_t i, Real cell, const Oven& oven) {
  const std::string path = fmt::format("colliders[{}]", i);
  Collider col = build_collider(c, cj, i, cell, FrictionModel::coulomb, oven);
  // A cup or container wall under two cells thick has grid nodes inside it
  // that are nearer its far face: their contact normal points the wrong way
  // and material sinks into the wall (the muffin cups did).
  if (cj["shape"].contains("wall_thickness") &&
      cj["shape"]["wall_thickness"].get<double>() < kMinWallCells * cell - 1e-12)
    c.fail(path + ".shape.wall_thickness",
           fmt::format("{} m is thinner than two MPM cells ({} m): material would sink into the wall; make it at "
                       "least {} m",
                       cj["shape"]["wall_thickness"].get<double>(), cell, kMinWallCells * cell));
  // Meshes act through a signed distance grid at half the MPM cell size.
  if (const auto* mesh = std::get_if<MeshCollider>(&col.geometry))
    col.geometry = mesh->with_signed_distance(0.5 * cell, 3 * cell);
  return col;
}

// auto: heat when anything thermal can happen.
mpm::HeatMethod heat_method(const std::string& heat, const mpm::Setup& setup) {
  if (heat == "explicit") return mpm::HeatMethod::explicit_;
  if (heat == "implicit") return mpm::HeatMethod::implicit;
  if (heat == "off") return mpm::HeatMethod::off;
  bool thermal = false;
  const auto& air = setup.oven.air_temperature.points();
  for (const auto& b : setup.bodies)
    for (const auto& [t, v] : air)
      thermal |= (setup.oven.heat_transfer_coefficient > 0 || setup.oven.emissivity > 0) && v != b.temperature;
  for (const auto& b : setup.bodies) thermal |= b.temperature != setup.bodies.front().temperature;
  for (const auto& g : setup.colliders) thermal |= g.temperature.has_value();
  for (const auto& m : setup.materials) thermal |= m.water.active() || m.gas.active() || m.setting.has_value();
  return thermal ? mpm::HeatMethod::explicit_ : mpm::HeatMethod::off;
}

}  // namespace

mpm::Setup build_mpm_setup(const Ctx& c, const json& doc, const SceneParts& parts) {
  mpm::Setup setup;
  static_cast<World&>(setup) = parts.world;
  const json& mj = doc["solver"]["mpm"];
  mpm::Settings& st = setup.settings;
  st.cell_size = mj["cell_size"].get<double>();
  st.particles_per_cell = mj["particles_per_cell"].get<int>();
  st.reorder_every = mj["reorder_every"].get<int>();
  st.cfl = doc["solver"]["cfl"].get<double>();
  st.max_dt = doc["solver"]["max_dt"].get<double>();
  st.baseline = mj["model"].get<std::string>() == "baseline";
  st.heat_tolerance = mj["heat_tolerance"].get<double>();
  st.heat_max_iterations = mj["heat_max_iterations"].get<int>();
  for (const std::string& name : parts.material_names)
    setup.materials.push_back(build_material(c, name, doc["materials"][name], parts.world.oven));
  for (std::size_t i = 0; i < parts.bodies.size(); ++i) {
    mpm::Body body;
    static_cast<BodyBase&>(body) = parts.bodies[i];
    body.angular_velocity = vec3(doc["bodies"][i]["angular_velocity"]);
    setup.bodies.push_back(std::move(body));
  }
  // Node counts in floating point, before anything is allocated (an integer
  // product wraps around for tiny cells); then about 500 bytes a point and
  // 170 a node (grid, heat and implicit-heat records).
  const Vec3 ext = setup.domain.extent();
  double nodes = 1, points = 0;
  for (int k = 0; k < 3; ++k) nodes *= std::ceil(ext[k] / st.cell_size) + 1;
  if (nodes > 4e8)
    c.fail("solver.mpm.cell_size",
           fmt::format("the grid over the domain would have {:.3g} nodes (at most 4e8): make the cells larger or the "
                       "domain smaller",
                       nodes));
  const Real spacing = st.cell_size / mpm::points_per_cell_axis(st.particles_per_cell);
  for (const auto& b : setup.bodies) points += lattice_points(b.shape, spacing);
  require_memory(c, "solver.mpm.cell_size", 500.0 * points + 170.0 * nodes,
                 fmt::format("about {:.3g} material points and {:.3g} grid nodes", points, nodes));
  for (std::size_t i = 0; i < doc["colliders"].size(); ++i)
    setup.colliders.push_back(build_grid_collider(c, doc["colliders"][i], i, st.cell_size, parts.world.oven));
  st.heat = heat_method(mj["heat"].get<std::string>(), setup);
  if (const std::string problem = mpm::periodic_problem(setup); !problem.empty()) c.fail("domain.periodic", problem);
  return setup;
}

}  // namespace bakesim::scene_parts
