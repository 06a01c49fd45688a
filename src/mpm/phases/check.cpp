// Phase browning (Zanoni et al. 1995 on the bake clock) and the health check
// after each step.
#include "mpm/solver.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "core/errors.hpp"
#include "core/health.hpp"
#include "core/parallel.hpp"

namespace bakesim::mpm {

// Crust colour (Zanoni et al. 1995, physics/browning.hpp) after this step's
// heat transfer, on the bake clock. A point with area facing the air browns at
// its face's temperature (physics/heat.hpp, CrustFace; the face is the fill's
// level 1/2, `face_depth_` away, as in G2P's exchange): the point takes the
// face's heat through its depth in series (G2P), so its face stands above it
// by the same profile, through its dried crust and the moist part below it
// (k_m the point's conductivity with the heat pipe), or through the whole
// depth where it holds no water. Faces against hot colliders take the point's
// temperature.
void MpmSolver::phase_browning(Real dt) {
  ScopedPhase t(timers_, t_browning_);
  const Oven& oven = setup_.oven;
  const Real air = oven.air_temperature(bake_time());
  const Real dt_bake = oven.bake_step(dt);
  parallel_for(
      x_.size(),
      [&](std::size_t p) {
        const Real theta = temperature_[p];
        const Material& mat = setup_.materials[material_[p]];
        const PoreWater& pw = mat.moisture;
        surface_temperature_[p] = theta;
        if (air_area_[p] > 0) {
          const Real kappa = mat.conductivity + cell_k_[p];
          CrustFace face;
          if (moist_ && pw.active()) {
            face = pw.crust_face(face_depth_[p], moisture_[p], water_[p], mat.conductivity, kappa);
          } else {
            face.face_distance = face_depth_[p];
            face.crust_conductivity = face.moist_conductivity = kappa;
          }
          surface_temperature_[p] = face.temperature(theta, air, oven.surface_coefficient(theta, air));
        }
        // Moist dough browns only above its boiling point (physics/browning.hpp, advance_above).
        browning_[p] =
            oven.browning.advance_above(browning_[p], surface_temperature_[p], pw.browning_threshold(moist_), dt_bake);
      },
      4096);
}

void MpmSolver::check_state() {
  ScopedPhase t(timers_, t_check_);
  const std::size_t n = x_.size();
  // G2P keeps points inside the domain; a cell beyond it the stencil still fits the grid.
  const Aabb reach{setup_.domain.min - Vec3::Constant(dx_), setup_.domain.max + Vec3::Constant(dx_)};
  // Every point every step, and a bad one is rare: the tests joined by &
  // rather than && (no branch each), the position's finiteness in the reach
  // test (NaN and infinity fail it). The message below sorts out which failed.
  const std::size_t bad = first_invalid(n, [&](std::size_t i) {
    const Vec3& v = v_[i];
    return bool(reach.contains(x_[i]) & std::isfinite(v.x()) & std::isfinite(v.y()) & std::isfinite(v.z()) &
                (j_[i] > 0) & std::isfinite(temperature_[i]) & (water_[i] >= 0));
  });
  if (bad == n) return;
  const char* what = !x_[bad].allFinite()                ? "position"
                     : !v_[bad].allFinite()              ? "velocity"
                     : !(j_[bad] > 0)                    ? "J (volume ratio)"
                     : !reach.contains(x_[bad])          ? "position (left the domain)"
                     : !std::isfinite(temperature_[bad]) ? "temperature"
                                                         : "water mass";
  throw SimulationError(
      fmt::format("mpm step {} (t = {:.6g} s): particle {} has an invalid {}: x = ({:.4g}, {:.4g}, {:.4g}), v = "
                  "({:.4g}, {:.4g}, {:.4g}), J = {:.4g}, "
                  "temperature = {:.4g} degC, water = {:.4g} kg",
                  steps_ + 1, time_, id_[bad], what, x_[bad].x(), x_[bad].y(), x_[bad].z(), v_[bad].x(), v_[bad].y(),
                  v_[bad].z(), j_[bad], temperature_[bad], water_[bad]));
}

// Restored points must lie inside the domain, where the solver keeps them.
std::string MpmSolver::restored_state_problem() const {
  const Vec3 lo = setup_.domain.min, hi = setup_.domain.max;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const char* what = !((x_[i].array() >= lo.array()).all() && (x_[i].array() <= hi.array()).all())
                           ? "a position outside the domain"
                       : !(j_[i] > 0)       ? "a volume ratio J <= 0"
                       : !(m_[i] > 0)       ? "a mass <= 0"
                       : !(volume0_[i] > 0) ? "an initial volume <= 0"
                       : !(water_[i] >= 0)  ? "a negative water mass"
                                            : nullptr;
    if (what) return fmt::format("particle entry {} (id {}) has {}", i, id_[i], what);
  }
  return {};
}

}  // namespace bakesim::mpm
