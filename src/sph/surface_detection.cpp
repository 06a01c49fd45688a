#include "sph/surface_detection.hpp"

#include <algorithm>
#include <limits>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "core/errors.hpp"

namespace bakesim::sph {

SurfaceMethod parse_surface_method(const std::string& name) {
  if (name == "colour") return SurfaceMethod::colour;
  if (name == "convex_hull") return SurfaceMethod::convex_hull;
  throw InputError("solver.sph.surface.method", "unknown surface method '" + name + "' (colour, convex_hull)");
}

std::string to_string(SurfaceMethod m) { return m == SurfaceMethod::colour ? "colour" : "convex_hull"; }

LocalConvexHull::LocalConvexHull() : sink_(std::fopen("/dev/null", "w")) {}

LocalConvexHull::~LocalConvexHull() {
  if (sink_) std::fclose(sink_);
}

Real LocalConvexHull::distance_to_boundary(const Vec3& centre, const Vec3* points, std::size_t count) {
  if (count < 3) return 0.0;
  // Coordinates relative to the particle: the particle is the origin, and
  // qhull's hyperplane offsets are then its signed distances.
  coords_.resize(3 * (count + 1));
  coords_[0] = coords_[1] = coords_[2] = 0.0;
  for (std::size_t k = 0; k < count; ++k)
    for (int d = 0; d < 3; ++d) coords_[3 * (k + 1) + d] = points[k][d] - centre[d];
  qhT qh_state;
  qhT* qh = &qh_state;
  qh_zero(qh, sink_);
  // Qt: triangulated output; the lattice's coplanar points are merged by
  // default, so precision problems do not stop the build.
  char flags[] = "qhull Qt";
  const int exitcode = qh_new_qhull(qh, 3, static_cast<int>(count + 1), coords_.data(), False, flags, nullptr, sink_);
  Real distance = 0.0;
  if (exitcode == 0) {
    distance = std::numeric_limits<Real>::infinity();
    facetT* facet;
    FORALLfacets {
      // Hyperplane n·x + offset = 0 with outward n: the origin lies at −offset inside.
      distance = std::min(distance, static_cast<Real>(-facet->offset));
    }
    distance = std::max(distance, 0.0);
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  return distance;
}

}  // namespace bakesim::sph
