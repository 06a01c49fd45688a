#pragma once
// Collider geometry (one-way: colliders move particles, never the reverse).
// Analytic colliders (planes, solid boxes, open-top containers, the domain
// walls) answer "which wall faces are near this point" with a distance and the
// face normal pointing into free space; mesh colliders answer segment queries
// against facing triangles (thesis 3.1.9).
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "geometry/mesh.hpp"
#include "physics/curves.hpp"

namespace bakesim {

// A nearby wall: signed distance from the wall surface (negative inside the
// solid) and the unit normal pointing out of the solid.
struct WallContact {
  Real distance;
  Vec3 normal;
};

struct PlaneCollider {
  Vec3 point;
  Vec3 normal;  // unit, pointing into the free side
};

struct BoxCollider {
  Aabb box;  // solid
};

// Open-top box: a floor and four walls of the given thickness around `inner`.
struct ContainerCollider {
  Aabb inner;
  Real wall_thickness;
  std::vector<Aabb> slabs() const;
};

// The inside of a box is free; everything outside is solid (domain walls).
struct InsideBoxCollider {
  Aabb box;
};

struct MeshCollider {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const TriangleGrid> grid;
  std::shared_ptr<const std::vector<Vec3>> normals;  // per triangle, unit
  static MeshCollider build(TriangleMesh mesh, Real cell_size);
};

using ColliderGeometry =
    std::variant<PlaneCollider, BoxCollider, ContainerCollider, InsideBoxCollider, MeshCollider>;

struct Collider {
  std::string name;
  ColliderGeometry geometry;
  Real friction = 0.0;  // 0: free slip (thesis β_c = 1), 1: no slip (β_c = 0)
  Real damping = 1.0;   // 1: normal velocity removed (α_c = 0), 0: elastic bounce (α_c = 1)
  // °C over bake time (a constant or a schedule); particles touching it
  // exchange heat with it when set.
  std::optional<PiecewiseLinear> temperature;
  Real heat_transfer_coefficient = 500.0;  // W/(m² K), contact exchange with touching particles
};

// Contact with a solid axis-aligned box from point p (outside or inside).
WallContact box_contact(const Aabb& box, const Vec3& p);

// Calls fn(WallContact) for each analytic wall face within `range` of p.
// Mesh colliders report nothing here.
template <class Fn>
void for_each_wall(const ColliderGeometry& g, const Vec3& p, Real range, Fn&& fn);

// First facing triangle hit by the segment from `from` to `to` extended by
// `radius` along its direction; accumulates hit normals.
struct SegmentHit {
  Vec3 normal_sum = Vec3::Zero();
  int hits = 0;
};
SegmentHit mesh_segment_hits(const MeshCollider& m, const Vec3& from, const Vec3& to, Real radius);

// ---- implementation of the template ---------------------------------------
template <class Fn>
void for_each_wall(const ColliderGeometry& g, const Vec3& p, Real range, Fn&& fn) {
  if (const auto* plane = std::get_if<PlaneCollider>(&g)) {
    const Real d = plane->normal.dot(p - plane->point);
    if (d < range) fn(WallContact{d, plane->normal});
  } else if (const auto* box = std::get_if<BoxCollider>(&g)) {
    const WallContact c = box_contact(box->box, p);
    if (c.distance < range) fn(c);
  } else if (const auto* cont = std::get_if<ContainerCollider>(&g)) {
    // Cheap reject: outside the container's outer box grown by range.
    const Real t = cont->wall_thickness + range;
    if ((p.array() < cont->inner.min.array() - t).any() || (p.array() > cont->inner.max.array() + t).any()) return;
    for (const Aabb& s : cont->slabs()) {
      const WallContact c = box_contact(s, p);
      if (c.distance < range) fn(c);
    }
  } else if (const auto* inside = std::get_if<InsideBoxCollider>(&g)) {
    const Aabb& b = inside->box;
    for (int k = 0; k < 3; ++k) {
      const Real lo = p[k] - b.min[k], hi = b.max[k] - p[k];
      if (lo < range) fn(WallContact{lo, Vec3::Unit(k)});
      if (hi < range) fn(WallContact{hi, -Vec3::Unit(k)});
    }
  }
}

}  // namespace bakesim
