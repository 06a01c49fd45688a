#pragma once
// Per-frame statistics of a particle set (stats.csv). Reductions are
// deterministic: the same state gives the same numbers on any thread count.
#include <limits>
#include <vector>

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

// Each particle's volume, m³: m/ρ (SPH, attribute density), J V⁰ (MPM,
// attributes J and initial_volume); 0 where the set has neither.
class ParticleVolume {
 public:
  explicit ParticleVolume(const ParticleSet& ps);
  bool available() const { return numerator_ != nullptr; }
  Real operator()(std::size_t i) const {
    if (!numerator_) return 0;
    if (!divide_) return (*numerator_)[i] * (*second_)[i];
    return (*second_)[i] > 0 ? (*numerator_)[i] / (*second_)[i] : 0;
  }

 private:
  const std::vector<Real>* numerator_ = nullptr;  // m (SPH) or J (MPM)
  const std::vector<Real>* second_ = nullptr;     // ρ (SPH) or V⁰ (MPM)
  bool divide_ = false;
};

// Per body (attribute body_id): volume Σ m/ρ (m³) and extent along `up` (m).
struct BodyStats {
  Real volume = 0;
  Real low = std::numeric_limits<Real>::infinity(), high = -std::numeric_limits<Real>::infinity();
  Real height() const { return high >= low ? high - low : 0.0; }
};
std::vector<BodyStats> compute_body_stats(const ParticleSet& particles, std::size_t bodies, const Vec3& up);

}  // namespace bakesim
