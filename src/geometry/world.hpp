#pragma once
// Where a run happens, the same for both solvers: the domain box and the
// contact law of its walls, gravity and the inertia it accelerates, the
// colliders and the oven. Each
// solver's Setup adds its settings, materials and bodies.
#include <array>
#include <vector>

#include "core/types.hpp"
#include "geometry/colliders.hpp"
#include "geometry/contact.hpp"
#include "geometry/periodic.hpp"
#include "physics/mass_scaling.hpp"
#include "physics/oven.hpp"

namespace bakesim {

struct World {
  Aabb domain;
  // The domain walls: separating contact; the friction model is the scene's
  // domain.friction_model (auto: velocity share for SPH, Coulomb for MPM).
  ContactLaw domain_contact;
  // Axes along which the domain is periodic (no walls on those faces).
  std::array<bool, 3> periodic{false, false, false};
  Periodicity periodicity() const { return Periodicity{domain, periodic}; }
  Vec3 gravity = Vec3(0, -9.81, 0);
  MassScaling mass_scaling;  // solver.mass_scaling (physics/mass_scaling.hpp)
  // SPH: analytic colliders and meshes; MPM: colliders act on the grid nodes
  // inside them (signed distance ≤ 0) through their velocity relative to their
  // own, mesh colliders through their signed distance grid.
  std::vector<Collider> colliders;
  Oven oven;  // air, bake clock, browning (physics/oven.hpp)
};

}  // namespace bakesim
