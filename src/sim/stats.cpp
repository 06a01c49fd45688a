#include "sim/stats.hpp"

#include <limits>

#include "core/parallel.hpp"

namespace bakesim {

FrameStats compute_frame_stats(const ParticleSet& ps) {
  FrameStats out;
  out.particles = ps.size();
  if (ps.size() == 0) return out;
  const auto& x = ps.vector("position");
  const auto& v = ps.vector("velocity");
  const auto& m = ps.scalar("mass");
  const bool has_t = ps.has("temperature");
  const std::vector<Real> none;
  const auto& t = has_t ? ps.scalar("temperature") : none;
  struct Acc {
    Real ke = 0, vmax2 = 0, mt = 0, msum = 0;
    Real tmin = std::numeric_limits<Real>::infinity(), tmax = -std::numeric_limits<Real>::infinity();
    Aabb box = Aabb::empty_box();
  };
  const Acc acc = deterministic_reduce(
      ps.size(), Acc{},
      [&](std::size_t b, std::size_t e) {
        Acc a;
        for (std::size_t i = b; i < e; ++i) {
          const Real v2 = v[i].squaredNorm();
          a.ke += 0.5 * m[i] * v2;
          a.vmax2 = std::max(a.vmax2, v2);
          a.box.expand(x[i]);
          if (has_t) {
            a.mt += m[i] * t[i];
            a.msum += m[i];
            a.tmin = std::min(a.tmin, t[i]);
            a.tmax = std::max(a.tmax, t[i]);
          }
        }
        return a;
      },
      [](Acc a, const Acc& b) {
        a.ke += b.ke;
        a.vmax2 = std::max(a.vmax2, b.vmax2);
        a.mt += b.mt;
        a.msum += b.msum;
        a.tmin = std::min(a.tmin, b.tmin);
        a.tmax = std::max(a.tmax, b.tmax);
        a.box.expand(b.box.min);
        a.box.expand(b.box.max);
        return a;
      });
  out.kinetic_energy = acc.ke;
  out.max_speed = std::sqrt(acc.vmax2);
  out.bounds = acc.box;
  if (has_t && acc.msum > 0) {
    out.mean_temperature = acc.mt / acc.msum;
    out.min_temperature = acc.tmin;
    out.max_temperature = acc.tmax;
  } else {
    const Real nan = std::numeric_limits<Real>::quiet_NaN();
    out.mean_temperature = out.min_temperature = out.max_temperature = nan;
  }
  return out;
}

ParticleVolume::ParticleVolume(const ParticleSet& ps) {
  if (ps.has("density") && ps.has("mass")) {
    numerator_ = &ps.scalar("mass"), second_ = &ps.scalar("density"), divide_ = true;
  } else if (ps.has("J") && ps.has("initial_volume")) {
    numerator_ = &ps.scalar("J"), second_ = &ps.scalar("initial_volume"), divide_ = false;
  }
}

std::vector<BodyStats> compute_body_stats(const ParticleSet& ps, std::size_t bodies, const Vec3& up) {
  using Acc = std::vector<BodyStats>;
  const ParticleVolume volume(ps);
  if (!ps.has("body_id") || !volume.available() || bodies == 0) return Acc(bodies);
  const auto& x = ps.vector("position");
  const auto& body = ps.integer("body_id");
  return deterministic_reduce(
      ps.size(), Acc(bodies),
      [&](std::size_t b, std::size_t e) {
        Acc a(bodies);
        for (std::size_t i = b; i < e; ++i) {
          BodyStats& s = a[static_cast<std::size_t>(body[i])];
          s.volume += volume(i);
          const Real u = x[i].dot(up);
          s.low = std::min(s.low, u);
          s.high = std::max(s.high, u);
        }
        return a;
      },
      [](Acc a, const Acc& b) {
        for (std::size_t k = 0; k < a.size(); ++k) {
          a[k].volume += b[k].volume;
          a[k].low = std::min(a[k].low, b[k].low);
          a[k].high = std::max(a[k].high, b[k].high);
        }
        return a;
      });
}

}  // namespace bakesim
