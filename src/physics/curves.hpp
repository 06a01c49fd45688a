#pragma once
// Curves of one variable: temperature schedules over time and, later,
// temperature-dependent material properties.
#include <cmath>
#include <utility>
#include <variant>
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

// λ(T) = scale [ (2/π) atan((T − centre)/width) + 1 ] + offset   (thesis Eq 4.3,
// centre 65 °C, width 2 °C, offset 2 s; `scale` is C_λ).
struct ZhangArctan {
  Real scale = 450.0;
  Real centre = 65.0;
  Real width = 2.0;
  Real offset = 2.0;
  Real operator()(Real t) const { return scale * (2.0 / kPi * std::atan((t - centre) / width) + 1.0) + offset; }
};

struct ConstantCurve {
  Real value = 0.0;
  Real operator()(Real) const { return value; }
};

// A material property as a function of temperature (°C). Solvers visit the
// variant once per material and evaluate inside their particle loops.
using TemperatureCurve = std::variant<ConstantCurve, PiecewiseLinear, ZhangArctan>;

inline Real evaluate(const TemperatureCurve& c, Real t) {
  return std::visit([t](const auto& curve) { return curve(t); }, c);
}
inline bool is_constant(const TemperatureCurve& c) { return std::holds_alternative<ConstantCurve>(c); }

}  // namespace bakesim
