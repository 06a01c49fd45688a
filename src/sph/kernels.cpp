#include "sph/kernels.hpp"

#include <algorithm>
#include <cmath>

namespace bakesim::sph {

Real lattice_kernel_sum(const CubicSpline& k, Real s) {
  const int n = static_cast<int>(std::ceil(k.support() / s)) + 1;
  Real sum = 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int l = -n; l <= n; ++l) sum += k.w(s * std::sqrt(Real(i * i + j * j + l * l)));
  return sum;
}

Real flat_face_colour_share(const CubicSpline& k, Real s) {
  const int n = static_cast<int>(std::ceil(k.support() / s)) + 1;
  // Σ_k W(x_j − x_k) over the half-lattice z ≤ 0 (ρ_j / m).
  auto kernel_sum = [&](int jz) {
    Real sum = 0;
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j)
        for (int l = -n; l <= n; ++l)
          if (jz + l <= 0) sum += k.w(s * std::sqrt(Real(i * i + j * j + l * l)));
    return sum;
  };
  // ∇C at the origin, a particle of the top layer: Σ_j V_j W'(r)/r (x_0 − x_j), along z.
  Real grad_z = 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int l = -n; l <= 0; ++l) {
        const Real r = s * std::sqrt(Real(i * i + j * j + l * l));
        if (r <= 0) continue;
        grad_z += k.dw_dr_over_r(r) * (-l * s) / kernel_sum(l);
      }
  return std::abs(grad_z) / kernel_sum(0) / (s * s);  // V_0 |∇C_0| / s²
}

WallKernelShare::WallKernelShare(const CubicSpline& k, Real s, Real lattice_sum, int samples) : h_(k.support()) {
  const int n = static_cast<int>(std::ceil(h_ / s)) + 1;
  // Kernel sum and its d-derivative over the ghost layers beyond the wall.
  auto ghost = [&](Real d, Real& value, Real& derivative) {
    value = 0;
    derivative = 0;
    for (int layer = 0;; ++layer) {
      const Real z = d + 0.5 * s + layer * s;
      if (z >= h_) break;
      for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j) {
          const Real r = std::sqrt(z * z + s * s * Real(i * i + j * j));
          value += k.w(r);
          if (r > 0) derivative += k.dw_dr(r) * z / r;
        }
    }
  };
  fraction_.assign(samples + 1, 0.0);
  slope_.assign(samples + 1, 0.0);
  for (int i = 0; i <= samples; ++i) {
    Real v, dv;
    ghost(h_ * i / samples, v, dv);
    fraction_[i] = v / lattice_sum;
    slope_[i] = -dv / lattice_sum;
  }
}

Real viscosity_lattice_calibration(const CubicSpline& k, Real s, Real lattice_sum) {
  const Real h = k.support();
  const ViscosityLaplacian lap(h);
  const int n = static_cast<int>(std::ceil(h / s)) + 1;
  // Σ_j V C (h − r) x_j² for v = x² (∇²v = 2), V = 1/lattice_sum.
  Real sum = 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int l = -n; l <= n; ++l) {
        const Real r = s * std::sqrt(Real(i * i + j * j + l * l));
        sum += lap(r) * (s * i) * (s * i);
      }
  return 2.0 / (sum / lattice_sum);
}

Real WallGhostSum::operator()(Real d) const {
  if (d >= h_) return 0.0;
  const int n = static_cast<int>(table_.size()) - 1;
  const Real x = std::clamp(d / h_, 0.0, 1.0) * n;
  const int i = std::min(n - 1, static_cast<int>(x));
  const Real f = x - i;
  return table_[std::size_t(i)] * (1 - f) + table_[std::size_t(i) + 1] * f;
}

Real WallKernelShare::lookup(const std::vector<Real>& t, Real d) const {
  const int n = static_cast<int>(t.size()) - 1;
  const Real x = std::clamp(d / h_, 0.0, 1.0) * n;
  const int i = std::min(n - 1, static_cast<int>(x));
  const Real f = x - i;
  return t[i] * (1 - f) + t[i + 1] * f;
}

}  // namespace bakesim::sph
