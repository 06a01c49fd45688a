// Phase surface: colour gradient, surface particles and their exchange areas
// (thesis 3.1.8, Eq 3.28, 3.43).
#include "sph/solver.hpp"

#include <tbb/enumerable_thread_specific.h>

#include "core/parallel.hpp"

namespace bakesim::sph {

namespace {

// Fewer neighbours than this (a full support holds about 33 at h = 2s) mark a
// particle as surface whatever its colour gradient.
constexpr std::uint32_t kSparseNeighbours = 6;

// Half-angle of the scan cone: a colour-field candidate with a neighbour
// within this angle of its outward normal has material above it and is not
// surface. cos 40°: on a lattice (faces, edges, the staircase of a curved
// face) the nearest neighbour off the normal sits at 45° or more, so every
// outer-layer particle stays surface.
constexpr Real kScanConeCos = 0.766044443118978;

}  // namespace

// Colour gradient ∇C_i = Σ V_j ∇W_ij (Eq 3.28; points into the fluid) and the
// surface particles (thesis 3.1.8): |∇C| h above a threshold (colour), or the
// local convex hull test (convex_hull, every `surface_every` steps), and their
// exchange areas.
void SphSolver::phase_surface(bool flags) {
  ScopedPhase t(timers_, t_surface_);
  const Settings& s = setup_.settings;
  const std::size_t n = x_.size();
  // The grid of open space follows the anchors and their radii at the last
  // search: built when the flags are next wanted (below).
  if (s.surface_open_space && anchors_moved_) {
    parallel_for(
        n, [&](std::size_t i) { fill_radius_[i] = std::cbrt(m_[i] / rho_[i]); }, 4096);
    open_space_built_ = false;
  }
  // Between heat steps only surface tension reads the colour gradient.
  if (!flags && !surface_tension_) return;
  colour_grad_.resize(n);
  parallel_for(n, [&](std::size_t i) {
    Vec3 grad = Vec3::Zero();
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pd = pair_dwr_.data() + i * lists_.stride();
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      grad += (m_[j] / rho_[j] * Real(pd[k])) * pair_offset(i, j);
    }
    colour_grad_[i] = grad;
  });
  if (!flags) return;
  if (s.surface_method == SurfaceMethod::colour) {
    const Real threshold = s.surface_colour_threshold;
    // A particle with almost no neighbours (blown off, or at the tip of an
    // expanded bubble) has a vanishing gradient but is surface all the same.
    // The colour test alone also flags the crumb of a risen dough: once the
    // bubbles have grown, a support holds fewer and unevenly spread
    // neighbours, |∇C| h is large deep inside, and over half of the particles
    // two spacings or more under the crust exchanged heat with the oven air
    // (issue 20). A candidate keeps its flag only if no neighbour lies in the
    // cone around its outward normal −∇C (the scan region of Marrone et al.
    // 2010, CMAME 199, reduced to its cone): a particle with material above
    // it is not on the surface.
    parallel_for(
        n,
        [&](std::size_t i) {
          const std::uint32_t count = lists_.count(i);
          if (count < kSparseNeighbours) {
            surface_[i] = 1;
            return;
          }
          const Real g = colour_grad_[i].norm();
          if (g * smoothing_[i] < threshold) {
            surface_[i] = 0;
            return;
          }
          const Vec3 outward = -colour_grad_[i] / g;
          const std::uint32_t* nb = lists_.begin(i);
          const float* r = lists_.distances(i);
          bool covered = false;
          for (std::uint32_t k = 0; k < count && !covered; ++k)
            covered = -pair_offset(i, nb[k]).dot(outward) > kScanConeCos * Real(r[k]);
          surface_[i] = covered ? 0 : 1;
        },
        4096);
  } else if (steps_ % s.surface_every == 0) {
    const Real threshold = s.surface_hull_threshold * s.spacing;
    struct Scratch {
      LocalConvexHull hull;
      std::vector<Vec3> points;
    };
    tbb::enumerable_thread_specific<Scratch> scratch;
    parallel_for(
        n,
        [&](std::size_t i) {
          Scratch& sc = scratch.local();
          sc.points.clear();
          const std::uint32_t* nb = lists_.begin(i);
          for (std::uint32_t k = 0; k < lists_.count(i); ++k) sc.points.push_back(x_[i] - pair_offset(i, nb[k]));
          surface_[i] = sc.hull.distance_to_boundary(x_[i], sc.points.data(), sc.points.size()) < threshold ? 1 : 0;
        },
        64);
  }
  // With `open_space`, flags that face no open space go (docs/physics.md, "Surface particles"):
  // a risen crumb holds voids where bubbles grew, and a particle beside one
  // passes both tests above although no oven air reaches it. Every particle
  // fills a ball of its own size on a grid of the spacing; the empty space
  // that floods from the border is open; a flagged particle stays surface only
  // if open space lies along its outward normal within its own size and two
  // spacings (where the space beyond a flat face's outer layer begins). The
  // grid is built on the neighbour search's anchors, again only when it
  // searches: the particles have moved less than half the Verlet skin since
  // (0.1 h by default), a fraction of the grid's cell.
  if (s.surface_open_space && !open_space_built_) {
    open_space_.build(anchor_, fill_radius_, s.spacing);
    open_space_built_ = true;
  }
  if (s.surface_open_space && (s.surface_method == SurfaceMethod::colour || steps_ % s.surface_every == 0)) {
    parallel_for(
        n,
        [&](std::size_t i) {
          const Real g = colour_grad_[i].norm();
          if (!surface_[i] || !(g > 0)) return;  // a lone particle has no normal and stays surface
          if (!open_space_.open_along(x_[i], -colour_grad_[i] / g, fill_radius_[i] + 2 * s.spacing)) surface_[i] = 0;
        },
        4096);
  }
  // Exchange areas from the surface itself (a departure from Eq 3.43's π r² for
  // every surface particle, which took in 21% too much on a lattice-aligned face
  // and 7–9% too little on a curved one): by the co-area formula Σ V |∇C| over
  // the surface layer is the area it holds of the colour's drop; divided by that
  // share on a flat face, the areas sum to the surface's (docs/physics.md).
  const Real inv_share = 1.0 / colour_share_;
  parallel_for(
      n, [&](std::size_t i) { area_[i] = surface_[i] ? m_[i] / rho_[i] * colour_grad_[i].norm() * inv_share : 0.0; },
      4096);
}

}  // namespace bakesim::sph
