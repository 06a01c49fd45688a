// Implicit viscosity: the viscous term of Eq 3.19 integrated by backward
// Euler, so that doughs of 10³–10⁴ Pa·s (thesis Table 4.1) do not force the
// explicit viscous time step (h²/ν, ~10⁻⁷ s) on the whole bake.
//
// Multiplying Eq 3.19 by m_i gives a symmetric graph Laplacian:
//   m_i dv_i/dt = Σ_j w_ij (v_j − v_i),  w_ij = μ̄_ij V_i V_j ∇²W_visc(r_ij) ≥ 0,
// so (M + dt K) v^{n+1} = M v* is symmetric positive definite and is solved
// matrix-free by conjugate gradients with a Jacobi preconditioner, the three
// velocity components side by side. Rows of K sum to zero: momentum is
// conserved to the solver tolerance.
#include <fmt/format.h>

#include <cmath>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "sph/solver.hpp"

namespace bakesim::sph {

namespace {

template <class Term>
Vec3 sum_blocks(std::size_t n, Term&& term) {
  return deterministic_reduce(
      n, Vec3(Vec3::Zero()),
      [&](std::size_t b, std::size_t e) {
        Vec3 s = Vec3::Zero();
        for (std::size_t i = b; i < e; ++i) s += term(i);
        return s;
      },
      [](const Vec3& a, const Vec3& b) { return Vec3(a + b); });
}

}  // namespace

void SphSolver::phase_viscosity(Real dt) {
  viscosity_iterations_ = 0;
  if (!implicit_viscosity_) return;
  ScopedPhase t(timers_, t_viscosity_);
  const std::size_t n = x_.size();
  const std::size_t stride = lists_.stride();
  const Real visc_c = visc_lap_.coefficient();
  pair_visc_.resize(n * stride);
  cg_r_.resize(n);
  cg_z_.resize(n);
  cg_p_.resize(n);
  cg_ap_.resize(n);
  std::vector<Real>& diag = dtemp_;  // free until the heat phase
  // Weights dt·w_ij and the preconditioner diagonal m_i + dt Σ_j w_ij.
  parallel_for(n, [&](std::size_t i) {
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pr = lists_.distances(i);
    double* w = pair_visc_.data() + i * stride;
    const Real vi = m_[i] / rho_[i];
    Real d = m_[i];
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const Real hij = adaptive_ ? 0.5 * (smoothing_[i] + smoothing_[j]) : h_;  // Eq 3.56
      const Real vc = adaptive_ ? ViscosityLaplacian::coefficient_for(hij) : visc_c;
      w[k] = dt * 0.5 * (mu_[i] + mu_[j]) * vi * (m_[j] / rho_[j]) * vc * (hij - Real(pr[k]));
      d += w[k];
    }
    diag[i] = d;
  });
  auto apply = [&](const std::vector<Vec3>& in, std::vector<Vec3>& out) {
    parallel_for(n, [&](std::size_t i) {
      const std::uint32_t* nb = lists_.begin(i);
      const std::uint32_t count = lists_.count(i);
      const double* w = pair_visc_.data() + i * stride;
      Vec3 acc = m_[i] * in[i];
      for (std::uint32_t k = 0; k < count; ++k) acc += w[k] * (in[i] - in[nb[k]]);
      out[i] = acc;
    });
  };
  // r = b − A v* with b = M v*: r = −dt K v*.
  apply(v_, cg_ap_);
  parallel_for(
      n,
      [&](std::size_t i) {
        cg_r_[i] = m_[i] * v_[i] - cg_ap_[i];
        cg_z_[i] = cg_r_[i] / diag[i];
        cg_p_[i] = cg_z_[i];
      },
      4096);
  // Residuals are measured against the momentum M v* plus the momentum one
  // step of gravity adds (m g dt per particle): a body nearly at rest then
  // does not demand a solve far below what its next step changes anyway.
  const Real floor_v = std::max(setup_.gravity.norm(), 1.0) * dt;
  const Vec3 b_norm2 = sum_blocks(n, [&](std::size_t i) {
    return Vec3((m_[i] * v_[i]).cwiseAbs2() + Vec3::Constant(m_[i] * m_[i] * floor_v * floor_v));
  });
  const Real tol = setup_.settings.implicit_tolerance;
  const Vec3 stop = (tol * tol) * b_norm2;
  Vec3 rz = sum_blocks(n, [&](std::size_t i) { return Vec3(cg_r_[i].cwiseProduct(cg_z_[i])); });
  Vec3 r2 = sum_blocks(n, [&](std::size_t i) { return Vec3(cg_r_[i].cwiseAbs2()); });
  const int max_it = setup_.settings.implicit_max_iterations;
  int it = 0;
  while (it < max_it && (r2.array() > stop.array()).any()) {
    apply(cg_p_, cg_ap_);
    const Vec3 pap = sum_blocks(n, [&](std::size_t i) { return Vec3(cg_p_[i].cwiseProduct(cg_ap_[i])); });
    Vec3 alpha;
    for (int c = 0; c < 3; ++c) alpha[c] = pap[c] > 0 && r2[c] > stop[c] ? rz[c] / pap[c] : 0.0;
    parallel_for(
        n,
        [&](std::size_t i) {
          v_[i] += alpha.cwiseProduct(cg_p_[i]);
          cg_r_[i] -= alpha.cwiseProduct(cg_ap_[i]);
          cg_z_[i] = cg_r_[i] / diag[i];
        },
        4096);
    const Vec3 rz_new = sum_blocks(n, [&](std::size_t i) { return Vec3(cg_r_[i].cwiseProduct(cg_z_[i])); });
    r2 = sum_blocks(n, [&](std::size_t i) { return Vec3(cg_r_[i].cwiseAbs2()); });
    Vec3 beta;
    for (int c = 0; c < 3; ++c) beta[c] = rz[c] > 0 ? rz_new[c] / rz[c] : 0.0;
    rz = rz_new;
    parallel_for(
        n, [&](std::size_t i) { cg_p_[i] = cg_z_[i] + beta.cwiseProduct(cg_p_[i]); }, 4096);
    ++it;
  }
  viscosity_iterations_ = it;
  if ((r2.array() > stop.array()).any() && !(r2.array() <= 1e4 * stop.array()).all())
    throw SimulationError(
        fmt::format("SPH step {} (t = {:.6g} s): implicit viscosity did not converge in {} iterations "
                    "(relative residual {:.3g}); raise solver.sph.implicit_viscosity.max_iterations",
                    steps_, time_, it, std::sqrt((r2.array() / (b_norm2.array() + 1e-30)).maxCoeff())));
}

}  // namespace bakesim::sph
