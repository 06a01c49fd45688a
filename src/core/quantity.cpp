#include "core/quantity.hpp"

#include <fmt/format.h>

#include "core/errors.hpp"

namespace bakesim {

ParticleQuantity ParticleQuantity::resolve(const ParticleSet& particles, const std::string& name,
                                           const std::string& where) {
  ParticleQuantity q;
  for (const auto& a : particles.scalars())
    if (a.info.name == name) {
      q.scalar_ = &a.data;
      return q;
    }
  const char* derived[] = {"velocity_x", "velocity_y", "velocity_z"};
  for (int k = 0; k < 3; ++k)
    if (name == derived[k] && particles.has("velocity")) {
      q.vector_ = &particles.vector("velocity");
      q.component_ = k;
      return q;
    }
  if (name == "speed" && particles.has("velocity")) {
    q.vector_ = &particles.vector("velocity");
    return q;
  }
  throw InputError(
      where, fmt::format("unknown quantity '{}' for this solver; it has: {}", name, fmt::join(names(particles), ", ")));
}

std::vector<std::string> ParticleQuantity::names(const ParticleSet& particles) {
  std::vector<std::string> out;
  for (const auto& a : particles.scalars()) out.push_back(a.info.name);
  if (particles.has("velocity"))
    for (const char* d : {"speed", "velocity_x", "velocity_y", "velocity_z"}) out.push_back(d);
  return out;
}

}  // namespace bakesim
