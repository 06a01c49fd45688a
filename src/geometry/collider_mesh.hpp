#pragma once
// Colliders as triangle meshes, for pictures and for export next to the body
// meshes: the solid each collider's contact law acts on (geometry/colliders.hpp),
// at its pose at a given time. Closed and outward-oriented, so their signed
// volume is the solid's (tested). Planes are infinite: they are drawn as a
// square slab (a counter, a board) of a given half-width around the point of
// the plane nearest a focus, `kPlaneSlabThickness` of that half-width thick.
// The domain walls (InsideBoxCollider) have no collider mesh: drawn whole they
// would hide the scene; pictures may draw them as an open tank (domain_tank_mesh).
#include <array>
#include <optional>
#include <string>

#include "geometry/colliders.hpp"
#include "geometry/mesh.hpp"

namespace bakesim {

inline constexpr Real kPlaneSlabThickness = 0.04;  // of the slab's half-width

// Triangles of the collider's solid in its rest pose (nothing for domain walls).
// `focus` and `half_width` place and size the slab standing for a plane; round
// parts have `segments` facets around (at least 8).
TriangleMesh collider_rest_mesh(const ColliderGeometry& geometry, const Vec3& focus, Real half_width,
                                int segments = 64);

// The same at the collider's pose at simulated time `time` (the plane's slab
// centred under `focus` as the plane then lies).
TriangleMesh collider_mesh_at(const Collider& collider, Real time, const Vec3& focus, Real half_width,
                              int segments = 64);

// Bounds of the collider's solid in its rest pose; nothing for planes and domain
// walls (unbounded).
std::optional<Aabb> collider_rest_bounds(const ColliderGeometry& geometry);

// The domain walls as a tank seen from `viewer`: a slab `thickness` thick
// outside each face of `domain` whose inner side the viewer sees (from outside
// and above: the floor and the far walls), so the tank never stands between the
// viewer and what it holds; none on periodic axes. Slabs reach over the edges
// so the corners close. Empty when the viewer sees no inner face.
TriangleMesh domain_tank_mesh(const Aabb& domain, const std::array<bool, 3>& periodic, const Vec3& viewer,
                              Real thickness);

}  // namespace bakesim
