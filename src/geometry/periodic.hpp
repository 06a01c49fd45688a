#pragma once
// Periodic boundaries of the domain box (scene key domain.periodic): along a
// periodic axis what leaves through one face comes back through the other,
// neighbours see each other across the faces, and that axis has no walls.
// Both solvers use it; a channel flow (Poiseuille start-up, a Bingham plug)
// is a periodic box between two plates.
#include <array>
#include <cmath>
#include <string>

#include "core/types.hpp"

namespace bakesim {

struct Periodicity {
  Aabb box;
  std::array<bool, 3> axes{false, false, false};

  bool any() const { return axes[0] || axes[1] || axes[2]; }
  bool along(int k) const { return axes[std::size_t(k)]; }
  // The point moved by whole box lengths into [min, max) along periodic axes.
  Vec3 wrap(Vec3 p) const {
    for (int k = 0; k < 3; ++k) {
      if (!along(k)) continue;
      const Real length = box.max[k] - box.min[k];
      Real u = p[k] - box.min[k];
      if (u < 0 || u >= length) u -= std::floor(u / length) * length;
      // floor can round u up to exactly `length` for u just below 0.
      p[k] = box.min[k] + (u < length ? u : Real(0));
    }
    return p;
  }
  // The shortest of the displacements d + n·L along periodic axes (the
  // nearest image), for pairs closer than half a box length.
  Vec3 nearest_image(Vec3 d) const {
    for (int k = 0; k < 3; ++k) {
      if (!along(k)) continue;
      const Real length = box.max[k] - box.min[k];
      if (d[k] > 0.5 * length)
        d[k] -= length;
      else if (d[k] < -0.5 * length)
        d[k] += length;
    }
    return d;
  }
  // "x", "x, z", ... ("none" when no axis is periodic), for messages.
  std::string describe() const {
    std::string s;
    for (int k = 0; k < 3; ++k)
      if (along(k)) s += std::string(s.empty() ? "" : ", ") + char('x' + k);
    return s.empty() ? "none" : s;
  }
};

}  // namespace bakesim
