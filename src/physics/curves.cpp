#include "physics/curves.hpp"

#include <algorithm>

#include "core/errors.hpp"

namespace bakesim {

PiecewiseLinear::PiecewiseLinear(std::vector<std::pair<Real, Real>> points) : points_(std::move(points)) {
  if (points_.empty()) throw Error("PiecewiseLinear needs at least one point");
  for (std::size_t i = 1; i < points_.size(); ++i)
    if (!(points_[i].first > points_[i - 1].first))
      throw Error("PiecewiseLinear points must have strictly increasing x");
}

Real PiecewiseLinear::operator()(Real x) const {
  if (points_.empty()) return 0.0;
  if (x <= points_.front().first) return points_.front().second;
  if (x >= points_.back().first) return points_.back().second;
  // The first point past x: a forward scan for the few points a property curve
  // has (it runs per particle and step; a binary search cost twice as many
  // instructions there), a binary search for long tables.
  auto it = points_.begin() + 1;
  if (points_.size() <= 16)
    while (!(x < it->first)) ++it;
  else
    it = std::upper_bound(points_.begin(), points_.end(), x,
                          [](Real v, const std::pair<Real, Real>& p) { return v < p.first; });
  const auto& [x1, y1] = *it;
  const auto& [x0, y0] = *(it - 1);
  return y0 + (y1 - y0) * (x - x0) / (x1 - x0);
}

}  // namespace bakesim
