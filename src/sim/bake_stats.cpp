#include "sim/bake_stats.hpp"

#include <algorithm>
#include <limits>

#include "core/parallel.hpp"
#include "sim/stats.hpp"

namespace bakesim {

namespace {

// Dough at or past the boiling point, less round-off of the boiling cap, has dried there: crust.
constexpr Real kCrustBelowBoiling = 0.5;  // K

const std::vector<Real>* area_attribute(const ParticleSet& ps) {
  if (ps.has("air_area")) return &ps.scalar("air_area");
  if (ps.has("surface_area")) return &ps.scalar("surface_area");
  return nullptr;
}

}  // namespace

BakeStatistics::BakeStatistics(const ParticleSet& initial, std::size_t bodies, Real boiling_point)
    : BakeStatistics(initial, std::vector<Real>(bodies, boiling_point)) {}

BakeStatistics::BakeStatistics(const ParticleSet& initial, const std::vector<Real>& boiling_points)
    : bodies_(boiling_points.size()),
      crust_from_celsius_(boiling_points),
      water_(initial.has("water_mass")),
      moisture_(water_ && initial.has("moisture") && initial.has("mass")),
      co2_(initial.has("co2") && initial.has("initial_volume")),
      initial_water_(bodies_, 0.0),
      initial_mass_(bodies_, 0.0),
      initial_moisture_(bodies_, 0.0) {
  for (Real& t : crust_from_celsius_) t -= kCrustBelowBoiling;
  if (!water_ || !initial.has("body_id")) {
    moisture_ = false;
    return;
  }
  // In particle order, one by one (the reference the moisture loss is measured against).
  const auto& water = initial.scalar("water_mass");
  const auto& body = initial.integer("body_id");
  for (std::size_t i = 0; i < initial.size(); ++i) initial_water_[body[i]] += water[i];
  if (initial.has("mass")) {
    const auto& mass = initial.scalar("mass");
    for (std::size_t i = 0; i < initial.size(); ++i) initial_mass_[body[i]] += mass[i];
  }
  if (moisture_) {
    const auto& moisture = initial.scalar("moisture");
    for (std::size_t i = 0; i < initial.size(); ++i)
      initial_moisture_[body[i]] = std::max(initial_moisture_[body[i]], moisture[i]);
    // MPM points carry the attribute whether or not their dough holds moisture.
    moisture_ = std::any_of(initial_moisture_.begin(), initial_moisture_.end(), [](Real x) { return x > 0; });
  }
}

std::vector<std::string> BakeStatistics::columns(const std::string& body) const {
  std::vector<std::string> out = {"core_temperature:" + body, "crust_temperature:" + body};
  if (water_) {
    out.push_back("water:" + body);
    out.push_back("moisture_loss_percent:" + body);
    out.push_back("weight_loss_percent:" + body);
  }
  if (moisture_) {
    out.push_back("crust_thickness:" + body);
    out.push_back("crust_moisture:" + body);
    out.push_back("crumb_moisture:" + body);
  }
  if (co2_) out.push_back("co2_mol:" + body);
  return out;
}

std::vector<Real> BakeStatistics::values(const BodyBake& b) const {
  std::vector<Real> out = {b.core_temperature, b.crust_temperature};
  if (water_) {
    out.push_back(b.water);
    out.push_back(b.moisture_loss_percent);
    out.push_back(b.weight_loss_percent);
  }
  if (moisture_) {
    out.push_back(b.crust_thickness);
    out.push_back(b.crust_moisture);
    out.push_back(b.crumb_moisture);
  }
  if (co2_) out.push_back(b.co2);
  return out;
}

std::vector<BodyBake> BakeStatistics::compute(const ParticleSet& ps) const {
  struct Acc {
    Real tmin = std::numeric_limits<Real>::infinity(), area = 0, area_t = 0, water = 0, co2 = 0;
    Real dried_volume = 0, outer_mass = 0, outer_moisture = 0, inner_mass = 0, inner_moisture = 0;
  };
  const std::size_t nb = bodies_;
  std::vector<BodyBake> out(nb);
  if (!ps.has("temperature") || !ps.has("body_id")) return out;
  const auto& t = ps.scalar("temperature");
  const auto& body = ps.integer("body_id");
  const std::vector<Real>* area = area_attribute(ps);
  const std::vector<Real>* water = water_ ? &ps.scalar("water_mass") : nullptr;
  const std::vector<Real>* co2 = co2_ ? &ps.scalar("co2") : nullptr;
  const std::vector<Real>* volume0 = co2_ ? &ps.scalar("initial_volume") : nullptr;
  const std::vector<Real>* moisture = moisture_ ? &ps.scalar("moisture") : nullptr;
  const std::vector<Real>* mass = moisture_ ? &ps.scalar("mass") : nullptr;
  const ParticleVolume volume(ps);
  const std::vector<Acc> acc = deterministic_reduce(
      ps.size(), std::vector<Acc>(nb),
      [&](std::size_t b, std::size_t e) {
        std::vector<Acc> a(nb);
        for (std::size_t i = b; i < e; ++i) {
          Acc& s = a[body[i]];
          s.tmin = std::min(s.tmin, t[i]);
          if (area) {
            s.area += (*area)[i];
            s.area_t += (*area)[i] * t[i];
          }
          if (water) s.water += (*water)[i];
          if (co2) s.co2 += (*co2)[i] * (*volume0)[i];
          if (moisture) {
            const Real x = (*moisture)[i], x0 = initial_moisture_[body[i]], v = volume(i);
            if (x0 > 0 && t[i] >= crust_from_celsius_[body[i]])
              s.dried_volume += v * std::clamp(1 - x / x0, Real(0), Real(1));
            // The particle's outer share: its exchange area over its cross-section (MPM gives interior
            // points specks of area from the noise of the grid's boundary field).
            const Real outer = area && v > 0 ? std::min(Real(1), (*area)[i] / std::cbrt(v * v)) : Real(0);
            s.outer_mass += outer * (*mass)[i];
            s.outer_moisture += outer * (*mass)[i] * x;
            s.inner_mass += (1 - outer) * (*mass)[i];
            s.inner_moisture += (1 - outer) * (*mass)[i] * x;
          }
        }
        return a;
      },
      [](std::vector<Acc> a, const std::vector<Acc>& b) {
        for (std::size_t k = 0; k < a.size(); ++k) {
          a[k].tmin = std::min(a[k].tmin, b[k].tmin);
          a[k].area += b[k].area;
          a[k].area_t += b[k].area_t;
          a[k].water += b[k].water;
          a[k].co2 += b[k].co2;
          a[k].dried_volume += b[k].dried_volume;
          a[k].outer_mass += b[k].outer_mass;
          a[k].outer_moisture += b[k].outer_moisture;
          a[k].inner_mass += b[k].inner_mass;
          a[k].inner_moisture += b[k].inner_moisture;
        }
        return a;
      });
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  for (std::size_t b = 0; b < nb; ++b) {
    out[b].core_temperature = acc[b].tmin;
    out[b].crust_temperature = acc[b].area > 0 ? acc[b].area_t / acc[b].area : nan;
    out[b].water = acc[b].water;
    out[b].moisture_loss_percent = initial_water_[b] > 0 ? 100.0 * (1 - acc[b].water / initial_water_[b]) : 0.0;
    out[b].weight_loss_percent =
        initial_mass_[b] > 0 ? 100.0 * (initial_water_[b] - acc[b].water) / initial_mass_[b] : 0.0;
    out[b].co2 = acc[b].co2;
    out[b].crust_thickness = acc[b].area > 0 ? acc[b].dried_volume / acc[b].area : 0.0;
    out[b].crust_moisture = acc[b].outer_mass > 0 ? acc[b].outer_moisture / acc[b].outer_mass : nan;
    out[b].crumb_moisture = acc[b].inner_mass > 0 ? acc[b].inner_moisture / acc[b].inner_mass : nan;
  }
  return out;
}

}  // namespace bakesim
