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
