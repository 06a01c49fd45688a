#include "geometry/mesh.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace bakesim {

Aabb TriangleMesh::bounds() const {
  Aabb b = Aabb::empty_box();
  for (const Vec3& v : vertices) b.expand(v);
  return b;
}

Vec3 TriangleMesh::normal(std::size_t t) const {
  const auto& tri = triangles[t];
  const Vec3 n = (vertices[tri[1]] - vertices[tri[0]]).cross(vertices[tri[2]] - vertices[tri[0]]);
  const Real len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

Real TriangleMesh::signed_volume() const {
  Real v = 0;
  for (const auto& t : triangles) v += vertices[t[0]].dot(vertices[t[1]].cross(vertices[t[2]])) / 6.0;
  return v;
}

Mat3 rotation_from_degrees(const Vec3& d) {
  const Real k = kPi / 180.0;
  return (Eigen::AngleAxis<Real>(d.z() * k, Vec3::UnitZ()) * Eigen::AngleAxis<Real>(d.y() * k, Vec3::UnitY()) *
          Eigen::AngleAxis<Real>(d.x() * k, Vec3::UnitX()))
      .toRotationMatrix();
}

void TriangleMesh::apply(Real scale, const Vec3& rotation_deg, const Vec3& translation) {
  const Mat3 r = rotation_from_degrees(rotation_deg);
  for (Vec3& v : vertices) v = r * (scale * v) + translation;
  if (scale < 0) flip_orientation();
}

void TriangleMesh::flip_orientation() {
  for (auto& t : triangles) std::swap(t[1], t[2]);
}

std::optional<Real> intersect_ray_triangle(const Vec3& origin, const Vec3& dir, const Vec3& a, const Vec3& b,
                                           const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = dir.cross(e2);
  const Real det = e1.dot(p);
  const Real scale = e1.squaredNorm() * dir.norm();
  if (std::abs(det) <= 1e-14 * scale) return std::nullopt;  // parallel
  const Real inv = 1.0 / det;
  const Vec3 s = origin - a;
  const Real u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return std::nullopt;
  const Vec3 q = s.cross(e1);
  const Real v = dir.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return std::nullopt;
  const Real t = e2.dot(q) * inv;
  if (t < 0.0) return std::nullopt;
  return t;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const Real denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

TriangleGrid::TriangleGrid(const TriangleMesh& mesh, Real cell_size) {
  if (mesh.triangles.empty()) return;
  bounds_ = mesh.bounds();
  const Vec3 ext = bounds_.extent();
  // Keep the grid at most 128 cells along its longest side.
  cell_ = std::max(cell_size, ext.maxCoeff() / 128.0);
  cell_ = std::max(cell_, 1e-9);
  nx_ = std::max(1, int(std::ceil(ext.x() / cell_)) + 1);
  ny_ = std::max(1, int(std::ceil(ext.y() / cell_)) + 1);
  nz_ = std::max(1, int(std::ceil(ext.z() / cell_)) + 1);
  const std::size_t ncell = std::size_t(nx_) * ny_ * nz_;
  std::vector<std::uint32_t> count(ncell + 1, 0);
  // Conservative: a cell is kept when the triangle comes within the cell's
  // circumscribed sphere.
  const Real reach2 = 0.75 * cell_ * cell_ * (1.0 + 1e-9);
  auto cells_of = [&](std::size_t t, auto&& fn) {
    const Vec3& a = mesh.vertices[mesh.triangles[t][0]];
    const Vec3& b = mesh.vertices[mesh.triangles[t][1]];
    const Vec3& c = mesh.vertices[mesh.triangles[t][2]];
    Aabb box = Aabb::empty_box();
    box.expand(a);
    box.expand(b);
    box.expand(c);
    const Vec3 lo = (box.min - bounds_.min) / cell_, hi = (box.max - bounds_.min) / cell_;
    auto cl = [](Real v, int n) { return std::max(0, std::min(n - 1, int(v))); };
    for (int z = cl(lo.z(), nz_); z <= cl(hi.z(), nz_); ++z)
      for (int y = cl(lo.y(), ny_); y <= cl(hi.y(), ny_); ++y)
        for (int x = cl(lo.x(), nx_); x <= cl(hi.x(), nx_); ++x) {
          const Vec3 centre = bounds_.min + cell_ * Vec3(x + 0.5, y + 0.5, z + 0.5);
          if ((closest_point_on_triangle(centre, a, b, c) - centre).squaredNorm() <= reach2)
            fn(std::size_t(x) + std::size_t(nx_) * (std::size_t(y) + std::size_t(ny_) * z));
        }
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) cells_of(t, [&](std::size_t c) { ++count[c + 1]; });
  cell_start_.assign(ncell + 1, 0);
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] = cell_start_[c] + count[c + 1];
  ids_.resize(cell_start_[ncell]);
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    cells_of(t, [&](std::size_t c) { ids_[fill[c]++] = static_cast<std::uint32_t>(t); });
}

}  // namespace bakesim
