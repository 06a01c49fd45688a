#include "io/run_meshes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/errors.hpp"
#include "io/files.hpp"
#include "io/mesh_files.hpp"
#include "io/ply_reader.hpp"
#include "io/run_directory.hpp"
#include "io/schema.hpp"
#include "io/scene_parts.hpp"
#include "mpm/setup.hpp"
#include "geometry/collider_mesh.hpp"

namespace bakesim {

namespace fs = std::filesystem;
using nlohmann::json;

RunGeometry run_geometry(const json& scene) {
  RunGeometry g;
  g.solver = scene.at("solver").at("type").get<std::string>();
  if (g.solver == "mpm") {
    const json& m = scene.at("solver").at("mpm");
    g.spacing = m.at("cell_size").get<double>() / mpm::points_per_cell_axis(m.at("particles_per_cell").get<double>());
  } else {
    g.spacing = scene.at("solver").at("sph").at("spacing").get<double>();
  }
  for (const auto& [name, material] : scene.at("materials").items()) {
    g.rest_density.push_back(material.at("density").get<double>());
    const json raw = material.value("raw_colour", json());  // runs written before it: the dough's
    g.raw_colour.push_back(raw.is_array() && raw.size() == 3
                               ? surface::Lab{raw[0].get<double>(), raw[1].get<double>(), raw[2].get<double>()}
                               : surface::dough_lab());
  }
  const json& domain = scene.at("domain");
  g.domain = {scene_parts::vec3(domain.at("min")), scene_parts::vec3(domain.at("max"))};
  for (const auto& axis : domain.value("periodic", json::array()))
    g.periodic[std::size_t(axis.get<std::string>().at(0) - 'x')] = true;
  return g;
}

MeshSettings mesh_settings(const json& m) {
  MeshSettings s;
  s.surface.method = surface::parse_surface_method(m.at("method").get<std::string>());
  s.surface.voxel_ratio = m.at("voxel_ratio").get<double>();
  s.colour = m.at("colour").get<std::string>();
  s.ply = s.obj = false;
  s.vdb = false;
  for (const auto& f : m.at("formats")) {
    const std::string name = f.get<std::string>();
    (name == "ply" ? s.ply : name == "obj" ? s.obj : s.vdb) = true;
  }
  return s;
}

namespace {
// A scalar or integer attribute as reals (frames read back from PLY carry every
// non-vector property as a scalar; a live particle set keeps its integers).
std::optional<std::vector<Real>> attribute_values(const ParticleSet& ps, const std::string& name) {
  for (const auto& a : ps.scalars())
    if (a.info.name == name) return a.data;
  for (const auto& a : ps.integers())
    if (a.info.name == name) return std::vector<Real>(a.data.begin(), a.data.end());
  return std::nullopt;
}
}  // namespace

std::vector<Real> particle_values(const ParticleSet& ps, const std::string& q) {
  if (auto v = attribute_values(ps, q)) return *v;
  if (q == "speed" && ps.has("velocity")) {
    std::vector<Real> v;
    for (const Vec3& u : ps.vector("velocity")) v.push_back(u.norm());
    return v;
  }
  std::string known;
  for (const auto& a : ps.scalars()) known += (known.empty() ? "" : ", ") + a.info.name;
  throw InputError("colour", fmt::format("the frames have no quantity '{}' (they have: {}{})", q, known,
                                         ps.has("velocity") ? ", speed" : ""));
}

std::pair<Real, Real> colour_range(const ParticleSet& ps, const std::string& q,
                                   const std::optional<std::pair<Real, Real>>& given) {
  if (given) return *given;
  if (q == "browning" || q == "saturation") return {0.0, 1.0};
  if (q == "temperature") return {20.0, 220.0};
  const std::vector<Real> v = particle_values(ps, q);
  if (v.empty()) return {0.0, 1.0};
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return {*lo, *hi > *lo ? *hi : *lo + 1.0};
}

surface::Palette colour_palette(const std::string& q) {
  return q == "browning" ? surface::Palette::baking : surface::Palette::heat;
}

surface::SurfaceParticles surface_particles(const ParticleSet& ps, const RunGeometry& run) {
  surface::SurfaceParticles s;
  s.spacing = run.spacing;
  s.position = ps.vector("position");
  s.density_ratio.assign(ps.size(), 1.0);
  const auto jacobian = attribute_values(ps, "J"), density = attribute_values(ps, "density");
  if (run.solver == "mpm" && jacobian) {
    s.density_ratio = *jacobian;  // ρ0/ρ = J
  } else if (density) {
    const auto& rho = *density;
    const auto mat = attribute_values(ps, "material_id");
    for (std::size_t i = 0; i < ps.size(); ++i) {
      std::size_t m = mat ? std::size_t(std::max(0.0, (*mat)[i])) : 0;
      if (m >= run.rest_density.size()) m = 0;
      const Real rest = run.rest_density.empty() ? rho[i] : run.rest_density[m];
      s.density_ratio[i] = rho[i] > 0 ? rest / rho[i] : 1.0;
    }
  }
  return s;
}

namespace {
// Samples at the particles, weighted by their volumes m/ρ = s³ ρ₀/ρ; values to be filled.
surface::ColourSamples samples_at(const surface::SurfaceParticles& sp, const RunGeometry& run) {
  surface::ColourSamples samples;
  samples.position = sp.position;
  const Real cell = run.spacing * run.spacing * run.spacing;
  samples.volume.resize(sp.position.size());
  for (std::size_t i = 0; i < sp.position.size(); ++i) samples.volume[i] = cell * sp.density_ratio[i];
  return samples;
}
}  // namespace

surface::ColourSamples colour_samples(const ParticleSet& ps, const RunGeometry& run, const MeshSettings& settings) {
  surface::ColourSamples samples = samples_at(surface_particles(ps, run), run);
  const auto [lo, hi] = colour_range(ps, settings.colour, settings.range);
  samples.value = particle_values(ps, settings.colour);
  for (Real& v : samples.value) v = (v - lo) / (hi - lo);
  if (const auto bubble = attribute_values(ps, "bubble"))
    for (Real b : *bubble) samples.bubble.push_back(b != 0 ? 1 : 0);
  if (settings.colour == "browning") samples.raw = particle_raw_colours(ps, run);
  // Browning is the surface's own colour: the SPH surface particles (exchange area > 0) show it.
  if (settings.colour == "browning")
    if (const auto area = attribute_values(ps, "surface_area"))
      for (Real a : *area) samples.face.push_back(a > 0 ? 1 : 0);
  return samples;
}

std::vector<surface::Lab> particle_raw_colours(const ParticleSet& ps, const RunGeometry& run) {
  std::vector<surface::Lab> raw;
  const auto material = attribute_values(ps, "material_id");
  const bool own_colours = std::any_of(run.raw_colour.begin(), run.raw_colour.end(), [](const surface::Lab& c) {
    return surface::lab_distance(c, surface::dough_lab()) > 0;
  });
  if (!material || !own_colours) return raw;
  raw.reserve(material->size());
  for (Real m : *material) {
    const std::size_t k = std::size_t(std::max(0.0, m));
    raw.push_back(k < run.raw_colour.size() ? run.raw_colour[k] : surface::dough_lab());
  }
  return raw;
}

surface::ColourSamples pore_samples(const ParticleSet& ps, const RunGeometry& run) {
  const surface::SurfaceParticles sp = surface_particles(ps, run);
  surface::ColourSamples samples = samples_at(sp, run);
  const auto bubble = attribute_values(ps, "bubble");
  samples.value.resize(ps.size());
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const bool gas = bubble && (*bubble)[i] != 0;
    samples.value[i] = gas ? 1.0 : std::max(0.0, 1.0 - 1.0 / std::max(sp.density_ratio[i], 1e-9));
  }
  return samples;
}

surface::SurfaceMesh frame_mesh(const ParticleSet& ps, const RunGeometry& run, const MeshSettings& settings) {
  surface::SurfaceMesh mesh = surface::reconstruct_surface(surface_particles(ps, run), settings.surface);
  surface::assign_uv(mesh, colour_samples(ps, run, settings), kColourSupport * run.spacing);
  surface::colour_vertices(mesh, colour_palette(settings.colour));
  return mesh;
}

void write_frame_mesh(const fs::path& dir, int frame, const surface::SurfaceMesh& mesh, const MeshSettings& settings) {
  ensure_directory(dir);
  const std::string stem = frame_stem(frame);
  if (settings.ply) write_file_atomic(dir / (stem + ".ply"), encode_mesh_ply(mesh));
  if (settings.obj) {
    const std::string palette = colour_palette(settings.colour) == surface::Palette::baking ? "baking" : "heat";
    const std::string texture = "gradient_" + palette + ".png", material = "bakesim_" + palette;
    if (!fs::exists(dir / texture))
      write_file_atomic(dir / texture, encode_png(gradient_texture(colour_palette(settings.colour))));
    write_file_atomic(dir / (material + ".mtl"), encode_mtl(material, texture));
    write_file_atomic(dir / (stem + ".obj"), encode_mesh_obj(mesh, material + ".mtl", material));
  }
}

void write_frame_vdb(const fs::path& dir, int frame, const ParticleSet& ps, const RunGeometry& run,
                     const MeshSettings& settings) {
  ensure_directory(dir);
  std::vector<surface::VolumeQuantity> quantities;
  const auto add = [&](const std::string& name, const std::string& unit) {
    for (const auto& q : quantities)
      if (q.name == name) return;
    if (auto values = attribute_values(ps, name)) quantities.push_back({name, unit, std::move(*values)});
  };
  add("temperature", "degC");
  add("browning", "");
  add("moisture", "kg/kg");
  add(settings.colour, "");
  write_file_atomic(
      dir / (frame_stem(frame) + ".vdb"),
      surface::encode_vdb(surface_particles(ps, run), settings.surface, quantities, kColourSupport * run.spacing));
}

json read_run_scene(const fs::path& file) {
  json scene;
  try {
    scene = json::parse(read_file(file));
  } catch (const json::exception& e) {
    throw InputError(file.string(), std::string("not valid JSON: ") + e.what());
  }
  // A run written by an older bakesim lacks the keys added since: checked against today's schema, a copy
  // gets their defaults. One the schema no longer takes is read as it was written.
  try {
    json filled = scene;
    scene_schema().validate(filled, file.string());
    return filled;
  } catch (const InputError&) {
    return scene;
  }
}

RunDirectory open_run(const fs::path& dir) {
  RunDirectory r;
  r.dir = dir;
  const fs::path scene = dir / "scene.json";
  if (!fs::is_regular_file(scene))
    throw InputError(dir.string(), "not a run directory (no scene.json; make one with `bakesim run SCENE --out DIR`)");
  r.scene = read_run_scene(scene);
  r.scene_dir = recorded_scene_dir(dir);
  if (fs::is_directory(dir / "frames"))
    for (const auto& entry : fs::directory_iterator(dir / "frames")) {
      const fs::path& p = entry.path();
      if (p.extension() != ".ply") continue;
      if (const auto number = frame_number(p.stem().string())) r.frames[*number] = p;
    }
  return r;
}

ParticleSet read_particle_frame(const fs::path& ply) {
  const std::string bytes = read_file(ply);
  return particles_from_ply(parse_ply(bytes, ply.string()), ply.string());
}

Real frame_rate(const RunDirectory& run) {
  return run.scene.contains("time") ? run.scene["time"].value("fps", 30.0) : 30.0;
}

Real frame_time(const RunDirectory& run, int frame) { return frame / frame_rate(run); }

std::vector<Collider> run_colliders(const RunDirectory& run, std::vector<std::string>& missing) {
  std::vector<Collider> out;
  if (!run.scene.contains("colliders") || !run.scene["colliders"].is_array()) return out;
  const fs::path scene_file = run.dir / "scene.json";
  const scene_parts::Ctx c{scene_file.string(),
                           run.scene_dir.empty() ? fs::absolute(run.dir).parent_path().string() : run.scene_dir};
  const json& list = run.scene["colliders"];
  const Oven oven =
      scene_parts::build_oven(c, run.scene.contains("environment") ? run.scene["environment"] : json::object());
  const Real cell = run_geometry(run.scene).spacing;
  for (std::size_t i = 0; i < list.size(); ++i) {
    try {
      out.push_back(scene_parts::build_collider(c, list[i], i, cell, FrictionModel::velocity_share, oven));
    } catch (const InputError& e) {
      missing.push_back(fmt::format("collider {} not drawn: {}", list[i].value("name", std::to_string(i)), e.what()));
    }
  }
  return out;
}

std::vector<PosedCollider> posed_colliders(const std::vector<Collider>& colliders, Real time, const Aabb& bodies) {
  const Vec3 focus = 0.5 * (bodies.min + bodies.max);
  const Real half_width = 1.5 * std::max(bodies.extent().maxCoeff(), Real(1e-3));
  std::vector<PosedCollider> out;
  for (const Collider& c : colliders) {
    if (c.look == ColliderLook::hidden || std::holds_alternative<InsideBoxCollider>(c.geometry)) continue;
    PosedCollider p;
    p.name = c.name;
    p.look = c.look;
    p.moves = c.motion.moves();
    p.bounded = !std::holds_alternative<PlaneCollider>(c.geometry);
    p.mesh = collider_mesh_at(c, time, focus, half_width);
    if (!p.mesh.triangles.empty()) out.push_back(std::move(p));
  }
  return out;
}

surface::SurfaceMesh collider_surface(const PosedCollider& collider) {
  surface::SurfaceMesh m;
  const TriangleMesh& t = collider.mesh;
  m.vertices.reserve(t.vertices.size());
  for (const Vec3& v : t.vertices) m.vertices.push_back(v.cast<float>());
  for (const auto& tri : t.triangles)
    m.triangles.push_back({std::uint32_t(tri[0]), std::uint32_t(tri[1]), std::uint32_t(tri[2])});
  surface::compute_normals(m);
  // The look's albedo in sRGB (gamma 2.2, as the pictures decode colours).
  const Vec3 albedo = look_albedo(collider.look);
  std::array<std::uint8_t, 3> srgb;
  for (int k = 0; k < 3; ++k) srgb[std::size_t(k)] = std::uint8_t(std::lround(255 * std::pow(albedo[k], 1 / 2.2)));
  m.colours.assign(m.vertices.size(), srgb);
  return m;
}

MeshRunResult mesh_run(const fs::path& dir, const MeshSettings& settings, std::vector<int> frames) {
  // The command line's limits, for every caller (0: the method's own voxel).
  const Real voxel = settings.surface.voxel_ratio;
  if (voxel != 0 && !(voxel >= 0.1 && voxel <= 2))
    throw InputError("mesh --voxel", fmt::format("{} is outside [0.1, 2] particle spacings", voxel));
  if (settings.range && !(settings.range->first < settings.range->second))
    throw InputError("mesh --range",
                     fmt::format("expects LOW < HIGH, got {}, {}", settings.range->first, settings.range->second));
  const RunDirectory run = open_run(dir);
  if (run.frames.empty()) throw InputError(dir.string(), "has no particle frames (frames/NNNNN.ply) to mesh");
  // meshes/ is the run's own folder: not while a run (or another mesh command) writes there.
  const RunDirectoryLock lock = claim_existing_run(dir);
  const RunGeometry geometry = run_geometry(run.scene);
  if (frames.empty())
    for (const auto& [f, path] : run.frames) frames.push_back(f);
  MeshRunResult result;
  for (int f : frames) {
    if (!run.frames.count(f)) throw InputError("mesh --frame", fmt::format("{} has no frame {}", dir.string(), f));
    const ParticleSet ps = read_particle_frame(run.frames.at(f));
    const surface::SurfaceMesh mesh = frame_mesh(ps, geometry, settings);
    const surface::MeshQuality q = surface::check_mesh(mesh);
    write_frame_mesh(run.dir / "meshes", f, mesh, settings);
    if (settings.vdb) write_frame_vdb(run.dir / "meshes", f, ps, geometry, settings);
    result.frames.push_back(f);
    result.triangles += mesh.triangles.size();
    if (!q.closed_and_oriented())
      result.warnings.push_back(fmt::format("frame {} mesh has {} open, {} non-manifold and {} misoriented edges", f,
                                            q.boundary_edges, q.non_manifold_edges, q.misoriented_edges));
  }
  // The colliders beside the bodies: once if they stay put, per frame if they move.
  std::vector<std::string> missing;
  const std::vector<Collider> colliders = run_colliders(run, missing);
  result.warnings.insert(result.warnings.end(), missing.begin(), missing.end());
  if (!colliders.empty() && !frames.empty()) {
    const fs::path out = run.dir / "meshes" / "colliders";
    Aabb first = Aabb::empty_box();
    for (const Vec3& x : read_particle_frame(run.frames.at(frames.front())).vector("position")) first.expand(x);
    for (std::size_t k = 0; k < frames.size(); ++k)
      for (const PosedCollider& p : posed_colliders(colliders, frame_time(run, frames[k]), first)) {
        if (!p.moves && k > 0) continue;
        ensure_directory(out);
        const std::string file = p.moves ? fmt::format("{}-{}.ply", output_component(p.name), frame_stem(frames[k]))
                                         : output_component(p.name) + ".ply";
        write_file_atomic(out / file, encode_mesh_ply(collider_surface(p)));
        ++result.collider_files;
      }
  }
  return result;
}

}  // namespace bakesim
