#pragma once
// Surfaces of a run's frames: what `bakesim mesh RUN_DIR` and the scene's
// output.mesh option write into RUN_DIR/meshes/:
//   NNNNN.ply               binary PLY: positions, normals, colours, UVs (s, t)
//   NNNNN.obj + bakesim.mtl OBJ with vertex colours and UVs; the material maps
//                           gradient_<palette>.png (the thesis's gradient texture)
#include <array>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "geometry/colliders.hpp"
#include "surface/surface.hpp"

namespace bakesim {

// What meshing needs to know about a run, read from its resolved scene.
struct RunGeometry {
  std::string solver;                    // "sph" or "mpm"
  Real spacing = 0.01;                   // initial particle spacing, m
  std::vector<Real> rest_density;        // SPH: by material id (materials in name order)
  std::vector<surface::Lab> raw_colour;  // by material id: its raw_colour, the dough's where none
  Aabb domain;                           // the domain box, its walls on its faces
  std::array<bool, 3> periodic{};        // axes without walls (domain.periodic)
};
RunGeometry run_geometry(const nlohmann::json& resolved_scene);

struct MeshSettings {
  surface::SurfaceOptions surface;
  std::string colour = "browning";             // particle quantity the surface is coloured by
  std::optional<std::pair<Real, Real>> range;  // value range mapped to [0, 1]; default per quantity
  bool ply = true, obj = true;
  bool vdb = false;  // NNNNN.vdb beside them (write_frame_vdb)
};
MeshSettings mesh_settings(const nlohmann::json& output_mesh);  // from the scene's output.mesh

// Default value range of a colouring quantity: browning [0, 1], temperature
// [20, 220] °C, saturation [0, 1], anything else the frame's min and max.
std::pair<Real, Real> colour_range(const ParticleSet& particles, const std::string& quantity,
                                   const std::optional<std::pair<Real, Real>>& given);
surface::Palette colour_palette(const std::string& quantity);
// Per-particle value of a quantity (scalar attribute, or speed).
std::vector<Real> particle_values(const ParticleSet& particles, const std::string& quantity);

surface::SurfaceParticles surface_particles(const ParticleSet& particles, const RunGeometry& run);
// Colours are smoothed over this many particle spacings (Eq 4.5's support).
inline constexpr Real kColourSupport = 2.0;
// The particles' colouring samples (thesis Eq 4.5-4.7) of `settings.colour`.
surface::ColourSamples colour_samples(const ParticleSet& particles, const RunGeometry& run,
                                      const MeshSettings& settings);
// The pore gas share of each particle, as samples for the cut face's crumb
// (RenderSettings::cut_pore_fraction): 1 for SPH bubble particles, else the
// share of its volume the dough gained, max(0, 1 − 1/J) (J = ρ₀/ρ in SPH, det F
// in MPM): the pores the rise opened. The gas the dough held before it rose is
// not in the frames and is left out.
surface::ColourSamples pore_samples(const ParticleSet& ps, const RunGeometry& run);
// Each particle's raw food colour (its material's raw_colour), what browning starts from; empty where every
// material is the dough's colour (or the frames carry no material ids).
std::vector<surface::Lab> particle_raw_colours(const ParticleSet& ps, const RunGeometry& run);
// Meshes and colours one frame.
surface::SurfaceMesh frame_mesh(const ParticleSet& particles, const RunGeometry& run, const MeshSettings& settings);
// Writes NNNNN.ply / NNNNN.obj (and the material and texture) into `meshes_dir`, atomically.
void write_frame_mesh(const std::filesystem::path& meshes_dir, int frame, const surface::SurfaceMesh& mesh,
                      const MeshSettings& settings);

// NNNNN.vdb into `meshes_dir`, atomically (surface::encode_vdb): the level set
// "surface" and the float grids "temperature" (°C), "browning", "moisture"
// (kg water per kg dry matter) where the frame has them, and the colouring
// quantity if it is another.
void write_frame_vdb(const std::filesystem::path& meshes_dir, int frame, const ParticleSet& particles,
                     const RunGeometry& run, const MeshSettings& settings);

// A finished (or running) run directory.
struct RunDirectory {
  std::filesystem::path dir;
  nlohmann::json scene;                         // scene.json, resolved
  std::map<int, std::filesystem::path> frames;  // frame number → frames/NNNNN.ply
  std::string scene_dir;                        // where the scene's mesh paths resolve ("" unknown)
};
RunDirectory open_run(const std::filesystem::path& dir);  // InputError when it is not a run directory
// A run's resolved scene.json, with the defaults of keys added since the run was written (checked against
// today's schema; as written when the schema no longer takes it). InputError when it is not JSON.
nlohmann::json read_run_scene(const std::filesystem::path& file);
ParticleSet read_particle_frame(const std::filesystem::path& ply);
// The scene's frames per simulated second (time.fps) and the simulated time of a frame.
Real frame_rate(const RunDirectory& run);
Real frame_time(const RunDirectory& run, int frame);

// The run's colliders as its scene builds them. A mesh collider whose file
// is no longer where the scene was (relative paths resolve in the recorded
// scene directory, else beside the run directory) is left out, with a line
// in `missing` saying so.
std::vector<Collider> run_colliders(const RunDirectory& run, std::vector<std::string>& missing);

// A collider drawn or exported at one time (geometry/collider_mesh.hpp): planes
// as a slab under the bodies, three body sizes across; domain walls and hidden
// colliders are left out.
struct PosedCollider {
  std::string name;
  ColliderLook look = ColliderLook::metal;
  bool moves = false;   // scripted motion: its mesh differs from frame to frame
  bool bounded = true;  // false for planes (their slab's size is arbitrary)
  TriangleMesh mesh;
};
std::vector<PosedCollider> posed_colliders(const std::vector<Collider>& colliders, Real time, const Aabb& bodies);
// The look's colour (sRGB) on every vertex, area-weighted vertex normals.
surface::SurfaceMesh collider_surface(const PosedCollider& collider);

// `bakesim mesh RUN_DIR`: meshes `frames` (all the run's frames when empty)
// into RUN_DIR/meshes/, holding the run directory's lock while it writes; the
// colliders into RUN_DIR/meshes/colliders/: NAME.ply once for one that stays
// put, NAME-NNNNN.ply per frame for one that moves (planes' slabs sized to the
// first meshed frame's bodies).
struct MeshRunResult {
  std::vector<int> frames;
  std::size_t triangles = 0;
  std::vector<std::string> warnings;  // frames whose mesh is not closed and oriented; colliders left out
  std::size_t collider_files = 0;
};
MeshRunResult mesh_run(const std::filesystem::path& dir, const MeshSettings& settings, std::vector<int> frames = {});

}  // namespace bakesim
