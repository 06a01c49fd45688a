#pragma once
// Surface particles (thesis 3.1.8): the local convex hull test of Mao and
// Yang, computed with Quickhull (qhull), and the cheaper colour-field test.
#include <cstdio>
#include <string>
#include <vector>

#include "core/types.hpp"

struct qhT;  // qhull's reentrant state

namespace bakesim::sph {

enum class SurfaceMethod { colour, convex_hull };
SurfaceMethod parse_surface_method(const std::string& name);
std::string to_string(SurfaceMethod m);

// The convex hull of a particle and its neighbours. A particle whose distance
// to the hull's boundary is below a threshold lies on the surface (interior
// particles are surrounded by neighbours on every side, so the hull boundary
// is about one support radius away). One instance per thread: qhull's state
// is reused between calls.
class LocalConvexHull {
 public:
  LocalConvexHull();
  ~LocalConvexHull();
  LocalConvexHull(const LocalConvexHull&) = delete;
  LocalConvexHull& operator=(const LocalConvexHull&) = delete;

  // Distance (m) from `centre` to the boundary of conv({centre} ∪ points);
  // 0 when the hull is flat or degenerate (fewer than four points off one
  // plane): such a particle has nothing on at least one side.
  Real distance_to_boundary(const Vec3& centre, const Vec3* points, std::size_t count);

 private:
  std::vector<double> coords_;
  std::FILE* sink_ = nullptr;  // qhull's message stream (discarded)
};

}  // namespace bakesim::sph
