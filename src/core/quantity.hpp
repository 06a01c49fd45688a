#pragma once
// A per-particle quantity by name, resolved once from the particle registry:
// any scalar attribute ("temperature", "density", "water_mass", ...), or
// "speed" and "velocity_x|y|z" from the velocity. Probes, followed particles
// and statistics read quantities through it, so a solver that registers a new
// attribute can be probed without code in the solver or the frame loop.
#include <string>
#include <vector>

#include "core/particles.hpp"

namespace bakesim {

class ParticleQuantity {
 public:
  // Throws InputError (at `where`) naming the quantities the set has.
  static ParticleQuantity resolve(const ParticleSet& particles, const std::string& name, const std::string& where);
  // Every name resolve() accepts for this set.
  static std::vector<std::string> names(const ParticleSet& particles);
  Real operator()(std::size_t i) const {
    if (scalar_) return (*scalar_)[i];
    const Vec3& v = (*vector_)[i];
    return component_ < 0 ? v.norm() : v[component_];
  }

 private:
  const std::vector<Real>* scalar_ = nullptr;
  const std::vector<Vec3>* vector_ = nullptr;
  int component_ = -1;  // −1: the norm
};

}  // namespace bakesim
