// Phase collide: walls, colliders and meshes (Eq 3.31–3.33, thesis 3.1.9).
#include "sph/solver.hpp"

#include "core/parallel.hpp"

namespace bakesim::sph {

// Eq 3.31–3.33 through the shared contact law (geometry/contact.hpp): by
// default v_new = β_c v_tangent − α_c v_normal with β_c = 1 − friction and
// α_c = 1 − damping, on the velocity relative to a moving collider. Analytic
// walls push the particle back to the contact distance; meshes revert it to
// its previous position (thesis 3.1.9). Along periodic axes a particle
// that left the box comes back through the opposite face.
void SphSolver::phase_collide() {
  ScopedPhase t(timers_, t_collide_);
  const Real rc = contact_distance_;
  // At a sticky wall, in contact means closer than the contact distance by
  // more than 1%: a lattice layer laid s/2 from the wall, and the pressure
  // noise around it, are not. A sticky wall stops what touches it; the flow
  // beside it is held by the wall's viscous stress (compute_wall_drag), so
  // stopping every particle that round-off or noise brought a hair inside
  // would pin whole layers at a rate set by the time step.
  const Real sticky_reach = 0.99 * rc;
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        Vec3& xi = x_[i];
        Vec3& vi = v_[i];
        for (std::size_t c = 0; c < walls_.size(); ++c) {
          const ContactLaw& law = walls_[c].contact;
          const Real reach = law.mode == ContactMode::sticky ? sticky_reach : rc;
          for_each_wall_of(c, xi, reach, [&](const WallContact& w, const Vec3& wall_velocity) {
            xi += (rc - w.distance) * w.normal;
            if (!walls_[c].motion.moves()) return apply_contact(vi, w.normal, law);
            Vec3 relative = vi - wall_velocity;
            apply_contact(relative, w.normal, law);
            vi = relative + wall_velocity;
          });
        }
        for (const Collider& c : meshes_) {
          const MeshCollider& mesh = std::get<MeshCollider>(c.geometry);
          const SegmentHit hit = mesh_segment_hits(mesh, x_prev_[i], xi, rc);
          if (hit.hits > 0) {
            const Real len = hit.normal_sum.norm();
            const Vec3 n = len > 0 ? Vec3(hit.normal_sum / len) : Vec3::UnitY();
            // Keep the part of the step along the surface when that path is
            // free: a particle sent back to x_{t−1} on every step would never
            // slide down a slope while gravity kept feeding its velocity.
            const Vec3 d = xi - x_prev_[i];
            const Real dn = d.dot(n);
            const Vec3 slid = x_prev_[i] + (dn < 0 ? Vec3(d - dn * n) : d);
            xi = mesh_segment_hits(mesh, x_prev_[i], slid, rc).hits == 0 ? slid : x_prev_[i];
            apply_contact(vi, n, c.contact);
          }
        }
        if (periodic_) xi = periodicity_.wrap(xi);  // out through one periodic face, in through the other
      },
      1024);
}

void SphSolver::update_wall_poses(Real time) {
  wall_poses_.resize(walls_.size());
  for (std::size_t c = 0; c < walls_.size(); ++c)
    if (walls_[c].motion.moves()) wall_poses_[c] = walls_[c].motion.at(time);
}

}  // namespace bakesim::sph
