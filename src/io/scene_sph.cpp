// The SPH solver's setup from a validated scene (docs/scene-reference.md).
#include <fmt/format.h>

#include <cmath>

#include "io/scene_parts.hpp"

namespace bakesim::scene_parts {

namespace {

sph::BubbleDistribution parse_distribution(const std::string& s) {
  if (s == "centred") return sph::BubbleDistribution::centred;
  if (s == "layered") return sph::BubbleDistribution::layered;
  if (s == "region") return sph::BubbleDistribution::region;
  return sph::BubbleDistribution::uniform;
}

// A curve above zero at both ends of the temperatures a bake can reach (the
// curves are piecewise linear or monotone between them).
bool positive_at_every_temperature(const TemperatureCurve& c) {
  return std::visit([](const auto& curve) { return curve(-273.15) > 0 && curve(2000.0) > 0; }, c);
}

sph::Material build_material(const Ctx& c, const std::string& name, const json& m, const Oven& oven) {
  const std::string path = "materials." + name;
  sph::Material mat;
  mat.name = name;
  mat.rest_density = m["density"].get<double>();
  mat.viscosity = build_curve(c, path + ".viscosity", m["viscosity"]);
  mat.surface_tension = m["surface_tension"].get<double>();
  mat.set = build_setting(m);
  mat.xsph = build_curve(c, path + ".xsph", m["xsph"]);
  mat.specific_heat = m["specific_heat"].get<double>();
  mat.conductivity = m["conductivity"].get<double>();
  mat.elasticity = build_curve(c, path + ".elasticity", m["elasticity"]);
  if (m.contains("relaxation_time")) {  // not with the elastoviscoplastic form (scene.cpp drops it)
    mat.relaxation_time = build_curve(c, path + ".relaxation_time", m["relaxation_time"]);
    if (!positive_at_every_temperature(mat.relaxation_time))
      c.fail(path + ".relaxation_time", "must stay above 0 s at every temperature");
  }
  mat.moisture = build_pore_water(c, path, m, oven);
  if (m.contains("herschel_bulkley")) {
    const json& hb = m["herschel_bulkley"];
    sph::Material::YieldFlow flow;
    flow.yield_stress = build_curve(c, path + ".herschel_bulkley.yield_stress", hb["yield_stress"]);
    flow.flow_index = hb["flow_index"].get<double>();
    if (hb.contains("regularisation_rate")) flow.regularisation = hb["regularisation_rate"].get<double>();
    flow.elastoviscoplastic = hb["form"].get<std::string>() == "elastoviscoplastic";
    if (flow.elastoviscoplastic && !positive_at_every_temperature(mat.elasticity))
      c.fail(path + ".herschel_bulkley.form",
             "\"elastoviscoplastic\" needs the material's elasticity (mu_e = 2 G, the elastic solid below the yield "
             "stress) above 0 Pa at every temperature");
    mat.yield_flow = flow;
  }
  return mat;
}

sph::BubbleSpec build_bubbles(const Ctx& c, const std::string& path, const json& bj) {
  sph::BubbleSpec bs;
  bs.fraction = bj["fraction"].get<double>();
  bs.distribution = parse_distribution(bj["distribution"].get<std::string>());
  bs.seed = bj["seed"].get<std::uint64_t>();
  bs.layers = bj["layers"].get<int>();
  if (bj.contains("region"))
    bs.region = build_shape(c, path + ".region", bj["region"]);
  else if (bs.distribution == sph::BubbleDistribution::region && bs.fraction > 0)
    c.fail(path, "distribution \"region\" needs a region shape");
  if (!bj["pressure_scale"].is_null()) bs.pressure_scale = bj["pressure_scale"].get<double>();
  bs.max_expansion = bj["max_expansion"].get<double>();
  bs.end_temperature = bj["end_temperature"].get<double>();
  bs.contract_on_cooling = bj["contract_on_cooling"].get<bool>();
  bs.vent_at_surface = bj["vent_at_surface"].get<bool>();
  return bs;
}

sph::Settings build_settings(const Ctx& c, const json& doc) {
  const json& sj = doc["solver"]["sph"];
  sph::Settings st;
  st.spacing = sj["spacing"].get<double>();
  st.smoothing_ratio = sj["smoothing_ratio"].get<double>();
  st.search = sph::parse_neighbour_method(sj["neighbour_search"].get<std::string>());
  st.neighbour_skin = sj["neighbour_skin"].get<double>();
  st.clamp_negative_pressure = sj["negative_pressure"].get<std::string>() == "clamp";
  st.wall_density_correction = sj["wall_correction"].get<bool>();
  st.av_alpha = sj["artificial_viscosity"]["alpha"].get<double>();
  st.av_beta = sj["artificial_viscosity"]["beta"].get<double>();
  st.av_epsilon = sj["artificial_viscosity"]["epsilon"].get<double>();
  st.surface_threshold = sj["surface_threshold"].get<double>();
  st.heat_conduction = sj["heat_conduction"].get<bool>();
  st.corrected_laplacian = sj["corrected_laplacian"].get<bool>();
  st.conduction_factor = sj["conduction_factor"].get<double>();
  st.heat_own_step = sj["heat_step"].get<std::string>() == "own";
  st.viscous_factor = sj["viscous_factor"].get<double>();
  st.force_factor = sj["force_factor"].get<double>();
  st.surface_method = sph::parse_surface_method(sj["surface"]["method"].get<std::string>());
  st.surface_colour_threshold = sj["surface"]["colour_threshold"].get<double>();
  st.surface_hull_threshold = sj["surface"]["hull_threshold"].get<double>();
  st.surface_every = sj["surface"]["every_steps"].get<int>();
  // The colour test runs every step (it is cheap and the exchange areas need it):
  // a spacing between detections would be silently ignored.
  if (st.surface_method == sph::SurfaceMethod::colour && st.surface_every != 1)
    c.fail("solver.sph.surface.every_steps",
           "spaces the \"convex_hull\" detections only; the \"colour\" method runs every step");
  st.surface_open_space = sj["surface"]["open_space"].get<bool>();
  st.viscosity_solver = sph::parse_viscosity_solver(sj["viscosity_solver"].get<std::string>());
  st.stress_viscosity = sj["viscosity_operator"].get<std::string>() == "stress";
  if (st.stress_viscosity && st.viscosity_solver == sph::ViscositySolver::explicit_euler)
    c.fail("solver.sph.viscosity_operator",
           "\"stress\" is solved implicitly: set viscosity_solver to implicit or auto");
  st.implicit_elasticity = sj["elasticity_solver"].get<std::string>() == "implicit";
  if (st.implicit_elasticity && st.viscosity_solver == sph::ViscositySolver::explicit_euler)
    c.fail("solver.sph.elasticity_solver",
           "\"implicit\" solves the elastic increment with the implicit viscosity: set viscosity_solver to implicit or "
           "auto");
  const json& aj = sj["adaptive_smoothing"];
  st.adaptive.enabled = aj["enabled"].get<bool>();
  st.adaptive.geometric_mean = aj["reference"].get<std::string>() == "geometric_mean";
  st.adaptive.sensitivity = aj["sensitivity"].get<double>();
  st.adaptive.scale = aj["scale"].get<double>();
  st.adaptive.min_ratio = aj["range"][0].get<double>();
  st.adaptive.max_ratio = aj["range"][1].get<double>();
  if (st.adaptive.min_ratio > st.adaptive.max_ratio)
    c.fail("solver.sph.adaptive_smoothing.range", "the lower limit exceeds the upper one");
  st.artificial_stress = sj["artificial_stress"]["epsilon"].get<double>();
  st.artificial_stress_exponent = sj["artificial_stress"]["exponent"].get<double>();
  if (sj["pressure_solver"].get<std::string>() == "divergence_free")
    st.pressure_solver = sph::PressureSolver::divergence_free;
  st.density_tolerance = sj["pressure_solve"]["density_tolerance"].get<double>();
  st.divergence_tolerance = sj["pressure_solve"]["divergence_tolerance"].get<double>();
  st.pressure_max_iterations = sj["pressure_solve"]["max_iterations"].get<int>();
  st.implicit_tolerance = sj["implicit_viscosity"]["tolerance"].get<double>();
  st.implicit_max_iterations = sj["implicit_viscosity"]["max_iterations"].get<int>();
  st.cfl = doc["solver"]["cfl"].get<double>();
  st.max_dt = doc["solver"]["max_dt"].get<double>();
  return st;
}

}  // namespace

sph::Setup build_sph_setup(const Ctx& c, json& doc, const SceneParts& parts) {
  sph::Setup setup;
  for (const std::string& name : parts.material_names)
    setup.materials.push_back(build_material(c, name, doc["materials"][name], parts.world.oven));
  Real max_initial_speed = 0;
  for (std::size_t i = 0; i < parts.bodies.size(); ++i) {
    const json& b = doc["bodies"][i];
    sph::Body body;
    static_cast<BodyBase&>(body) = parts.bodies[i];
    body.hold_temperature = b["hold_temperature"].get<bool>();
    body.bubbles = build_bubbles(c, fmt::format("bodies[{}].bubbles", i), b["bubbles"]);
    max_initial_speed = std::max(max_initial_speed, body.velocity.norm());
    setup.bodies.push_back(std::move(body));
  }
  sph::Settings& st = setup.settings;
  st = build_settings(c, doc);
  if (parts.world.mass_scaling.active() && st.pressure_solver == sph::PressureSolver::divergence_free)
    c.fail("solver.mass_scaling",
           "mass scaling works with the weakly compressible pressure only (the divergence-free solve holds the "
           "density by the true inertia): leave it at 1 or use solver.sph.pressure_solver \"weakly_compressible\"");
  // Rising bubbles press by a gas law: their density is what the law
  // balances, not a rest density a solve could hold.
  if (st.pressure_solver == sph::PressureSolver::divergence_free)
    for (std::size_t i = 0; i < setup.bodies.size(); ++i)
      if (setup.bodies[i].bubbles.fraction > 0)
        c.fail("solver.sph.pressure_solver",
               fmt::format("\"divergence_free\" holds every particle at its rest density, but bodies[{}] has "
                           "bubbles (a gas pressure law): use \"weakly_compressible\"",
                           i));
  // About 1.5 kB a particle with its neighbour lists (about 40 pairs of index,
  // distance and kernel values) and per-step scratch.
  double points = 0;
  for (const auto& b : setup.bodies) points += lattice_points(b.shape, st.spacing);
  if (points > 2e9)
    c.fail("solver.sph.spacing", fmt::format("the bodies would hold about {:.3g} particles at this spacing (at most "
                                             "2e9)",
                                             points));
  require_memory(c, "solver.sph.spacing", 1500.0 * points,
                 fmt::format("about {:.3g} particles at spacing {} m", points, st.spacing));
  static_cast<World&>(setup) = parts.world;

  const json& sj = doc["solver"]["sph"];
  if (sj["speed_of_sound"].is_string()) {
    // auto: ten times the fastest flow expected, so density varies ~1%.
    const Real g = setup.gravity.norm();
    const Real height = g > 0 ? std::abs(setup.domain.extent().dot(setup.gravity / g)) : 0.0;
    const Real v = std::max({std::sqrt(2.0 * g * height), max_initial_speed, 0.1});
    st.speed_of_sound = 10.0 * v;
    doc["solver"]["sph"]["speed_of_sound"] = st.speed_of_sound;
  } else {
    st.speed_of_sound = sj["speed_of_sound"].get<double>();
  }

  const Real h = st.spacing * st.smoothing_ratio;
  // A neighbour must be found once: along a periodic axis the box is longer
  // than two of the largest supports.
  const Real h_max = h * (st.adaptive.enabled ? std::max(Real(1), st.adaptive.max_ratio) : Real(1));
  for (int k = 0; k < 3; ++k)
    if (setup.periodic[std::size_t(k)] && setup.domain.extent()[k] <= 2.0 * h_max)
      c.fail("domain.periodic",
             fmt::format("the domain is {:.4g} m long along the periodic axis {}, which must exceed two smoothing "
                         "supports ({:.4g} m): make it longer or the spacing smaller",
                         setup.domain.extent()[k], char('x' + k), 2.0 * h_max));
  for (std::size_t i = 0; i < doc["colliders"].size(); ++i) {
    const json& cj = doc["colliders"][i];
    Collider col = build_collider(c, cj, i, h, FrictionModel::velocity_share, parts.world.oven);
    if (cj.contains("motion") && std::holds_alternative<MeshCollider>(col.geometry))
      c.fail(fmt::format("colliders[{}].motion", i),
             "moving mesh colliders are available for the MPM solver only (SPH moves analytic colliders: plane, "
             "box, container, cylinder, cup)");
    setup.colliders.push_back(std::move(col));
  }
  return setup;
}

}  // namespace bakesim::scene_parts
