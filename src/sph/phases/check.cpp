// Health check after each step: non-finite state, a particle outside the
// domain or a collapsed density stops the run with the particle named.
#include "sph/solver.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"
#include "core/health.hpp"

namespace bakesim::sph {

void SphSolver::check_finite() {
  ScopedPhase t(timers_, t_check_);
  const std::size_t n = x_.size();
  // Non-finite state, a particle outside the domain, or a density collapsed
  // below 1% of the rest density (a particle that lost all its neighbours
  // while inside the fluid: the pressure has blown the fluid apart).
  auto collapsed = [&](std::size_t i) { return rho_[i] < 0.01 * setup_.materials[material_[i]].rest_density; };
  const std::size_t bad = first_invalid(n, [&](std::size_t i) {
    return x_[i].allFinite() && v_[i].allFinite() && std::isfinite(rho_[i]) && std::isfinite(p_[i]) &&
           std::isfinite(temperature_[i]) && setup_.domain.contains(x_[i]) && !collapsed(i);
  });
  if (bad == n) return;
  const std::string quantity = !x_[bad].allFinite()                ? "non-finite position"
                               : !v_[bad].allFinite()              ? "non-finite velocity"
                               : !std::isfinite(rho_[bad])         ? "non-finite density"
                               : !std::isfinite(p_[bad])           ? "non-finite pressure"
                               : !std::isfinite(temperature_[bad]) ? "non-finite temperature"
                               : !setup_.domain.contains(x_[bad])  ? "position outside the domain"
                                                                   : "collapsed density";
  std::string neighbours;
  const bool listed = bad < lists_.size();
  const std::uint32_t* nb = listed ? lists_.begin(bad) : nullptr;
  const std::uint32_t count = listed ? lists_.count(bad) : 0;
  for (std::uint32_t k = 0; k < std::min<std::uint32_t>(count, 4); ++k) {
    const std::uint32_t j = nb[k];
    neighbours +=
        fmt::format("{}particle {} (x ({:.4g}, {:.4g}, {:.4g}), v ({:.4g}, {:.4g}, {:.4g}), density {:.6g}, T {:.4g})",
                    k ? "; " : "", id_[j], x_[j].x(), x_[j].y(), x_[j].z(), v_[j].x(), v_[j].y(), v_[j].z(), rho_[j],
                    temperature_[j]);
  }
  throw SimulationError(
      fmt::format("SPH step {} (t = {:.6g} s): particle {} of body '{}' has a {}: x ({:.4g}, {:.4g}, {:.4g}), v "
                  "({:.4g}, {:.4g}, {:.4g}), "
                  "density {:.6g} kg/m^3, pressure {:.6g} Pa, T {:.4g} degC, {} neighbours{}{}",
                  steps_, time_, id_[bad], setup_.bodies[body_[bad]].name, quantity, x_[bad].x(), x_[bad].y(),
                  x_[bad].z(), v_[bad].x(), v_[bad].y(), v_[bad].z(), rho_[bad], p_[bad], temperature_[bad], count,
                  count ? ": " : "", neighbours));
}

// The neighbour grid covers the domain with cells of the largest support
// radius: positions inside it, support radii within the adaptive limits.
std::string SphSolver::restored_state_problem() const {
  const AdaptiveSmoothing& a = setup_.settings.adaptive;
  const Real h_lo = (adaptive_ ? a.min_ratio : 1.0) * h_ * (1 - 1e-9),
             h_hi = (adaptive_ ? a.max_ratio : 1.0) * h_ * (1 + 1e-9);
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const char* what = !setup_.domain.contains(x_[i])                      ? "a position outside the domain"
                       : !(m_[i] > 0)                                      ? "a mass <= 0"
                       : !(rho_[i] > 0)                                    ? "a density <= 0"
                       : !(smoothing_[i] >= h_lo && smoothing_[i] <= h_hi) ? "a support radius outside its limits"
                                                                           : nullptr;
    if (what) return fmt::format("particle entry {} (id {}) has {}", i, id_[i], what);
  }
  // The heat waits at most kMaxHeatEverySteps steps of at most max_dt (heat_due).
  if (heat_pending_ > kMaxHeatEverySteps * setup_.settings.max_dt * (1 + 1e-9))
    return fmt::format("its heat is {:.3g} s behind, more than {} steps of max_dt", heat_pending_, kMaxHeatEverySteps);
  return {};
}

}  // namespace bakesim::sph
