#pragma once
// SPH kernels. Convention of the thesis: h is the support radius and
// q = 2r/h ∈ [0, 2] (Eq 3.9–3.10). The printed Eq 3.9 omits that the 3D
// normalisation for support h is 8/(π h³) (= 1/(π ħ³) with ħ = h/2); Eq
// 3.11–3.12 omit the chain-rule factors 2/h and 4/h². See docs/physics.md.
#include <cmath>
#include <vector>

#include "core/types.hpp"

namespace bakesim::sph {

class CubicSpline {
 public:
  explicit CubicSpline(Real h) { set_support(h); }
  void set_support(Real h) {
    h_ = h;
    inv_h_ = 1.0 / h;
    sigma_ = 8.0 / (kPi * h * h * h);
  }
  Real support() const { return h_; }

  // Eq 3.9
  Real w(Real r) const {
    const Real q = 2.0 * r * inv_h_;
    if (q < 1.0) return sigma_ * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
    if (q < 2.0) {
      const Real a = 2.0 - q;
      return sigma_ * 0.25 * a * a * a;
    }
    return 0.0;
  }
  // dW/dr (Eq 3.11 with the factor σ·2/h); the gradient is dw_dr(r) · r̂.
  Real dw_dr(Real r) const {
    const Real q = 2.0 * r * inv_h_;
    const Real f = sigma_ * 2.0 * inv_h_;
    if (q < 1.0) return f * (-3.0 * q + 2.25 * q * q);
    if (q < 2.0) {
      const Real a = 2.0 - q;
      return f * (-0.75 * a * a);
    }
    return 0.0;
  }
  // W'(r)/r without a division in the inner branch (the gradient is
  // dw_dr_over_r(r) · rij).
  Real dw_dr_over_r(Real r) const {
    const Real q = 2.0 * r * inv_h_;
    const Real f = sigma_ * 2.0 * inv_h_;
    if (q < 1.0) return f * 2.0 * inv_h_ * (-3.0 + 2.25 * q);
    if (q < 2.0) {
      const Real a = 2.0 - q;
      return f * (-0.75 * a * a) / r;
    }
    return 0.0;
  }
  // ∇_i W(x_i − x_j) for rij = x_i − x_j with |rij| = r > 0.
  Vec3 gradient(const Vec3& rij, Real r) const { return (r > 0 ? dw_dr(r) / r : 0.0) * rij; }
  // The 3D Laplacian W'' + 2W'/r (Eq 3.12 is W'' alone, without its 4/h² and
  // with a typo in the second branch).
  Real laplacian(Real r) const {
    const Real q = 2.0 * r * inv_h_;
    const Real f = sigma_ * 4.0 * inv_h_ * inv_h_;
    if (q < 1.0) return f * (-9.0 + 9.0 * q);
    if (q < 2.0) {
      const Real a = 2.0 - q;
      return f * (1.5 * a - 1.5 * a * a / q);
    }
    return 0.0;
  }

 private:
  Real h_ = 1, inv_h_ = 1, sigma_ = 1;
};

// Müller et al. viscosity kernel Laplacian 45/(π h⁶)(h − r) (Eq 3.8), support
// h, times a calibration factor (1: the thesis's; the solver passes
// viscosity_lattice_calibration so that the operator is exact on its lattice).
class ViscosityLaplacian {
 public:
  explicit ViscosityLaplacian(Real h, Real calibration = 1.0)
      : h_(h), calibration_(calibration), c_(coefficient_for(h)) {}
  Real operator()(Real r) const { return r < h_ ? c_ * (h_ - r) : 0.0; }
  // calibration · 45/(π h⁶), for loops that already know r < h.
  Real coefficient() const { return c_; }
  Real coefficient_for(Real h) const {
    const Real h3 = h * h * h;
    return calibration_ * 45.0 / (kPi * h3 * h3);
  }
  Real calibration() const { return calibration_; }

 private:
  Real h_, calibration_, c_;
};

// The factor that makes Σ_j V_j C (h − r_ij)(v_j − v_i) (Eq 3.19 with Eq
// 3.8) return ∇²v exactly for a quadratic velocity field on the sampling
// lattice (V = 1/lattice_sum, as the density summation gives there). The
// continuous coefficient 45/(π h⁶) is exact only in the integral: on the
// lattice at h = 2s the sum is 1.2% low (3.4% at h = 2.4s), so shear decays
// and channel flows run that much too fast (docs/physics.md).
Real viscosity_lattice_calibration(const CubicSpline& kernel, Real spacing, Real lattice_sum);

// What a no-slip wall adds to a pair sum: the lattice continued beyond the
// wall (layers at s/2 + k·s behind it, as WallKernelShare) as ghosts that
// move with the velocity the particle's profile extrapolates to there,
// v_w − (v_i − v_w) s'/d (Morris, Fox & Zhu 1997), so v_i − v_ghost =
// (v_i − v_w)(1 + s'/d) and the sums stay exact for a linear shear profile up
// to the wall. Tabulated over the particle's distance d to the wall:
//   S(d) = Σ_ghost V f(r, z) (1 + s'/d),  z = d + s' the normal separation,
// with V = 1/lattice_sum. d is clamped below at s/4 (particles are kept s/2
// from walls). Two uses:
//  - viscosity (Eq 3.19), f = C (h − r): the wall adds −μ_i S(d)(v_i − v_w)
//    to ρ_i a_i;
//  - velocity gradient (Eq 3.27), f = −W'(r) z/r: the wall adds
//    (v_i − v_w) ⊗ n S(d) to ∇v (n the wall's normal into the fluid).
class WallGhostSum {
 public:
  template <class F>
  WallGhostSum(Real support, Real spacing, Real lattice_sum, F&& f, int samples = 512);
  Real operator()(Real d) const;

 private:
  Real h_, d_min_;
  std::vector<Real> table_;
};

template <class F>
WallGhostSum::WallGhostSum(Real h, Real s, Real lattice_sum, F&& f, int samples) : h_(h), d_min_(0.25 * s) {
  const int n = static_cast<int>(std::ceil(h / s)) + 1;
  table_.assign(std::size_t(samples) + 1, 0.0);
  for (int t = 0; t <= samples; ++t) {
    const Real d = std::max(d_min_, h * t / samples);
    Real sum = 0;
    for (int layer = 0;; ++layer) {
      const Real depth = 0.5 * s + layer * s;  // s' behind the wall
      const Real z = d + depth;
      if (z >= h) break;
      for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j) {
          const Real r = std::sqrt(z * z + s * s * Real(i * i + j * j));
          if (r < h) sum += f(r, z) * (1.0 + depth / d);
        }
    }
    table_[std::size_t(t)] = sum / lattice_sum;
  }
}

// The share of a particle's kernel sum that lies beyond a planar wall, for the
// wall density correction. The region beyond the wall is treated as the
// particle lattice continued through the wall: layers at d + s/2 + k·s from
// the particle (d = distance to the wall, s = spacing), each an infinite
// square lattice, normalised by the full lattice sum. So a particle of a
// lattice body whose first layer sits s/2 from the wall starts at exactly its
// rest density (the continuum integral would leave it a few % too dense).
//   fraction(d) ∈ [0, ~0.5],   slope(d) = −d fraction / dd ≥ 0.
// Tabulated once; d < 0 (inside the wall) is clamped to 0.
class WallKernelShare {
 public:
  WallKernelShare(const CubicSpline& kernel, Real spacing, Real lattice_sum, int samples = 1024);
  Real fraction(Real d) const { return lookup(fraction_, d); }
  Real slope(Real d) const { return lookup(slope_, d); }

 private:
  Real lookup(const std::vector<Real>& t, Real d) const;
  Real h_;
  std::vector<Real> fraction_, slope_;
};

// Sum of W over an infinite cubic lattice of spacing s around a lattice point,
// self included.
Real lattice_kernel_sum(const CubicSpline& kernel, Real spacing);
// The colour gradient's area share on a flat lattice face: V |∇C| / s² of a
// particle of the outermost layer of a half-lattice at `spacing`, with the
// volumes V = m/ρ the density summation gives there (Eq 3.13, 3.28). By the
// co-area formula Σ V |∇C| over a surface layer is the area the layer holds of
// the colour's drop, so dividing by this share makes it the surface's area.
Real flat_face_colour_share(const CubicSpline& kernel, Real spacing);

}  // namespace bakesim::sph
