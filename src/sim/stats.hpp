#pragma once
// Per-frame statistics of a particle set (stats.csv). Reductions are
// deterministic: the same state gives the same numbers on any thread count.
#include "core/particles.hpp"

namespace bakesim {

struct FrameStats {
  std::size_t particles = 0;
  Real kinetic_energy = 0;  // J
  Real max_speed = 0;       // m/s
  Aabb bounds;
  Real mean_temperature = 0, min_temperature = 0, max_temperature = 0;  // °C, mass-weighted mean
};

FrameStats compute_frame_stats(const ParticleSet& particles);

}  // namespace bakesim
