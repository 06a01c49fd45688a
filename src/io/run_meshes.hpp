#pragma once
// Surfaces of a run's frames: what `bakesim mesh RUN_DIR` and the scene's
// output.mesh option write into RUN_DIR/meshes/:
//   NNNNN.ply               binary PLY: positions, normals, colours, UVs (s, t)
//   NNNNN.obj + bakesim.mtl OBJ with vertex colours and UVs; the material maps
//                           gradient_<palette>.png (the thesis's gradient texture)
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/particles.hpp"
#include "surface/surface.hpp"

namespace bakesim {

// What meshing needs to know about a run, read from its resolved scene.
struct RunGeometry {
  std::string solver;              // "sph" or "mpm"
  Real spacing = 0.01;             // initial particle spacing, m
  std::vector<Real> rest_density;  // SPH: by material id (materials in name order)
};
RunGeometry run_geometry(const nlohmann::json& resolved_scene);

struct MeshSettings {
  surface::SurfaceOptions surface;
  std::string colour = "browning";             // particle quantity the surface is coloured by
  std::optional<std::pair<Real, Real>> range;  // value range mapped to [0, 1]; default per quantity
  bool ply = true, obj = true;
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
// Meshes and colours one frame.
surface::SurfaceMesh frame_mesh(const ParticleSet& particles, const RunGeometry& run, const MeshSettings& settings);
// Writes NNNNN.ply / NNNNN.obj (and the material and texture) into `meshes_dir`, atomically.
void write_frame_mesh(const std::filesystem::path& meshes_dir, int frame, const surface::SurfaceMesh& mesh,
                      const MeshSettings& settings);

// A finished (or running) run directory.
struct RunDirectory {
  std::filesystem::path dir;
  nlohmann::json scene;                         // scene.json, resolved
  std::map<int, std::filesystem::path> frames;  // frame number → frames/NNNNN.ply
};
RunDirectory open_run(const std::filesystem::path& dir);  // InputError when it is not a run directory
ParticleSet read_particle_frame(const std::filesystem::path& ply);

// `bakesim mesh RUN_DIR`: meshes `frames` (all the run's frames when empty)
// into RUN_DIR/meshes/, holding the run directory's lock while it writes.
struct MeshRunResult {
  std::vector<int> frames;
  std::size_t triangles = 0;
  std::vector<std::string> warnings;  // frames whose mesh is not closed and oriented
};
MeshRunResult mesh_run(const std::filesystem::path& dir, const MeshSettings& settings, std::vector<int> frames = {});

}  // namespace bakesim
