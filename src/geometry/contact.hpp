#pragma once
// The contact law both solvers use at colliders and domain walls. It acts on
// the velocity relative to the collider (moving colliders carry the material
// with them), given the collider's outward unit normal n at the contact:
//   sticky    v_rel = 0 (grips hold what lies inside them)
//   slip      the normal part is removed, in either direction
//   separate  the normal part is removed only while moving in (v·n < 0)
// then friction on the tangential part v_t:
//   coulomb         |v_t| shrinks by μ |v_n| (friction ∝ the removed normal speed), never past 0
//   velocity_share  v_t ← (1 − friction) v_t (thesis Eq 3.33, β_c = 1 − friction)
// and damping of the normal part: v ← v_t − (1 − damping) v_n (Eq 3.33,
// α_c = 1 − damping: 1 removes it, 0 bounces elastically).
#include <algorithm>
#include <cmath>

#include "core/types.hpp"

namespace bakesim {

enum class ContactMode { sticky, slip, separate };
enum class FrictionModel { coulomb, velocity_share };

struct ContactLaw {
  ContactMode mode = ContactMode::separate;
  FrictionModel friction_model = FrictionModel::coulomb;
  Real friction = 0.0;  // Coulomb μ, or the share of the tangential velocity removed
  Real damping = 1.0;   // share of the normal velocity removed (1: no bounce)
};

// Applies the law to v (the velocity relative to the collider) at normal n.
inline void apply_contact(Vec3& v, const Vec3& n, const ContactLaw& law) {
  if (law.mode == ContactMode::sticky) {
    v.setZero();
    return;
  }
  const Real vn = v.dot(n);
  if (law.mode == ContactMode::separate && vn >= 0) return;  // leaving the wall
  if (law.friction_model == FrictionModel::velocity_share) {
    const Vec3 normal = vn * n;
    const Vec3 tangent = v - normal;
    v = (1.0 - law.friction) * tangent - (1.0 - law.damping) * normal;
    return;
  }
  Vec3 vt = v - vn * n;
  const Real pressure = std::abs(std::min(vn, Real(0)));
  const Real t = vt.norm();
  if (law.friction > 0 && t > 0) vt *= std::max(Real(0), 1 - law.friction * pressure / t);
  v = law.damping == 1.0 ? vt : Vec3(vt - (1.0 - law.damping) * (vn * n));
}

}  // namespace bakesim
