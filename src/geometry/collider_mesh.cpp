#include "geometry/collider_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Geometry>

namespace bakesim {

namespace {

// Appends a hexahedron (12 triangles) from its corners numbered as a box's,
// bit 0, 1, 2 of k choosing the far side along the first, second, third edge
// direction. Outward when those directions form a right-handed frame; for a
// left-handed one each face is wound the other way round.
void add_hexahedron(TriangleMesh& m, const std::array<Vec3, 8>& corners, bool left_handed) {
  const int o = int(m.vertices.size());
  m.vertices.insert(m.vertices.end(), corners.begin(), corners.end());
  // Faces as quads of corner indices, counter-clockwise seen from outside (right-handed).
  const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    const int b = left_handed ? q[2] : q[1], d = left_handed ? q[1] : q[2];
    const int e = left_handed ? q[3] : q[2], f = left_handed ? q[2] : q[3];
    m.triangles.push_back({o + q[0], o + b, o + d});
    m.triangles.push_back({o + q[0], o + e, o + f});
  }
}

// Appends a solid axis-aligned box, outward.
void add_box(TriangleMesh& m, const Aabb& b) {
  std::array<Vec3, 8> corners;
  for (int k = 0; k < 8; ++k)
    corners[std::size_t(k)] =
        Vec3(k & 1 ? b.max.x() : b.min.x(), k & 2 ? b.max.y() : b.min.y(), k & 4 ? b.max.z() : b.min.z());
  add_hexahedron(m, corners, false);
}

// Appends a solid ring r_in ≤ ρ ≤ r_out, h0 ≤ (x − base)·axis ≤ h1 (r_in = 0:
// a capped cylinder), outward, with `n` facets around.
void add_ring(TriangleMesh& m, const Vec3& base, const Vec3& axis, Real r_in, Real r_out, Real h0, Real h1, int n) {
  const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  auto point = [&](Real r, Real h, int k) {
    const Real a = 2 * kPi * Real(k % n) / Real(n);
    return Vec3(base + h * axis + r * (std::cos(a) * e1 + std::sin(a) * e2));
  };
  const int o = int(m.vertices.size());
  // Vertices: outer bottom, outer top, then (ring) inner bottom, inner top, else the two axis points.
  for (int k = 0; k < n; ++k) m.vertices.push_back(point(r_out, h0, k));
  for (int k = 0; k < n; ++k) m.vertices.push_back(point(r_out, h1, k));
  const bool ring = r_in > 0;
  if (ring) {
    for (int k = 0; k < n; ++k) m.vertices.push_back(point(r_in, h0, k));
    for (int k = 0; k < n; ++k) m.vertices.push_back(point(r_in, h1, k));
  } else {
    m.vertices.push_back(base + h0 * axis);
    m.vertices.push_back(base + h1 * axis);
  }
  const int ob = o, ot = o + n, ib = o + 2 * n, it = o + 3 * n, cb = o + 2 * n, ct = o + 2 * n + 1;
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    // Outer wall (e1 × e2 = axis, so increasing k turns counter-clockwise about the axis).
    m.triangles.push_back({ob + k, ob + k1, ot + k1});
    m.triangles.push_back({ob + k, ot + k1, ot + k});
    if (ring) {
      m.triangles.push_back({ib + k, it + k1, ib + k1});  // inner wall, facing the axis
      m.triangles.push_back({ib + k, it + k, it + k1});
      m.triangles.push_back({ot + k, ot + k1, it + k1});  // top annulus
      m.triangles.push_back({ot + k, it + k1, it + k});
      m.triangles.push_back({ob + k, ib + k1, ob + k1});  // bottom annulus
      m.triangles.push_back({ob + k, ib + k, ib + k1});
    } else {
      m.triangles.push_back({ct, ot + k, ot + k1});  // top cap
      m.triangles.push_back({cb, ob + k1, ob + k});  // bottom cap
    }
  }
}

}  // namespace

TriangleMesh collider_rest_mesh(const ColliderGeometry& geometry, const Vec3& focus, Real half_width, int segments) {
  const int n = std::max(segments, 8);
  TriangleMesh m;
  std::visit(Overloaded{
                 [&](const PlaneCollider& p) {
                   // A square slab under the focus, its top face on the plane.
                   const Vec3 centre = focus - p.normal.dot(focus - p.point) * p.normal;
                   const Vec3 e1 = p.normal.unitOrthogonal(), e2 = p.normal.cross(e1);
                   const Real depth = kPlaneSlabThickness * half_width;
                   // Corners along (e1, e2, −normal): e1 × e2 = normal, so that frame is left-handed.
                   std::array<Vec3, 8> corners;
                   for (int k = 0; k < 8; ++k)
                     corners[std::size_t(k)] = centre + (k & 1 ? half_width : -half_width) * e1 +
                                               (k & 2 ? half_width : -half_width) * e2 -
                                               (k & 4 ? depth : 0.0) * p.normal;
                   add_hexahedron(m, corners, true);
                 },
                 [&](const BoxCollider& b) { add_box(m, b.box); },
                 [&](const ContainerCollider& c) {
                   // The floor and four walls as the solid they make, without overlaps.
                   const Real t = c.wall_thickness;
                   const Vec3 &a = c.inner.min, &b = c.inner.max;
                   add_box(m, {Vec3(a.x() - t, a.y() - t, a.z() - t), Vec3(b.x() + t, a.y(), b.z() + t)});
                   add_box(m, {Vec3(a.x() - t, a.y(), a.z() - t), Vec3(a.x(), b.y(), b.z() + t)});
                   add_box(m, {Vec3(b.x(), a.y(), a.z() - t), Vec3(b.x() + t, b.y(), b.z() + t)});
                   add_box(m, {Vec3(a.x(), a.y(), a.z() - t), Vec3(b.x(), b.y(), a.z())});
                   add_box(m, {Vec3(a.x(), a.y(), b.z()), Vec3(b.x(), b.y(), b.z() + t)});
                 },
                 [&](const CylinderCollider& c) {
                   add_ring(m, c.center, c.axis, 0, c.radius, -0.5 * c.height, 0.5 * c.height, n);
                 },
                 [&](const CupCollider& c) {
                   const Real t = c.wall_thickness;
                   add_ring(m, c.base, c.axis, 0, c.radius + t, -t, 0, n);               // floor
                   add_ring(m, c.base, c.axis, c.radius, c.radius + t, 0, c.height, n);  // wall
                   if (c.tube_radius > 0) add_ring(m, c.base, c.axis, 0, c.tube_radius, 0, c.height, n);
                 },
                 [&](const InsideBoxCollider&) {},
                 [&](const MeshCollider& mesh) {
                   if (mesh.mesh) m = *mesh.mesh;
                 },
             },
             geometry);
  return m;
}

TriangleMesh collider_mesh_at(const Collider& collider, Real time, const Vec3& focus, Real half_width, int segments) {
  const RigidPose pose = collider.motion.at(time);
  TriangleMesh m = collider_rest_mesh(collider.geometry, pose.to_rest(focus), half_width, segments);
  for (Vec3& v : m.vertices) v = pose.to_world(v);
  return m;
}

std::optional<Aabb> collider_rest_bounds(const ColliderGeometry& geometry) {
  if (std::holds_alternative<PlaneCollider>(geometry) || std::holds_alternative<InsideBoxCollider>(geometry))
    return std::nullopt;
  const TriangleMesh m = collider_rest_mesh(geometry, Vec3::Zero(), 1, 16);
  if (m.vertices.empty()) return std::nullopt;
  Aabb box = Aabb::empty_box();
  for (const Vec3& v : m.vertices) box.expand(v);
  // Round parts bulge past the polygon's corners by at most r (1 − cos(π/16)) < 2%.
  box.min.array() -= 0.02 * box.extent().norm();
  box.max.array() += 0.02 * box.extent().norm();
  return box;
}

TriangleMesh domain_tank_mesh(const Aabb& domain, const std::array<bool, 3>& periodic, const Vec3& viewer,
                              Real thickness) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis) {
    if (periodic[std::size_t(axis)]) continue;
    for (int side = 0; side < 2; ++side) {
      // The face's outward normal is ±e_axis; the viewer sees its inner side when it lies inside the face's plane.
      const Real face = side ? domain.max[axis] : domain.min[axis];
      const bool sees_inner = side ? viewer[axis] < face : viewer[axis] > face;
      if (!sees_inner) continue;
      Aabb slab{Vec3(domain.min.array() - thickness), Vec3(domain.max.array() + thickness)};
      if (side)
        slab.min[axis] = face;
      else
        slab.max[axis] = face;
      add_box(m, slab);
    }
  }
  return m;
}

}  // namespace bakesim
