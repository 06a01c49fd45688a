#pragma once
// Jacobi-preconditioned conjugate gradients, matrix-free, shared by the SPH
// implicit viscosity (three velocity components side by side) and the MPM
// implicit heat (one temperature per grid node). `Value` is Real (one system)
// or Vec3 (three independent systems with the same matrix, each with its own
// step lengths and stopping test; or, with Coupled, one system of 3n
// unknowns whose components the matrix couples: the stress-form viscosity).
// Every sum is a deterministic reduction, so the iterates do not depend on
// the thread count.
//
// One failure policy for both: a solve that stops at max_iterations with a
// residual within 100× the tolerance is accepted (the step goes on; the next
// one starts from a good guess); beyond that it is a SimulationError that
// names the solve and the setting to raise.
#include <fmt/format.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/types.hpp"

namespace bakesim {

namespace pcg_detail {
inline Real times(Real a, Real b) { return a * b; }
inline Vec3 times(const Vec3& a, const Vec3& b) { return a.cwiseProduct(b); }
inline bool any_above(Real a, Real b) { return a > b; }
inline bool any_above(const Vec3& a, const Vec3& b) { return (a.array() > b.array()).any(); }
inline bool all_within(Real a, Real b) { return a <= b; }
inline bool all_within(const Vec3& a, const Vec3& b) { return (a.array() <= b.array()).all(); }
inline Real zero(Real) { return 0.0; }
inline Vec3 zero(const Vec3&) { return Vec3::Zero(); }
inline int size(Real) { return 1; }
inline int size(const Vec3&) { return 3; }
// Coupled: every component carries the sum over components (one system).
inline Real couple(Real v) { return v; }
inline Vec3 couple(const Vec3& v) { return Vec3::Constant(v.sum()); }
inline Real& at(Real& v, int) { return v; }
inline Real& at(Vec3& v, int c) { return v[c]; }
inline Real at(const Real& v, int) { return v; }
inline Real at(const Vec3& v, int c) { return v[c]; }
}  // namespace pcg_detail

// Scratch vectors of a solve, kept by the caller between steps (no allocation once sized).
template <class Value>
struct PcgScratch {
  std::vector<Value> r, z, p, ap;
};

template <class Value>
struct PcgResult {
  int iterations = 0;
  Value residual2{};  // r·r per system at the end
  Value stop2{};      // the tolerance the caller set, as r·r
  bool converged() const { return !pcg_detail::any_above(residual2, stop2); }
  // The failure policy: converged, or within 100× the tolerance (10⁴ in r·r).
  bool acceptable() const { return converged() || pcg_detail::all_within(residual2, 1e4 * stop2); }
};

// Σ term(i) over [0, n), the same on any thread count.
template <class Value, class Term>
Value pcg_sum(std::size_t n, Term&& term) {
  return deterministic_sum_of(n, pcg_detail::zero(Value{}), term);
}

// Solves A x = b for the rows where active(i) (x is the initial guess and the
// answer); `apply(in, out)` writes out = A in over all n rows, `diag` is A's
// diagonal (the Jacobi preconditioner, 1 on inactive rows). Stops when
// r·r ≤ stop2 for every system, or after max_iterations. Coupled (Vec3):
// one system, its dot products summed over the components (stop2 then
// bounds the whole r·r in every component).
template <class Value, bool Coupled = false, class Apply, class Active>
PcgResult<Value> solve_pcg(std::size_t n, Apply&& apply, Active&& active, const std::vector<Real>& diag,
                           const std::vector<Value>& b, std::vector<Value>& x, const Value& stop2, int max_iterations,
                           PcgScratch<Value>& w) {
  using namespace pcg_detail;
  for (std::vector<Value>* v : {&w.r, &w.z, &w.p, &w.ap}) v->resize(n);
  std::vector<Value>&r = w.r, &z = w.z, &p = w.p, &ap = w.ap;
  // The vector loops below go through raw pointers: through the vectors'
  // references the compiler reloaded every data pointer after each store
  // (a store might have changed a vector's own pointer), which made the
  // fused update cost a quarter of a matrix product (perf on the bread roll:
  // 4.3% of a run, now 2.8%; the same arithmetic, the same iterates).
  Value* const rp = r.data();
  Value* const zp = z.data();
  Value* const pp = p.data();
  Value* const xp = x.data();
  const Value* const app = ap.data();
  const Value* const bp = b.data();
  const Real* const dp = diag.data();
  apply(x, ap);
  parallel_for(
      n,
      [&](std::size_t i) {
        rp[i] = active(i) ? Value(bp[i] - app[i]) : zero(bp[i]);
        zp[i] = rp[i] / dp[i];
        pp[i] = zp[i];
      },
      4096);
  auto dot = [&](const std::vector<Value>& a, const std::vector<Value>& b) {
    const Value d = pcg_sum<Value>(n, [&](std::size_t i) { return times(a[i], b[i]); });
    if constexpr (Coupled)
      return couple(d);
    else
      return d;
  };
  Value rz = dot(r, z);
  PcgResult<Value> result;
  result.stop2 = stop2;
  result.residual2 = dot(r, r);
  while (result.iterations < max_iterations && any_above(result.residual2, stop2)) {
    apply(p, ap);
    const Value pap = dot(p, ap);
    Value alpha = zero(pap);
    for (int c = 0; c < size(pap); ++c)
      at(alpha, c) = at(pap, c) > 0 && at(result.residual2, c) > at(stop2, c) ? at(rz, c) / at(pap, c) : 0.0;
    // The update and both dot products in one pass over the vectors (the
    // sums in the same order as two separate dots: same chunks, same order).
    using Sums = std::pair<Value, Value>;  // r·z, r·r
    const Sums sums = deterministic_reduce(
        n, Sums{zero(rz), zero(rz)},
        [&](std::size_t begin, std::size_t end) {
          Sums s{zero(rz), zero(rz)};
          for (std::size_t i = begin; i < end; ++i) {
            xp[i] += times(alpha, pp[i]);
            const Value ri = rp[i] - times(alpha, app[i]);
            const Value zi = ri / dp[i];
            rp[i] = ri;
            zp[i] = zi;
            s.first += times(ri, zi);
            s.second += times(ri, ri);
          }
          return s;
        },
        [](const Sums& a, const Sums& b) {
          return Sums{Value(a.first + b.first), Value(a.second + b.second)};
        });
    Value rz_new = sums.first, rr = sums.second;
    if constexpr (Coupled) {
      rz_new = couple(rz_new);
      rr = couple(rr);
    }
    result.residual2 = rr;
    Value beta = zero(rz);
    for (int c = 0; c < size(rz); ++c) at(beta, c) = at(rz, c) > 0 ? at(rz_new, c) / at(rz, c) : 0.0;
    rz = rz_new;
    parallel_for(
        n, [&](std::size_t i) { pp[i] = zp[i] + times(beta, pp[i]); }, 4096);
    ++result.iterations;
  }
  return result;
}

// The failure policy's error: `what` names the solve, `setting` the key to raise.
// `describe()` names the solve in the message; it runs only when the solve
// failed, so a step that converges formats nothing (and allocates nothing).
template <class Value, class Describe>
void require_acceptable(const PcgResult<Value>& result, const Value& b_norm2, Describe&& describe,
                        const char* setting) {
  if (result.acceptable()) return;
  Real worst = 0;
  for (int c = 0; c < pcg_detail::size(b_norm2); ++c)
    worst = std::max(worst, std::sqrt(pcg_detail::at(result.residual2, c) / (pcg_detail::at(b_norm2, c) + 1e-30)));
  throw SimulationError(fmt::format("{} did not converge in {} iterations (relative residual {:.3g}); raise {}",
                                    describe(), result.iterations, worst, setting));
}

}  // namespace bakesim
