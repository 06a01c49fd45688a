#pragma once
// Curves of one variable: temperature schedules over time and, later,
// temperature-dependent material properties.
#include <utility>
#include <vector>

#include "core/types.hpp"

namespace bakesim {

// Piecewise-linear through (x, y) points, constant beyond the ends.
class PiecewiseLinear {
 public:
  PiecewiseLinear() = default;
  explicit PiecewiseLinear(std::vector<std::pair<Real, Real>> points);
  static PiecewiseLinear constant(Real y) { return PiecewiseLinear({{0.0, y}}); }
  Real operator()(Real x) const;
  const std::vector<std::pair<Real, Real>>& points() const { return points_; }

 private:
  std::vector<std::pair<Real, Real>> points_;
};

}  // namespace bakesim
