#include "geometry/colliders.hpp"

#include <cmath>

namespace bakesim {

std::vector<Aabb> ContainerCollider::slabs() const {
  const Real t = wall_thickness;
  const Vec3& a = inner.min;
  const Vec3& b = inner.max;
  return {
      {Vec3(a.x() - t, a.y() - t, a.z() - t), Vec3(b.x() + t, a.y(), b.z() + t)},  // floor
      {Vec3(a.x() - t, a.y(), a.z() - t), Vec3(a.x(), b.y(), b.z() + t)},          // -x wall
      {Vec3(b.x(), a.y(), a.z() - t), Vec3(b.x() + t, b.y(), b.z() + t)},          // +x wall
      {Vec3(a.x(), a.y(), a.z() - t), Vec3(b.x(), b.y(), a.z())},                  // -z wall
      {Vec3(a.x(), a.y(), b.z()), Vec3(b.x(), b.y(), b.z() + t)},                  // +z wall
  };
}

WallContact box_contact(const Aabb& box, const Vec3& p) {
  const Vec3 q = p.cwiseMax(box.min).cwiseMin(box.max);
  const Vec3 d = p - q;
  const Real dist = d.norm();
  if (dist > 0) return {dist, d / dist};
  // Inside: leave through the nearest face.
  Real best = 1e300;
  Vec3 n = Vec3::UnitY();
  for (int k = 0; k < 3; ++k) {
    const Real lo = p[k] - box.min[k], hi = box.max[k] - p[k];
    if (lo < best) { best = lo; n = -Vec3::Unit(k); }
    if (hi < best) { best = hi; n = Vec3::Unit(k); }
  }
  return {-best, n};
}

MeshCollider MeshCollider::build(TriangleMesh mesh, Real cell_size) {
  auto m = std::make_shared<const TriangleMesh>(std::move(mesh));
  auto normals = std::make_shared<std::vector<Vec3>>(m->triangles.size());
  for (std::size_t t = 0; t < m->triangles.size(); ++t) (*normals)[t] = m->normal(t);
  return MeshCollider{m, std::make_shared<const TriangleGrid>(*m, cell_size), normals};
}

SegmentHit mesh_segment_hits(const MeshCollider& m, const Vec3& from, const Vec3& to, Real radius) {
  SegmentHit out;
  const Vec3 delta = to - from;
  const Real len = delta.norm();
  if (len <= 0) return out;
  const Vec3 dir = delta / len;
  const Real reach = len + radius;
  Aabb box{from.cwiseMin(to) - Vec3::Constant(radius), from.cwiseMax(to) + Vec3::Constant(radius)};
  const TriangleMesh& mesh = *m.mesh;
  m.grid->for_each_candidate(box, [&](std::uint32_t t) {
    const Vec3& n = (*m.normals)[t];
    if (n.dot(dir) >= 0) return;  // only triangles facing the incoming particle
    const auto& tri = mesh.triangles[t];
    const auto hit = intersect_ray_triangle(from, dir, mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                            mesh.vertices[tri[2]]);
    if (hit && *hit <= reach) {
      out.normal_sum += n;
      ++out.hits;
    }
  });
  return out;
}

}  // namespace bakesim
