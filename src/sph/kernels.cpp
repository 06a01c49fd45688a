#include "sph/kernels.hpp"

#include <algorithm>

namespace bakesim::sph {

HalfSpaceIntegrals::HalfSpaceIntegrals(Real h, int samples) : h_(h) {
  const CubicSpline k(h);
  gamma_.assign(samples + 1, 0.0);
  area_.assign(samples + 1, 0.0);
  // area(z) = 2π ∫_z^h W(r) r dr (the plane z cuts the sphere of radius h).
  const int fine = 4000;
  auto area_at = [&](Real z) {
    const Real dr = (h - z) / fine;
    Real s = 0;
    for (int i = 0; i < fine; ++i) {
      const Real r = z + (i + 0.5) * dr;
      s += k.w(r) * r * dr;
    }
    return 2.0 * kPi * s;
  };
  for (int i = 0; i <= samples; ++i) area_[i] = area_at(h * i / samples);
  // gamma(d) = ∫_d^h area(z) dz, trapezoid from the far end.
  gamma_[samples] = 0.0;
  const Real dz = h / samples;
  for (int i = samples - 1; i >= 0; --i) gamma_[i] = gamma_[i + 1] + 0.5 * dz * (area_[i] + area_[i + 1]);
}

Real HalfSpaceIntegrals::lookup(const std::vector<Real>& t, Real d) const {
  const int n = static_cast<int>(t.size()) - 1;
  const Real x = std::clamp(d / h_, 0.0, 1.0) * n;
  const int i = std::min(n - 1, static_cast<int>(x));
  const Real f = x - i;
  return t[i] * (1 - f) + t[i + 1] * f;
}

}  // namespace bakesim::sph
