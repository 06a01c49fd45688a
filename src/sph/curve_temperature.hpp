#pragma once
// The temperature a material's property curves read for a particle, and a
// yield-stress material's law at it.
#include <algorithm>
#include <cstdint>
#include <variant>
#include <vector>

#include "core/parallel.hpp"
#include "core/types.hpp"
#include "physics/constants.hpp"
#include "physics/rheology.hpp"
#include "physics/setting.hpp"
#include "sph/setup.hpp"

namespace bakesim::sph {

// The temperature a material's curves read for particle i: its own, or the
// peak it reached once set (physics/setting.hpp). A material set from the
// start (or never) reads one of the two throughout.
class CurveTemperature {
 public:
  CurveTemperature(const IrreversibleSetting& set, const std::vector<Real>& temperature, const std::vector<Real>& peak)
      : set_(set), temperature_(temperature), peak_(peak), always_(set.is_set(-kZeroCelsius)), never_(!set.ever()) {}
  Real operator()(std::size_t i) const {
    if (always_) return peak_[i];
    if (never_) return temperature_[i];
    return set_.property_temperature(temperature_[i], peak_[i]);
  }

 private:
  const IrreversibleSetting& set_;
  const std::vector<Real>& temperature_;
  const std::vector<Real>& peak_;
  bool always_, never_;
};

// Calls fn(i, law) in parallel for every particle i of material `id` (which
// has a yield_flow), with its Herschel–Bulkley law at the temperature its
// curves read; the curves are visited once, not per particle.
template <class Fn>
void for_each_yield_law(const Material& mat, int id, const std::vector<std::int32_t>& material,
                        const CurveTemperature& at, Fn&& fn) {
  const Material::YieldFlow& flow = *mat.yield_flow;
  std::visit(
      [&](const auto& consistency, const auto& yield) {
        parallel_for(
            material.size(),
            [&](std::size_t i) {
              if (material[i] != id) return;
              const Real t = at(i);
              fn(i, HerschelBulkley{std::max(Real(0), yield(t)), std::max(Real(0), consistency(t)), flow.flow_index,
                                    flow.regularisation});
            },
            1024);
      },
      mat.viscosity, flow.yield_stress);
}

}  // namespace bakesim::sph
