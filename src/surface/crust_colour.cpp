#include "surface/crust_colour.hpp"

#include <algorithm>
#include <cmath>

#include "physics/browning.hpp"

namespace bakesim::surface {

namespace {

// Measured crust colours (see the header and docs/surfaces.md).
constexpr Lab kPath[] = {{80.0, -0.5, 18.0}, {66.0, 2.4, 22.3}, {25.0, 15.0, 30.0}};
constexpr int kPathPoints = sizeof(kPath) / sizeof(kPath[0]);

Lab mix(const Lab& p, const Lab& q, Real t) {
  return {p.L + t * (q.L - p.L), p.a + t * (q.a - p.a), p.b + t * (q.b - p.b)};
}

}  // namespace

Real lab_distance(const Lab& p, const Lab& q) {
  return std::sqrt((p.L - q.L) * (p.L - q.L) + (p.a - q.a) * (p.a - q.a) + (p.b - q.b) * (p.b - q.b));
}

Lab crust_lab(Real colour_difference) {
  const Lab& dough = kPath[0];
  if (!(colour_difference > 0)) return dough;
  // The distance from the dough grows along each segment (each turns by less
  // than a right angle from the direction away from the dough), so the point at
  // a given distance is found on the first segment whose end lies beyond it, as
  // the root of a quadratic in the segment parameter.
  for (int s = 0; s + 1 < kPathPoints; ++s) {
    const Lab &p = kPath[s], &q = kPath[s + 1];
    if (lab_distance(q, dough) < colour_difference) continue;
    const Real dx[3] = {q.L - p.L, q.a - p.a, q.b - p.b};
    const Real ox[3] = {p.L - dough.L, p.a - dough.a, p.b - dough.b};
    Real A = 0, B = 0, C = -colour_difference * colour_difference;
    for (int k = 0; k < 3; ++k) {
      A += dx[k] * dx[k];
      B += 2 * dx[k] * ox[k];
      C += ox[k] * ox[k];
    }
    const Real t = (-B + std::sqrt(std::max(Real(0), B * B - 4 * A * C))) / (2 * A);
    return mix(p, q, std::clamp(t, Real(0), Real(1)));
  }
  return kPath[kPathPoints - 1];
}

Lab crust_lab_of_browning(Real browning) {
  return crust_lab(BrowningKinetics{}.colour_difference(std::clamp(browning, Real(0), Real(1))));
}

Lab dough_lab() { return kPath[0]; }

Lab crust_lab_of_browning(Real browning, const Lab& raw) {
  const Lab on_path = crust_lab_of_browning(browning);
  const Lab &dough = kPath[0], &darkest = kPath[kPathPoints - 1];
  const Real fade = 1 - std::clamp(lab_distance(on_path, dough) / lab_distance(darkest, dough), Real(0), Real(1));
  return {on_path.L + fade * (raw.L - dough.L), on_path.a + fade * (raw.a - dough.a),
          on_path.b + fade * (raw.b - dough.b)};
}

std::array<Real, 3> lab_to_srgb(const Lab& c) {
  // L*a*b* → XYZ (CIE 15:2004, D65 white Xn 0.95047, Yn 1, Zn 1.08883).
  constexpr Real delta = 6.0 / 29.0;
  auto f_inverse = [&](Real t) { return t > delta ? t * t * t : 3 * delta * delta * (t - 4.0 / 29.0); };
  const Real fy = (c.L + 16.0) / 116.0, fx = fy + c.a / 500.0, fz = fy - c.b / 200.0;
  const Real X = 0.95047 * f_inverse(fx), Y = f_inverse(fy), Z = 1.08883 * f_inverse(fz);
  // XYZ → linear sRGB (IEC 61966-2-1), then the sRGB transfer function.
  const Real linear[3] = {3.2406 * X - 1.5372 * Y - 0.4986 * Z, -0.9689 * X + 1.8758 * Y + 0.0415 * Z,
                          0.0557 * X - 0.2040 * Y + 1.0570 * Z};
  std::array<Real, 3> rgb{};
  for (int k = 0; k < 3; ++k) {
    const Real v = std::clamp(linear[k], Real(0), Real(1));
    rgb[k] = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  }
  return rgb;
}

}  // namespace bakesim::surface
