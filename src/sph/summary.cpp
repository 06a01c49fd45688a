// What an SPH run will simulate, for `bakesim validate`.
#include <fmt/format.h>

#include "sph/solver.hpp"

namespace bakesim::sph {

std::string SphSolver::summary() const {
  const Settings& st = setup_.settings;
  std::string out;
  out += fmt::format("spacing    {} m, support h = {} m, speed of sound {:.3g} m/s, neighbour search {}\n", st.spacing,
                     st.spacing * st.smoothing_ratio, st.speed_of_sound, to_string(st.search));
  if (divergence_free_)
    out += fmt::format(
        "pressure   divergence-free (DFSPH): density tolerance {:g}, divergence tolerance {:g}, at most {} iterations "
        "(the speed of sound only enters the artificial viscosity)\n",
        st.density_tolerance, st.divergence_tolerance, st.pressure_max_iterations);
  else
    out += "pressure   weakly compressible (Tait)\n";
  out += setup_.mass_scaling.summary_line("pressure and elastic waves");
  out += fmt::format("viscosity  {} (setting: {})\n", implicit_viscosity() ? "implicit" : "explicit",
                     to_string(st.viscosity_solver));
  if (elastic_)
    out += fmt::format("elasticity {} (Maxwell stress; setting: {})\n", implicit_elasticity_ ? "implicit" : "explicit",
                       st.implicit_elasticity ? "implicit" : "explicit");
  out += fmt::format("surface    {} test\n", to_string(st.surface_method));
  if (periodic_) out += fmt::format("periodic   along {} (no walls on those faces)\n", periodicity_.describe());
  for (const Material& m : setup_.materials)
    if (elastoviscoplastic(m))
      out += fmt::format(
          "yield flow material {}: Herschel-Bulkley, n = {}, elastoviscoplastic (elastic below the yield stress)\n",
          m.name, m.yield_flow->flow_index);
    else if (m.yield_flow)
      out += fmt::format("yield flow material {}: Herschel-Bulkley, n = {}, regularisation rate {} 1/s\n", m.name,
                         m.yield_flow->flow_index, m.yield_flow->regularisation);
  out += fmt::format("particles  {} in total\n", particles_.size());
  for (std::size_t b = 0; b < setup_.bodies.size(); ++b) {
    const Body& body = setup_.bodies[b];
    out += fmt::format("  body {:<16} {:>9} particles  material {:<10} mass {:.4g} kg each, {:.1f} degC\n",
                       "'" + body.name + "'", body_particle_count(b), setup_.materials[body.material].name,
                       particle_mass(body.material), body.temperature);
    out += fmt::format("    fills {:.1f}% of its shape's volume\n", 100 * body_fill_.at(b).fraction);
    if (body.bubbles.fraction > 0) {
      std::size_t count = 0;
      for (std::size_t i = 0; i < bubble_.size(); ++i) count += body_[i] == int(b) && bubble_[i];
      out += fmt::format("    {} bubble particles ({:.1f}%)\n", count, 100.0 * count / body_particle_count(b));
    }
  }
  out += fmt::format("colliders  {}\n", setup_.colliders.size());
  for (const Collider& c : setup_.colliders)
    out += fmt::format("  '{}' friction {} damping {}{}{}\n", c.name, c.contact.friction, c.contact.damping,
                       c.contact.mode == ContactMode::sticky ? ", sticky (no-slip)" : "",
                       c.motion.moves() ? ", moving" : "");
  out += "time step  bounds at t = 0:\n";
  for (const StepBound& b : time_step_bounds())
    out += fmt::format("  {:<10} {:.3e} s{}\n", b.name, b.dt,
                       setup_.settings.heat_own_step && b.heat ? " (the heat's own step)" : "");
  return out;
}

}  // namespace bakesim::sph
