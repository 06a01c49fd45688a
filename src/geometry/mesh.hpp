#pragma once
// Triangle meshes: storage, transforms, ray casts and a uniform-grid index of
// triangles for fast local queries.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace bakesim {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;

  Aabb bounds() const;
  // Unit normal of triangle t by the right-hand rule on its vertex order.
  Vec3 normal(std::size_t t) const;
  // Signed volume (positive for a closed, outward-oriented mesh).
  Real signed_volume() const;
  void apply(Real scale, const Vec3& rotation_deg, const Vec3& translation);
  void flip_orientation();
};

// Rotation matrix from XYZ Euler angles in degrees (applied X first, then Y, then Z).
Mat3 rotation_from_degrees(const Vec3& degrees);

// Möller–Trumbore ray/triangle intersection; returns the ray parameter t ≥ 0
// (hit point = origin + t * dir) or nothing.
std::optional<Real> intersect_ray_triangle(const Vec3& origin, const Vec3& dir, const Vec3& a, const Vec3& b,
                                           const Vec3& c);

// Closest point to p on triangle (a, b, c), by Voronoi regions of the
// vertices, edges and face.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Uniform grid of triangle ids: a triangle is listed in every cell it passes
// through (not every cell of its bounding box, which for long slanted
// triangles would cover much empty space), for segment queries near a mesh.
class TriangleGrid {
 public:
  TriangleGrid() = default;
  TriangleGrid(const TriangleMesh& mesh, Real cell_size);
  // Calls fn(triangle_id) once per candidate triangle overlapping the box.
  template <class Fn>
  void for_each_candidate(const Aabb& box, Fn&& fn) const;

 private:
  Aabb bounds_;
  Real cell_ = 1.0;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> ids_;
};

template <class Fn>
void TriangleGrid::for_each_candidate(const Aabb& box, Fn&& fn) const {
  if (nx_ == 0) return;
  if ((box.max.array() < bounds_.min.array()).any() || (box.min.array() > bounds_.max.array()).any()) return;
  auto clampi = [](Real v, int n) { return std::max(0, std::min(n - 1, static_cast<int>(v))); };
  const Vec3 lo = (box.min - bounds_.min) / cell_;
  const Vec3 hi = (box.max - bounds_.min) / cell_;
  const int x0 = clampi(lo.x(), nx_), x1 = clampi(hi.x(), nx_);
  const int y0 = clampi(lo.y(), ny_), y1 = clampi(hi.y(), ny_);
  const int z0 = clampi(lo.z(), nz_), z1 = clampi(hi.z(), nz_);
  // Small candidate lists: dedupe by linear scan of what was already visited.
  std::uint32_t seen[64];
  int nseen = 0;
  for (int z = z0; z <= z1; ++z)
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t c = std::size_t(x) + std::size_t(nx_) * (std::size_t(y) + std::size_t(ny_) * z);
        for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
          const std::uint32_t id = ids_[k];
          bool dup = false;
          for (int s = 0; s < nseen; ++s) dup |= (seen[s] == id);
          if (dup) continue;
          if (nseen < 64) seen[nseen++] = id;
          fn(id);
        }
      }
}

}  // namespace bakesim
