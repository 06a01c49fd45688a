// What an MPM run will simulate, for `bakesim validate`.
#include <fmt/format.h>

#include "mpm/solver.hpp"

namespace bakesim::mpm {

std::string MpmSolver::summary() const {
  const Settings& ms = setup_.settings;
  std::string out;
  out += fmt::format("grid       cell {} m, {} particles per cell, {} x {} x {} nodes\n", ms.cell_size,
                     ms.particles_per_cell, nx_, ny_, nz_);
  out += fmt::format("heat       {}{}\n",
                     ms.heat == HeatMethod::off        ? "off"
                     : ms.heat == HeatMethod::implicit ? "implicit"
                                                       : "explicit",
                     ms.baseline ? " (baseline model: no gas, no water)" : "");
  out += setup_.mass_scaling.summary_line("elastic waves");
  if (periodicity_.any())
    out +=
        fmt::format("periodic   along {} (no walls on those faces; guard nodes are images)\n", periodicity_.describe());
  out += fmt::format("particles  {} in total, mass {:.4g} kg\n", particles_.size(), total_mass());
  for (std::size_t b = 0; b < setup_.bodies.size(); ++b)
    out += fmt::format("  body {:<16} fills {:.1f}% of its shape's volume\n", "'" + setup_.bodies[b].name + "'",
                       100 * body_fill_.at(b).fraction);
  for (const Material& mat : setup_.materials)
    out += fmt::format("  material {:<12} rho {} kg/m^3, mu {:.4g} Pa, lambda {:.4g} Pa, {}, {}\n", mat.name,
                       mat.density, mat.lame.mu, mat.lame.lambda,
                       std::holds_alternative<Hencky>(mat.elastic) ? "hencky" : "fixed corotated",
                       std::holds_alternative<VonMises>(mat.plastic)              ? "von Mises plasticity"
                       : std::holds_alternative<CamClay>(mat.plastic)             ? "Cam-clay plasticity"
                       : std::holds_alternative<HerschelBulkleyFlow>(mat.plastic) ? "Herschel-Bulkley flow"
                                                                                  : "elastic");
  out += fmt::format("colliders  {}\n", setup_.colliders.size());
  for (const Collider& c : setup_.colliders)
    out += fmt::format("  '{}' {} contact, friction {}{}\n", c.name,
                       c.contact.mode == ContactMode::sticky ? "sticky"
                       : c.contact.mode == ContactMode::slip ? "slip"
                                                             : "separate",
                       c.contact.friction, c.motion.moves() ? ", moving" : "");
  return out;
}

}  // namespace bakesim::mpm
