#include "sim/bake_stats.hpp"

#include <limits>

#include "core/parallel.hpp"

namespace bakesim {

namespace {

const std::vector<Real>* area_attribute(const ParticleSet& ps) {
  if (ps.has("air_area")) return &ps.scalar("air_area");
  if (ps.has("surface_area")) return &ps.scalar("surface_area");
  return nullptr;
}

}  // namespace

BakeStatistics::BakeStatistics(const ParticleSet& initial, std::size_t bodies)
    : bodies_(bodies),
      water_(initial.has("water_mass")),
      co2_(initial.has("co2") && initial.has("initial_volume")),
      initial_water_(bodies, 0.0),
      initial_mass_(bodies, 0.0) {
  if (!water_ || !initial.has("body_id")) return;
  // In particle order, one by one (the reference the moisture loss is measured against).
  const auto& water = initial.scalar("water_mass");
  const auto& body = initial.integer("body_id");
  for (std::size_t i = 0; i < initial.size(); ++i) initial_water_[body[i]] += water[i];
  if (initial.has("mass")) {
    const auto& mass = initial.scalar("mass");
    for (std::size_t i = 0; i < initial.size(); ++i) initial_mass_[body[i]] += mass[i];
  }
}

std::vector<std::string> BakeStatistics::columns(const std::string& body) const {
  std::vector<std::string> out = {"core_temperature:" + body, "crust_temperature:" + body};
  if (water_) {
    out.push_back("water:" + body);
    out.push_back("moisture_loss_percent:" + body);
    out.push_back("weight_loss_percent:" + body);
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
  if (co2_) out.push_back(b.co2);
  return out;
}

std::vector<BodyBake> BakeStatistics::compute(const ParticleSet& ps) const {
  struct Acc {
    Real tmin = std::numeric_limits<Real>::infinity(), area = 0, area_t = 0, water = 0, co2 = 0;
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
  }
  return out;
}

}  // namespace bakesim
