#pragma once
// Solid shapes that bodies are made of, and their sampling into particles.
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "geometry/mesh.hpp"

namespace bakesim {

struct BoxShape {
  Vec3 min, max;
};
struct SphereShape {
  Vec3 center;
  Real radius;
};
// A finite right circular cylinder; `center` is the middle of its axis.
struct CylinderShape {
  Vec3 center;
  Vec3 axis;  // unit
  Real radius;
  Real height;
};
// A closed triangle mesh; inside/outside by ray parity along +x, with
// triangles binned by their (y, z) extent so each ray tests few of them.
class MeshShape {
 public:
  explicit MeshShape(TriangleMesh mesh);
  bool contains(const Vec3& p) const;
  Aabb bounds() const { return bounds_; }
  const TriangleMesh& mesh() const { return mesh_; }

 private:
  TriangleMesh mesh_;
  Aabb bounds_;
  Real cell_ = 1.0;
  int ny_ = 1, nz_ = 1;
  std::vector<std::vector<std::uint32_t>> rows_;
};

struct ShapeUnion;
struct ShapeDifference;

using Shape = std::variant<BoxShape, SphereShape, CylinderShape, std::shared_ptr<const MeshShape>,
                           std::shared_ptr<const ShapeUnion>, std::shared_ptr<const ShapeDifference>>;

struct ShapeUnion {
  std::vector<Shape> parts;
};
struct ShapeDifference {
  Shape base;
  std::vector<Shape> subtract;
};

bool contains(const Shape& s, const Vec3& p);
Aabb bounds(const Shape& s);
Real volume_estimate(const Shape& s, Real spacing);
// The shape's volume, m³: exact for boxes, spheres, cylinders and closed
// meshes; unions and differences counted on a lattice of a quarter of
// `spacing` (their parts may overlap), coarser where that lattice would pass
// four million points over their bounding box.
Real shape_volume(const Shape& s, Real spacing);

// What a lattice sampling (sample_lattice) holds of its shape. The lattice
// holds whole spacings, so a body whose size is not a multiple of the spacing
// is sampled short along it (a 47.5 mm loaf at 3 mm: 15 layers, 45 mm), and
// its mass with it, since every particle stands for a spacing³.
struct SamplingFill {
  Real volume = 0;                     // shape_volume, m³
  Real fraction = 1;                   // count · spacing³ / volume
  Vec3 sampled_extent = Vec3::Zero();  // the points' bounding box grown by a spacing, m
  Vec3 shape_extent = Vec3::Zero();    // the shape's bounding box, m
};
// `volume`: the shape's, when the caller has it (0: shape_volume(s, spacing)).
SamplingFill sampling_fill(const Shape& s, const std::vector<Vec3>& points, Real spacing, Real volume = 0);
// Sampled volumes further than this from the shape's are worth a warning.
inline constexpr Real kSamplingFillTolerance = 0.05;
// A spacing near `spacing` whose lattice fills the shape within the tolerance:
// of those that lay whole layers along one of its bounding box's axes (E/n,
// with n the layers `spacing` fits there or one more, to six significant
// digits rounded down) and fill it within the tolerance, the nearest (then the
// one that fills it best), with its fill; spacing 0 if none does.
struct FittingSpacing {
  Real spacing = 0, fraction = 0;
};
FittingSpacing fitting_spacing(const Shape& s, Real spacing, Real volume = 0);
// The scene key that sets the lattice's spacing, and the key's value per spacing
// ("solver.sph.spacing", 1; "solver.mpm.cell_size", the cube root of particles_per_cell).
struct SpacingKey {
  const char* path;
  Real per_spacing;
};
// "" when the fill is within kSamplingFillTolerance, else a warning naming the
// body (`where`, its name) and the `points` ("particles", "material points"),
// with the key's value that would fill it (fitting_spacing) where there is one.
std::string sampling_warning(const std::string& where, const std::string& name, const char* points, std::size_t count,
                             Real spacing, const SamplingFill& fill, const Shape& shape, const SpacingKey& key);

// Points of a cubic lattice with the given spacing that lie inside the shape.
// The lattice starts half a spacing inside the shape's bounding box, so a box
// of size n·s gets exactly n particles along each side.
std::vector<Vec3> sample_lattice(const Shape& s, Real spacing);

// What both solvers know of a body: its name, where the scene defined it,
// its material (index in name order), shape, initial temperature and velocity.
// Each solver's Body adds what only it reads.
struct BodyBase {
  std::string name;
  std::string source;  // "FILE: bodies[i]", for messages
  int material = 0;
  Shape shape;
  Real temperature = 20.0;  // °C
  Vec3 velocity = Vec3::Zero();
};

}  // namespace bakesim
