#pragma once
// Collider geometry (one-way: colliders move particles, never the reverse).
// Analytic colliders (planes, solid boxes, open-top containers, the domain
// walls) answer "which wall faces are near this point" with a distance and the
// face normal pointing into free space; mesh colliders answer segment queries
// against facing triangles (thesis 3.1.9).
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "geometry/contact.hpp"
#include "geometry/mesh.hpp"
#include "geometry/motion.hpp"
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
  std::array<Aabb, 5> slabs() const;  // floor and four walls
};

// Solid capped cylinder (a grip, a rolling pin, a post).
struct CylinderCollider {
  Vec3 center;  // middle of the axis
  Vec3 axis;    // unit
  Real radius, height;
};

// Open-top cylindrical container (ramekin, cake pan, pitcher): a floor disc
// below `base` and a wall ring of the given thickness around the inner space
// of `radius` × `height`; with tube_radius > 0 a solid central tube of the same
// height (tube pan).
struct CupCollider {
  Vec3 base;  // centre of the inner floor
  Vec3 axis;  // unit, from the floor towards the open top
  Real radius, height, wall_thickness;
  Real tube_radius = 0;
};

// The inside of a box is free; everything outside is solid (domain walls).
struct InsideBoxCollider {
  Aabb box;
  std::array<bool, 3> open{false, false, false};  // no faces along these axes (periodic domain)
};

// Signed distance of a triangle mesh sampled on a regular grid (negative
// inside), exact within `band` of the surface and +band beyond it; sampled
// trilinearly. The sign comes from angle-weighted pseudo-normals (Bærentzen
// and Aanæs 2005), right for closed meshes; for an open mesh the side its
// triangles face is outside.
struct SignedDistanceGrid {
  Aabb box;
  Real cell = 0, band = 0;
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> phi;  // x fastest
  static SignedDistanceGrid from_mesh(const TriangleMesh& mesh, const TriangleGrid& index, Real cell, Real band);
  // Signed distance and unit gradient (outward normal) at p.
  WallContact sample(const Vec3& p) const;
};

struct MeshCollider {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const TriangleGrid> grid;
  std::shared_ptr<const std::vector<Vec3>> normals;  // per triangle, unit
  std::shared_ptr<const SignedDistanceGrid> sdf;     // built for grid-based (MPM) contact
  static MeshCollider build(TriangleMesh mesh, Real cell_size);
  // The same collider with a signed distance grid of spacing `cell`.
  MeshCollider with_signed_distance(Real cell, Real band) const;
};

using ColliderGeometry = std::variant<PlaneCollider, BoxCollider, ContainerCollider, CylinderCollider, CupCollider,
                                      InsideBoxCollider, MeshCollider>;

// What a collider is made of in pictures (render/): a pan, tray, plate, funnel,
// board or rock. `hidden` is not drawn (nor exported as a mesh).
enum class ColliderLook { metal, ceramic, glass, wood, stone, hidden };
// The look a shape gets when the scene names none: planes are a wooden counter
// or board, cylinders wood (a rolling pin, a grip), meshes ceramic, boxes,
// containers and cups metal (trays, tins, pans).
ColliderLook default_look(const ColliderGeometry& geometry);
// "auto" is default_look; InputError(where, ...) for other names.
ColliderLook parse_collider_look(const std::string& name, const ColliderGeometry& geometry, const std::string& where);
std::string to_string(ColliderLook look);
// A look's linear RGB albedo (the pictures shade with it; exported meshes carry
// it in sRGB; glass: what one face lets through).
Vec3 look_albedo(ColliderLook look);

// One collider for both solvers: its geometry in the rest pose, the contact
// law (geometry/contact.hpp), an optional scripted rigid motion, an
// optional surface temperature, and how it looks in pictures.
struct Collider {
  std::string name;
  ColliderGeometry geometry;
  ContactLaw contact;
  RigidMotion motion;  // no keyframes: the collider stays in its rest pose
  // °C over bake time (a constant or a schedule); particles touching it
  // exchange heat with it when set.
  std::optional<PiecewiseLinear> temperature;
  Real heat_transfer_coefficient = 500.0;  // W/(m² K), contact exchange with touching particles
  ColliderLook look = ColliderLook::metal;
};

// Contact with a solid axis-aligned box from point p (outside or inside).
WallContact box_contact(const Aabb& box, const Vec3& p);
// Contact with a solid ring r_in ≤ ρ ≤ r_out (r_in = 0: a solid cylinder)
// spanning h0 ≤ (p − base)·axis ≤ h1 (exact signed distance).
WallContact ring_contact(const Vec3& base, const Vec3& axis, Real r_in, Real r_out, Real h0, Real h1, const Vec3& p);

// Signed distance to the nearest solid part of a collider and the outward
// normal there (for grid-based contact). Mesh colliders need their signed
// distance grid; without one they report +infinity.
WallContact signed_distance(const ColliderGeometry& g, const Vec3& p);

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

// An overload set for std::visit: a collider shape without a case does not compile.
template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

template <class Fn>
void for_each_wall(const ColliderGeometry& g, const Vec3& p, Real range, Fn&& fn) {
  std::visit(Overloaded{
                 [&](const PlaneCollider& plane) {
                   const Real d = plane.normal.dot(p - plane.point);
                   if (d < range) fn(WallContact{d, plane.normal});
                 },
                 [&](const BoxCollider& box) {
                   const WallContact c = box_contact(box.box, p);
                   if (c.distance < range) fn(c);
                 },
                 [&](const ContainerCollider& cont) {
                   // Cheap reject: outside the container's outer box grown by range.
                   const Real t = cont.wall_thickness + range;
                   if ((p.array() < cont.inner.min.array() - t).any() || (p.array() > cont.inner.max.array() + t).any())
                     return;
                   // And inside, farther than range from the floor and the four sides (at any height: the
                   // slabs lie below the floor and beyond the sides), where most of a tin's dough is.
                   if (p.y() > cont.inner.min.y() + range && p.x() > cont.inner.min.x() + range &&
                       p.x() < cont.inner.max.x() - range && p.z() > cont.inner.min.z() + range &&
                       p.z() < cont.inner.max.z() - range)
                     return;
                   for (const Aabb& s : cont.slabs()) {
                     const WallContact c = box_contact(s, p);
                     if (c.distance < range) fn(c);
                   }
                 },
                 [&](const CylinderCollider& cyl) {
                   const WallContact c = ring_contact(cyl.center - 0.5 * cyl.height * cyl.axis, cyl.axis, 0, cyl.radius,
                                                      0, cyl.height, p);
                   if (c.distance < range) fn(c);
                 },
                 [&](const CupCollider& cup) {
                   // The wall and the tube reach down through the floor: parts that only
                   // touched would leave a seam inside the solid (the wall's lower face, one
                   // ε above the floor's top) along which particles slid out through the wall.
                   const Real t = cup.wall_thickness;
                   const WallContact parts[3] = {
                       ring_contact(cup.base, cup.axis, 0, cup.radius + t, -t, 0, p),                    // floor
                       ring_contact(cup.base, cup.axis, cup.radius, cup.radius + t, -t, cup.height, p),  // wall
                       cup.tube_radius > 0 ? ring_contact(cup.base, cup.axis, 0, cup.tube_radius, -t, cup.height, p)
                                           : WallContact{std::numeric_limits<Real>::infinity(), cup.axis}};  // tube
                   for (const WallContact& c : parts)
                     if (c.distance < range) fn(c);
                 },
                 [&](const InsideBoxCollider& inside) {
                   const Aabb& b = inside.box;
                   for (int k = 0; k < 3; ++k) {
                     if (inside.open[std::size_t(k)]) continue;
                     const Real lo = p[k] - b.min[k], hi = b.max[k] - p[k];
                     if (lo < range) fn(WallContact{lo, Vec3::Unit(k)});
                     if (hi < range) fn(WallContact{hi, -Vec3::Unit(k)});
                   }
                 },
                 // Meshes answer segment queries (mesh_segment_hits) and signed distances, not wall faces.
                 [&](const MeshCollider&) {},
             },
             g);
}

}  // namespace bakesim
