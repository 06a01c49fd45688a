#pragma once
// The temperature a material's property curves read for a particle.
#include <vector>

#include "core/types.hpp"
#include "physics/constants.hpp"
#include "physics/setting.hpp"

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

}  // namespace bakesim::sph
