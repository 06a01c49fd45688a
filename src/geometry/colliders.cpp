#include "geometry/colliders.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Geometry>

#include "core/errors.hpp"
#include "core/parallel.hpp"

namespace bakesim {

std::array<Aabb, 5> ContainerCollider::slabs() const {
  const Real t = wall_thickness;
  const Vec3& a = inner.min;
  const Vec3& b = inner.max;
  // The slabs overlap at the edges and corners (each wall reaches through the
  // floor and across the neighbouring walls): slabs that only touched would
  // leave seams inside the solid along which particles slid out.
  return {{
      {Vec3(a.x() - t, a.y() - t, a.z() - t), Vec3(b.x() + t, a.y(), b.z() + t)},  // floor
      {Vec3(a.x() - t, a.y() - t, a.z() - t), Vec3(a.x(), b.y(), b.z() + t)},      // -x wall
      {Vec3(b.x(), a.y() - t, a.z() - t), Vec3(b.x() + t, b.y(), b.z() + t)},      // +x wall
      {Vec3(a.x() - t, a.y() - t, a.z() - t), Vec3(b.x() + t, b.y(), a.z())},      // -z wall
      {Vec3(a.x() - t, a.y() - t, b.z()), Vec3(b.x() + t, b.y(), b.z() + t)},      // +z wall
  }};
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
    if (lo < best) {
      best = lo;
      n = -Vec3::Unit(k);
    }
    if (hi < best) {
      best = hi;
      n = Vec3::Unit(k);
    }
  }
  return {-best, n};
}

WallContact ring_contact(const Vec3& base, const Vec3& axis, Real r_in, Real r_out, Real h0, Real h1, const Vec3& p) {
  const Vec3 d = p - base;
  const Real h = d.dot(axis);
  const Vec3 radial_vec = d - h * axis;
  const Real rho = radial_vec.norm();
  Vec3 radial;
  if (rho > 1e-12 * (r_out + 1e-30)) {
    radial = radial_vec / rho;
  } else {  // on the axis: any direction perpendicular to it
    radial = axis.unitOrthogonal();
  }
  // Distances to the radial and axial extents (positive outside) and the
  // directions out of the solid across each.
  Real dr;
  Vec3 nr;
  if (r_in <= 0) {
    dr = rho - r_out;
    nr = radial;
  } else {
    const Real mid = 0.5 * (r_in + r_out);
    dr = std::abs(rho - mid) - 0.5 * (r_out - r_in);
    nr = rho >= mid ? radial : -radial;
  }
  const Real hm = 0.5 * (h0 + h1);
  const Real dh = std::abs(h - hm) - 0.5 * (h1 - h0);
  const Vec3 nh = h >= hm ? axis : Vec3(-axis);
  if (dr <= 0 && dh <= 0) return dr > dh ? WallContact{dr, nr} : WallContact{dh, nh};
  const Real a = std::max(dr, Real(0)), b = std::max(dh, Real(0));
  const Real dist = std::sqrt(a * a + b * b);
  return {dist, (a * nr + b * nh) / dist};
}

WallContact signed_distance(const ColliderGeometry& g, const Vec3& p) {
  const auto nearest_face = [&](const auto&) {
    WallContact best{std::numeric_limits<Real>::infinity(), Vec3::UnitY()};
    for_each_wall(g, p, std::numeric_limits<Real>::infinity(), [&](const WallContact& c) {
      if (c.distance < best.distance) best = c;
    });
    return best;
  };
  return std::visit(Overloaded{
                        [&](const PlaneCollider& c) { return nearest_face(c); },
                        [&](const BoxCollider& c) { return nearest_face(c); },
                        [&](const ContainerCollider& c) { return nearest_face(c); },
                        [&](const CylinderCollider& c) { return nearest_face(c); },
                        [&](const CupCollider& c) { return nearest_face(c); },
                        [&](const InsideBoxCollider& c) { return nearest_face(c); },
                        [&](const MeshCollider& m) {
                          if (!m.sdf) return WallContact{std::numeric_limits<Real>::infinity(), Vec3::UnitY()};
                          return m.sdf->sample(p);
                        },
                    },
                    g);
}

namespace {

// Which feature of triangle (a, b, c) the point q (on the triangle) lies on:
// 0–2 a vertex, 3–5 the edge opposite vertex k−3 ... encoded as below, 6 the face.
int triangle_feature(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Barycentric coordinates of q.
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const Real d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const Real den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 0)) return 0;
  const Real v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den, u = 1 - v - w;
  const Real eps = 1e-7;
  const bool zu = u < eps, zv = v < eps, zw = w < eps;
  if (zv && zw) return 0;  // vertex a
  if (zu && zw) return 1;  // vertex b
  if (zu && zv) return 2;  // vertex c
  if (zw) return 3;        // edge a–b
  if (zu) return 4;        // edge b–c
  if (zv) return 5;        // edge c–a
  return 6;
}

}  // namespace

SignedDistanceGrid SignedDistanceGrid::from_mesh(const TriangleMesh& mesh, const TriangleGrid& index, Real cell,
                                                 Real band) {
  // Pseudo-normals: faces, edges (sum of the adjacent face normals), vertices
  // (face normals weighted by the incident angle).
  const std::size_t nt = mesh.triangles.size();
  std::vector<Vec3> face(nt), vertex(mesh.vertices.size(), Vec3::Zero());
  std::map<std::pair<int, int>, Vec3> edge;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    face[t] = mesh.normal(t);
    for (int k = 0; k < 3; ++k) {
      const int i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
      const Vec3 e1 = (mesh.vertices[j] - mesh.vertices[i]).normalized(),
                 e2 = (mesh.vertices[l] - mesh.vertices[i]).normalized();
      vertex[i] += std::acos(std::clamp(e1.dot(e2), Real(-1), Real(1))) * face[t];
      auto key = std::minmax(i, j);
      auto [it, fresh] = edge.emplace(std::make_pair(key.first, key.second), face[t]);
      if (!fresh) it->second += face[t];
    }
  }
  SignedDistanceGrid g;
  g.cell = cell;
  g.band = band;
  const Aabb b = mesh.bounds();
  g.box = {b.min - Vec3::Constant(band + cell), b.max + Vec3::Constant(band + cell)};
  g.nx = static_cast<int>(std::ceil(g.box.extent().x() / cell)) + 1;
  g.ny = static_cast<int>(std::ceil(g.box.extent().y() / cell)) + 1;
  g.nz = static_cast<int>(std::ceil(g.box.extent().z() / cell)) + 1;
  g.phi.assign(std::size_t(g.nx) * g.ny * g.nz, static_cast<float>(band));
  parallel_for(
      g.phi.size(),
      [&](std::size_t k) {
        const std::size_t ix = k % g.nx, iy = (k / g.nx) % g.ny, iz = k / (std::size_t(g.nx) * g.ny);
        const Vec3 p = g.box.min + cell * Vec3(Real(ix), Real(iy), Real(iz));
        Real best = band * band;
        Vec3 best_q = p, best_n = Vec3::Zero();
        index.for_each_candidate({p - Vec3::Constant(band), p + Vec3::Constant(band)}, [&](std::uint32_t t) {
          const auto& tri = mesh.triangles[t];
          const Vec3 &a = mesh.vertices[tri[0]], &bb = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
          const Vec3 q = closest_point_on_triangle(p, a, bb, c);
          const Real d2 = (p - q).squaredNorm();
          if (d2 >= best) return;
          best = d2;
          best_q = q;
          const int f = triangle_feature(q, a, bb, c);
          if (f < 3) {
            best_n = vertex[tri[f]];
          } else if (f < 6) {
            const int i = tri[f - 3], j = tri[(f - 2) % 3];
            best_n = edge.at(std::make_pair(std::min(i, j), std::max(i, j)));
          } else {
            best_n = face[t];
          }
        });
        if (best >= band * band) return;
        const Real d = std::sqrt(best);
        g.phi[k] = static_cast<float>((p - best_q).dot(best_n) < 0 ? -d : d);
      },
      256);
  return g;
}

WallContact SignedDistanceGrid::sample(const Vec3& p) const {
  const Vec3 u = (p - box.min) / cell;
  const int i = static_cast<int>(std::floor(u.x())), j = static_cast<int>(std::floor(u.y())),
            k = static_cast<int>(std::floor(u.z()));
  if (i < 0 || j < 0 || k < 0 || i + 1 >= nx || j + 1 >= ny || k + 1 >= nz) return {band, Vec3::UnitY()};
  const Real fx = u.x() - i, fy = u.y() - j, fz = u.z() - k;
  auto at = [&](int a, int b, int c) -> Real {
    return phi[std::size_t(i + a) + std::size_t(nx) * (std::size_t(j + b) + std::size_t(ny) * (k + c))];
  };
  Real value = 0;
  Vec3 grad = Vec3::Zero();
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        const Real wx = a ? fx : 1 - fx, wy = b ? fy : 1 - fy, wz = c ? fz : 1 - fz;
        const Real v = at(a, b, c);
        value += wx * wy * wz * v;
        grad += v * Vec3((a ? 1 : -1) * wy * wz, wx * (b ? 1 : -1) * wz, wx * wy * (c ? 1 : -1));
      }
  const Real n = grad.norm();
  return {value, n > 0 ? Vec3(grad / n) : Vec3::UnitY()};
}

MeshCollider MeshCollider::with_signed_distance(Real cell, Real band) const {
  MeshCollider m = *this;
  m.sdf = std::make_shared<const SignedDistanceGrid>(SignedDistanceGrid::from_mesh(*mesh, *grid, cell, band));
  return m;
}

MeshCollider MeshCollider::build(TriangleMesh mesh, Real cell_size) {
  auto m = std::make_shared<const TriangleMesh>(std::move(mesh));
  auto normals = std::make_shared<std::vector<Vec3>>(m->triangles.size());
  for (std::size_t t = 0; t < m->triangles.size(); ++t) (*normals)[t] = m->normal(t);
  return MeshCollider{m, std::make_shared<const TriangleGrid>(*m, cell_size), normals, nullptr};
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
    const auto hit =
        intersect_ray_triangle(from, dir, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    if (hit && *hit <= reach) {
      out.normal_sum += n;
      ++out.hits;
    }
  });
  return out;
}

}  // namespace bakesim

namespace bakesim {

ColliderLook default_look(const ColliderGeometry& geometry) {
  return std::visit(Overloaded{
                        [](const PlaneCollider&) { return ColliderLook::wood; },
                        [](const CylinderCollider&) { return ColliderLook::wood; },
                        [](const MeshCollider&) { return ColliderLook::ceramic; },
                        [](const InsideBoxCollider&) { return ColliderLook::hidden; },
                        [](const auto&) { return ColliderLook::metal; },
                    },
                    geometry);
}

ColliderLook parse_collider_look(const std::string& name, const ColliderGeometry& geometry, const std::string& where) {
  if (name == "auto") return default_look(geometry);
  for (ColliderLook look : {ColliderLook::metal, ColliderLook::ceramic, ColliderLook::glass, ColliderLook::wood,
                            ColliderLook::stone, ColliderLook::hidden})
    if (to_string(look) == name) return look;
  throw InputError(where, "unknown look '" + name + "' (auto, metal, ceramic, glass, wood, stone, hidden)");
}

Vec3 look_albedo(ColliderLook look) {
  switch (look) {
    case ColliderLook::metal: return {0.42, 0.43, 0.45};    // aluminium or tinned steel
    case ColliderLook::ceramic: return {0.80, 0.78, 0.72};  // glazed white
    case ColliderLook::glass: return {0.95, 0.98, 0.98};    // slightly tinted
    case ColliderLook::wood: return {0.42, 0.25, 0.12};     // a beech board
    case ColliderLook::stone: return {0.16, 0.15, 0.14};    // dark basalt (a volcano, a baking stone)
    default: return {0.5, 0.5, 0.5};
  }
}

std::string to_string(ColliderLook look) {
  switch (look) {
    case ColliderLook::metal: return "metal";
    case ColliderLook::ceramic: return "ceramic";
    case ColliderLook::glass: return "glass";
    case ColliderLook::wood: return "wood";
    case ColliderLook::stone: return "stone";
    default: return "hidden";
  }
}

}  // namespace bakesim
