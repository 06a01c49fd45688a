// Phase grid: node velocities with gravity and the contact law at colliders and
// domain walls (spec 4.4), and with heat the explicit temperature increment, the
// boundary exchange with the air and hot colliders, and the water ratio (spec
// 4.2, 4.3, 4.6).
#include "mpm/solver.hpp"

#include <algorithm>

#include "core/parallel.hpp"
#include "physics/constants.hpp"
#include "physics/heat.hpp"

namespace bakesim::mpm {

// Spec 4.4: v_i = (m v)_i / m_i + Δt g (Δt g / s with mass scaling), then the collider conditions.
// With heat (spec 4.2, 4.3, 4.6): θ_i = E_i / M_i advanced by the explicit
// rate, Δθ_i kept for the FLIP transfer; the boundary area of the node
// a_i = Δx³ |∇φ|, φ = V_i / Δx³ by central differences (Σ a_i is the surface
// area for any smooth profile of φ; a neighbour without material gives its
// half of the difference to the node, so no area is lost), exchanging
// (physics/heat.hpp, SurfaceExchange) with a hot collider within 3 Δx of the
// node through the part of the area vector Δx³ ∇φ that faces it (all of it
// for a node inside the collider), and with the air through the rest; water:
// the ratio r_i = Δt ΔW_i / W_i, never below −1 (water is never negative; what
// was asked beyond that is counted as clamped), and the saturation s_i for the
// next flux.
void MpmSolver::phase_grid(Real dt) {
  ScopedPhase t(timers_, t_grid_);
  const Vec3 origin = grid_origin_;
  // With mass scaling the weight m g accelerates the inertia s m.
  const Vec3 g = setup_.gravity / setup_.mass_scaling.factor;
  // The domain walls lie on the domain faces (the grid reaches kGuardCells beyond them).
  const ColliderGeometry walls = InsideBoxCollider{setup_.domain, setup_.periodic};  // none on periodic faces
  // A node takes a wall's condition when it lies in the solid or on its face, within
  // a thousandth of a cell (distance < kNodeOnFace Δx): a face on a node plane holds the same whichever side
  // round-off puts the node (a sticky plate 2e-18 m off let its channel run free).
  const Real on_face = kNodeOnFace * dx_;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  // Collider poses at the end of the step, where the nodes' new velocities take the material.
  collider_poses_.resize(setup_.colliders.size());
  for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci)
    collider_poses_[ci] = setup_.colliders[ci].motion.at(time_ + dt);
  const bool heat = thermal();
  const Oven& oven = setup_.oven;
  const Real dtb = oven.bake_step(dt), bake_t = oven.bake_time(time_ + dt);
  const Real air_t = oven.air_temperature(bake_t);
  collider_temperatures_.read(
      setup_.colliders.size(), [&](std::size_t ci) -> const auto& { return setup_.colliders[ci].temperature; }, bake_t);
  const Real inv_rho_w = 1.0 / kWaterDensity;
  const Real clamped = deterministic_reduce(
      grid_.size(), Real(0),
      [&](std::size_t kb, std::size_t ke) {
        Real clamp_sum = 0;
        for (std::size_t k = kb; k < ke; ++k) {
          GridNode& node = grid_[k];
          if (node.mass <= 0 || is_image_node(k)) continue;  // images take their node's result below
          Vec3 v = Vec3(node.mv[0], node.mv[1], node.mv[2]) / node.mass + dt * g;
          const Vec3 xi = origin + dx_ * Vec3(Real(k / syz), Real((k / nz) % ny_), Real(k % nz));
          // Area vector Δx³ ∇φ (into the material) by central differences of V over 2Δx.
          // The part facing each hot collider within 3 Δx exchanges with it, the rest with the air
          // (∇φ reaches 2 Δx into the material; particles rest up to a cell off a wall).
          // Colliders without a temperature insulate the area facing them.
          // (Nodes on the grid's outer layer have no neighbours to difference: no area there.)
          const std::size_t ki = k / syz, kj = (k / nz) % ny_, kk = k % nz;
          const bool inner = ki > 0 && kj > 0 && kk > 0 && ki + 1 < std::size_t(nx_) && kj + 1 < std::size_t(ny_) &&
                             kk + 1 < std::size_t(nz_);
          const HeatSums* sums = heat ? &heat_sums_[k] : nullptr;
          const bool exchange = heat && inner && sums->heat_capacity > 0 && sums->volume > 0;
          Vec3 area = Vec3::Zero();
          if (exchange) {
            // Each difference between neighbouring nodes is shared half and half by the two, and a
            // neighbour without material (which takes no exchange) gives its half to this node: so
            // every face's area lands on nodes that hold material, wherever the face lies between
            // nodes (a face half a cell off a node plane lost the outer node's share: a 40 mm cube
            // in 4 mm cells took in 15% too little heat in its first 3 minutes of bake, 7% with its
            // faces on node planes; tests/verification/test_body_heat.cpp).
            const Real v = sums->volume;
            const std::size_t step[3] = {syz, nz, 1};
            for (int axis = 0; axis < 3; ++axis) {
              const Real below = heat_sums_[k - step[axis]].volume, above = heat_sums_[k + step[axis]].volume;
              area[axis] = (0.5 * inv_dx_) * ((above - v) * (above > 0 ? 1 : 2) + (v - below) * (below > 0 ? 1 : 2));
            }
          }
          SurfaceExchange hot;  // the parts facing hot colliders
          Real hot_area = 0;
          bool near = false;
          for (std::size_t ci = 0; ci < setup_.colliders.size(); ++ci) {
            const Collider& c = setup_.colliders[ci];
            const RigidPose& pose = collider_poses_[ci];
            const WallContact w = signed_distance(c.geometry, pose.to_rest(xi));
            near = near || w.distance < 2 * dx_;
            if (exchange && w.distance < 3 * dx_) {
              const Vec3 n = pose.rotation * w.normal;
              // A node inside the solid holds only the spread of faces that lie against it: all of
              // its area faces the collider (its nearest face's normal need not be the one the
              // material touches: inside a thin wall standing on a floor it is the floor's).
              const bool inside = w.distance < -on_face;
              const Real facing = inside ? area.norm() : std::max(Real(0), area.dot(n));
              area = inside ? Vec3::Zero() : Vec3(area - facing * n);
              if (c.temperature) {
                hot.add(facing, c.heat_transfer_coefficient, collider_temperatures_[ci]);
                hot_area += facing;
              }
            }
            if (w.distance >= on_face) continue;
            const Vec3 vc = pose.velocity_at(xi);
            Vec3 rel = v - vc;
            apply_contact(rel, pose.rotation * w.normal, c.contact);
            v = rel + vc;
          }
          if (!near_collider_.empty()) near_collider_[k] = near;
          for_each_wall(walls, xi, on_face,
                        [&](const WallContact& w) { apply_contact(v, w.normal, setup_.domain_contact); });
          node.mv[0] = v.x(), node.mv[1] = v.y(), node.mv[2] = v.z();
          if (!exchange) {  // no exchange, θ = 0 (a node without mass keeps its old state: below)
            if (heat) heat_state_[k] = HeatState{};
            continue;
          }
          const HeatSums& f = *sums;
          const Real volume = f.volume;
          const Real air_area = area.norm();
          const Real inv_v = 1.0 / volume;
          if (!implicit_mass_.empty()) implicit_mass_[k] = f.heat_capacity;
          const Real theta = f.energy / f.heat_capacity, dtheta = dtb * f.heat_rate / f.heat_capacity;
          Real ratio = 0, sat = 0, vapour_ratio = 0;
          if (f.water > 0) {
            ratio = dtb * f.water_rate / f.water;
            if (ratio < -1) clamp_sum += (-1 - ratio) * f.water, ratio = -1;
            // Moisture: the vapour's share, applied as the liquid's (never below what the node holds).
            vapour_ratio = dtb * f.vapour_rate / f.water;
            if (ratio + vapour_ratio < -1)
              clamp_sum += (-1 - ratio - vapour_ratio) * f.water, vapour_ratio = -1 - ratio;
            sat = (1 + ratio + vapour_ratio) * f.water * inv_rho_w / volume;
          } else {
            // Nothing here to carry what arrives: it is booked as gone, so the budget still closes.
            clamp_sum -= dtb * (f.water_rate + f.vapour_rate);
          }
          SurfaceExchange exchanged = hot;
          exchanged.add(air_area, oven.surface_coefficient(theta, air_t), air_t);
          HeatState& s = heat_state_[k];
          s.dtheta = dtheta;
          s.theta = theta + dtheta;
          s.exchange = exchanged.conductance * inv_v;
          s.exchange_theta = exchanged.drive * inv_v;
          s.exchange_area = (air_area + hot_area) * inv_v;
          s.fill = volume * inv_dx_ * inv_dx_ * inv_dx_;
          s.water_ratio = ratio;
          s.saturation = sat;
          s.air_area = air_area * inv_v;
          s.vapour_ratio = vapour_ratio;
          s.vapour_density = f.vapour * inv_v;
        }
        return clamp_sum;
      },
      [](Real a, Real b) { return a + b; });
  if (heat) {
    budget_.clamped += clamped;
    budget_.evaporated -= clamped;
  }
  mirror_sticky_planes();
  if (periodicity_.any()) {
    copy_periodic(grid_);
    if (heat) copy_periodic(heat_state_);
    if (!near_collider_.empty()) copy_periodic(near_collider_);
  }
}

// No-slip at sticky planes, second order: the nodes within two cells behind
// the plane take the velocity mirrored through it, v = 2 v_plane − v(x'),
// x' the node's mirror image in front of the plane (trilinear from the nodes
// there), instead of the plane's own velocity. The velocity field is then odd
// about the plane, so a shear profile continues through it and the particles
// beside the plane (whose stencils reach behind it) see the wall where the
// plane is; with v_plane on every node behind it they saw it a fraction of a
// cell further out, and a channel between two sticky plates ran 2% fast
// (Newtonian) to 8% (Bingham plug) at 20 cells across. Planes only: material
// never belongs behind a plane, whereas grips (boxes, meshes) hold material
// inside them and keep their own velocity there.
MpmSolver::WorldPlane MpmSolver::world_plane(std::size_t collider, const RigidPose& pose) const {
  const PlaneCollider& plane = std::get<PlaneCollider>(setup_.colliders[collider].geometry);
  return {pose.rotation * plane.normal, pose.to_world(plane.point)};
}

void MpmSolver::mirror_sticky_planes() {
  if (sticky_planes_.empty()) return;
  for (std::size_t s = 0; s < sticky_planes_.size(); ++s)
    sticky_world_[s] = world_plane(sticky_planes_[s], collider_poses_[sticky_planes_[s]]);
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real on_face = kNodeOnFace * dx_;
  auto node_position = [&](std::size_t k) {
    return Vec3(grid_origin_ + dx_ * Vec3(Real(k / syz), Real((k / nz) % ny_), Real(k % nz)));
  };
  // Where the flow is: nodes with mass in front of every sticky plane (by more than on_face).
  auto in_front = [&](const Vec3& x) {
    for (const WorldPlane& plane : sticky_world_)
      if (plane.distance(x) < on_face) return false;
    return true;
  };
  mirror_velocity_.resize(grid_.size());
  parallel_for(
      grid_.size(),
      [&](std::size_t k) {
        const GridNode& node = grid_[k];
        const bool flow = node.mass > 0 && in_front(node_position(k));
        mirror_velocity_[k] = flow ? Vec4(node.mv[0], node.mv[1], node.mv[2], 1) : Vec4::Zero();
      },
      4096);
  parallel_for(
      grid_.size(),
      [&](std::size_t k) {
        GridNode& node = grid_[k];
        if (node.mass <= 0) return;
        const Vec3 xi = node_position(k);
        for (std::size_t s = 0; s < sticky_planes_.size(); ++s) {  // s: a sticky plane (k is the node)
          const RigidPose& pose = collider_poses_[sticky_planes_[s]];
          const WorldPlane& plane = sticky_world_[s];
          const Real distance = plane.distance(xi);
          if (distance >= -on_face || distance < -2 * dx_) continue;  // on or in front of the face, or deep
          const Vec3 mirror = xi - 2 * distance * plane.normal;
          // Trilinear over the flow nodes around the mirror point (weights renormalised).
          const Vec3 g = (mirror - grid_origin_) * inv_dx_;
          const Vec3 base = g.array().floor().matrix();
          const Vec3 f = g - base;
          Vec4 sum = Vec4::Zero();
          for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
              for (int c = 0; c < 2; ++c) {
                const long ix = long(base.x()) + a, iy = long(base.y()) + b, iz = long(base.z()) + c;
                if (ix < 0 || iy < 0 || iz < 0 || ix >= nx_ || iy >= ny_ || iz >= nz_) continue;
                const Real wt = (a ? f.x() : 1 - f.x()) * (b ? f.y() : 1 - f.y()) * (c ? f.z() : 1 - f.z());
                sum += wt * mirror_velocity_[std::size_t(ix) * syz + std::size_t(iy) * nz + std::size_t(iz)];
              }
          if (sum[3] < 0.5) continue;  // no flow in front to mirror: keep the plane's velocity
          const Vec3 v_flow = sum.head<3>() / sum[3];
          const Vec3 v = 2 * pose.velocity_at(xi) - v_flow;
          node.mv[0] = v.x(), node.mv[1] = v.y(), node.mv[2] = v.z();
          break;
        }
      },
      4096);
}

}  // namespace bakesim::mpm
