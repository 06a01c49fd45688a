#pragma once
// Surface reconstruction from particles (thesis 3.5, spec sph-baking.md
// features 18–19) and per-vertex colouring (thesis 4.4).
//
// Two methods, both polygonised by OpenVDB's volume-to-mesh (a marching-cubes
// family polygoniser; its quads are split into triangles):
//   levelset  (default) each particle is a sphere of radius 1.5 s·c_i
//             rasterised into a narrow-band level set (union), meshed at the
//             level −s·c̄ (an erosion): a morphological closing that smooths the
//             sphere bumps and leaves the surface half a spacing outside the
//             outer particle centres, where the material boundary is.
//   wyvill    the thesis's field: φ(x) = Σ_i φ_W(|x − x_i|, b_i) with the
//             Wyvill–McPheeters–Wyvill polynomial (Eq 3.59) and the
//             density-adaptive radius b_i = α + β ρ0/ρ_i (Eq 3.60), meshed at
//             half the field value inside material at rest.
// Here s is the initial particle spacing and c_i = (ρ0/ρ_i)^{1/3} the linear
// expansion of particle i (SPH: rest over current density; MPM: J^{1/3}).
#include <array>
#include <memory>
#include <cstdint>
#include <string>
#include <optional>
#include <vector>

#include "core/types.hpp"
#include "surface/crust_colour.hpp"

namespace bakesim::surface {

struct SurfaceMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3f> normals;                 // area-weighted vertex normals, unit length
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from outside
  std::vector<float> uv;                                // per vertex U = V (thesis Eq 4.5)
  std::vector<std::array<std::uint8_t, 3>> colours;     // per vertex sRGB
  // Per vertex, the raw colour of the food there (materials' raw_colour, blended
  // where two meet); empty: the dough's. The baking palette browns from it.
  std::vector<Lab> raw_colour;
};

struct SurfaceParticles {
  std::vector<Vec3> position;
  std::vector<Real> density_ratio;  // ρ0/ρ per particle (1 at rest, > 1 expanded)
  Real spacing = 0.01;              // initial particle spacing s, m
};

enum class SurfaceMethod { levelset, wyvill };
SurfaceMethod parse_surface_method(const std::string& name);  // throws InputError
std::string to_string(SurfaceMethod m);

struct SurfaceOptions {
  SurfaceMethod method = SurfaceMethod::levelset;
  Real voxel_ratio = 0;  // voxel size / s; 0: the method's default (levelset 0.75, wyvill 0.5)
  // levelset
  Real sphere_radius = 1.5;      // × s c_i
  int smoothing_iterations = 4;  // mean-curvature flow steps before meshing (flatten lattice bands; docs/surfaces.md)
  // wyvill (Eq 3.60: b_i = (α + β ρ0/ρ_i) s)
  Real wyvill_alpha = 1.0;
  Real wyvill_beta = 1.0;
};

// A closed, consistently oriented triangle mesh (no colours yet). Empty when
// there are no particles.
SurfaceMesh reconstruct_surface(const SurfaceParticles& particles, const SurfaceOptions& options);

// One frame as OpenVDB volumes (`bakesim mesh --vdb`, output.mesh.formats
// "vdb"), the bytes of a .vdb file written by OpenVDB's own I/O:
//   "surface"   the level set the levelset method meshes (class level set,
//               world units, negative inside), whatever options.method says;
//   one float grid per quantity, named as given (e.g. "temperature" in °C),
//   the Shepard-normalised cubic-spline average of the particles' values
//   (support `support`, weights m/ρ) at every voxel within the support of a
//   particle: the body's inside and a band around it are active.
// All grids share the level set's transform (voxel = voxel_ratio × spacing).
struct VolumeQuantity {
  std::string name;
  std::string unit;
  std::vector<Real> value;  // one per particle
};
std::string encode_vdb(const SurfaceParticles& particles, const SurfaceOptions& options,
                       const std::vector<VolumeQuantity>& quantities, Real support);

// Area-weighted unit vertex normals from the triangles.
void compute_normals(SurfaceMesh& mesh);

// The Wyvill–McPheeters–Wyvill field of one particle (Eq 3.59 with a = 1).
inline Real wyvill_field(Real r, Real b) {
  if (r >= b) return 0;
  const Real q = (r * r) / (b * b);
  return 1.0 - (4.0 / 9.0) * q * q * q + (17.0 / 9.0) * q * q - (22.0 / 9.0) * q;
}
// Field value deep inside material at rest sampled at spacing s with radius b:
// (b/s)³ 4π ∫₀¹ φ_W(t) t² dt. The wyvill method meshes at half of it.
Real wyvill_interior_value(Real radius_over_spacing);

// Colouring (thesis Eq 4.5–4.7): every vertex gets U = the Shepard-normalised
// SPH sum of G over the particles within `support` (cubic spline kernel), with
//   G_j = O_j + 0.8 value_j + 0.05,  O_j = 0 for bubble particles, 0.1 otherwise,
// where value_j ∈ [0, 1] is the normalised quantity (browning index, or
// (T − T0)/(Tf − T0) for temperature). Vertices with no particle within the
// support take their nearest particle's G.
struct ColourSamples {
  std::vector<Vec3> position;
  std::vector<Real> volume;          // m_j / ρ_j
  std::vector<Real> value;           // normalised to [0, 1]
  std::vector<std::uint8_t> bubble;  // 1 for bubble particles (may be empty)
  // 1 for the particles that form the surface (SPH: exchange area > 0), when
  // the colour is the surface's own (browning); may be empty. A vertex with
  // such particles within the support takes its colour from them alone: the
  // crust is one particle thick and the unbrowned crumb under it is not seen.
  std::vector<std::uint8_t> face;
  // The raw colour of each particle's material (CIE L*a*b*), for the baking
  // palette; may be empty (every particle the dough's colour).
  std::vector<Lab> raw;
};
void assign_uv(SurfaceMesh& mesh, const ColourSamples& samples, Real support);

// The same U at any point (the cut face of `bakesim render --cut`): built once
// over the samples, queried from many threads at once.
class ColourField {
 public:
  ColourField(ColourSamples samples, Real support);
  ~ColourField();
  ColourField(const ColourField&) = delete;
  ColourField& operator=(const ColourField&) = delete;
  Real uv_at(const Vec3& x) const;
  // The Shepard sum alone: none when no sample lies within the support.
  std::optional<Real> uv_within(const Vec3& x) const;
  // The samples' own values (clamped to [0, 1]) by the same Shepard sum, the
  // nearest sample's where none lies within the support; 0 without samples
  // (the cut face's pore share).
  Real value_at(const Vec3& x) const;
  // The samples' raw colours by the same Shepard sum (the nearest sample's
  // where none lies within the support); none when the samples carry none.
  std::optional<Lab> raw_at(const Vec3& x) const;

 private:
  struct Index;
  // Σ w_j g(j) / Σ w_j over the samples within the support (Eq 4.5's weights).
  template <class R, class G>
  std::optional<R> shepard(const Vec3& x, const G& g) const;
  std::size_t nearest(const Vec3& x) const;
  ColourSamples samples_;
  Real support_;
  std::unique_ptr<Index> index_;
};

// Colour maps from a value fraction ∈ [0, 1] to sRGB: baking is the measured
// crust colour at browning index B = u (crust_colour.hpp), heat blue → red.
enum class Palette { baking, heat };
std::array<std::uint8_t, 3> palette_colour(Palette p, Real u);
// The baking palette for a food of raw colour `raw` (crust_lab_of_browning).
std::array<std::uint8_t, 3> baking_colour(const Lab& raw, Real u);
// The value fraction a colouring coordinate U (Eq 4.7, G = O + 0.8 v + 0.05)
// stands for, read as dough's (O = 0.1): v = (U − 0.15) / 0.8 in [0, 1], so a
// mesh shows a value in the colour the particles and the colour bar show it;
// bubble particles' O = 0 still draws them an eighth of the scale paler.
Real value_of_colour_coordinate(Real u);
void colour_vertices(SurfaceMesh& mesh, Palette p);  // colours from uv (and raw_colour: baking)

// Checks used by tests and by `bakesim mesh` to report on what it wrote.
struct MeshQuality {
  std::size_t boundary_edges = 0;      // edges with one triangle
  std::size_t non_manifold_edges = 0;  // edges with more than two
  std::size_t misoriented_edges = 0;   // shared edges walked the same way by both triangles
  Real volume = 0;                     // enclosed (divergence theorem), m³
  Real area = 0;
  bool closed_and_oriented() const { return boundary_edges == 0 && non_manifold_edges == 0 && misoriented_edges == 0; }
};
MeshQuality check_mesh(const SurfaceMesh& mesh);

// Symmetric Hausdorff distance between two meshes' vertex sets (the vertices
// of a fine mesh sample its surface to within a voxel), m.
Real hausdorff_distance(const SurfaceMesh& a, const SurfaceMesh& b);

}  // namespace bakesim::surface
