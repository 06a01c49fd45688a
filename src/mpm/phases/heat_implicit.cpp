// Phase heat_solve (implicit heat, spec 4.3 with γ = 1): conjugate gradients on
// the grid nodes.
#include "mpm/solver.hpp"

#include <fmt/format.h>

#include <cmath>

#include "core/parallel.hpp"
#include "core/pcg.hpp"

namespace bakesim::mpm {

// Spec 4.3 with γ = 1: (M/Δt + K + R) θ = (M/Δt) θⁿ + b, K the weak-form
// conduction Σ_p V κ ∇w_ip ∇w_jpᵀ, R the boundary exchange Σ_p S β w_ip w_jp
// (both symmetric positive semi-definite, so the matrix is SPD), solved
// matrix-free by Jacobi-preconditioned conjugate gradients over the nodes
// with heat capacity.
void MpmSolver::phase_heat_implicit(Real dt) {
  ScopedPhase t(timers_, t_heat_);
  const Real dtb = setup_.oven.bake_step(dt);
  const std::size_t nodes = heat_state_.size();
  const Vec3 origin = grid_origin_;
  const std::size_t nz = nz_, syz = std::size_t(ny_) * nz_;
  const Real gscale = 4.0 * inv_dx_;
  std::vector<Real>& mass = implicit_mass_;
  // Particle-to-node operator: y_i = Σ_p w (a_p + g_p · o), per colour so no two threads share a node.
  auto scatter = [&](std::vector<Real>& y, auto&& particle_terms) {
    blocks_.for_each_by_colour(
        x_, origin, inv_dx_, [&](std::uint32_t p, const Axis& ax, const Axis& ay, const Axis& az) {
          Real a;
          Vec3 gv;
          Real diag_a, diag_g;
          particle_terms(p, ax, ay, az, a, gv, diag_a, diag_g);
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
              const std::size_t row = std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base;
              for (int kk = 0; kk < 3; ++kk) {
                const Vec3 o(i - ax.frac, j - ay.frac, kk - az.frac);
                const Real w = ax.w[i] * ay.w[j] * az.w[kk];
                y[row + kk] += w * (a + gv.dot(o)) + w * w * (diag_a + diag_g * o.squaredNorm());
              }
            }
        });
  };
  auto gather = [&](const std::vector<Real>& x, const Axis& ax, const Axis& ay, const Axis& az, Real& value,
                    Vec3& grad) {
    value = 0;
    grad.setZero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const std::size_t row = std::size_t(ax.base + i) * syz + std::size_t(ay.base + j) * nz + az.base;
        for (int kk = 0; kk < 3; ++kk) {
          const Real w = ax.w[i] * ay.w[j] * az.w[kk], xv = x[row + kk];
          value += w * xv;
          grad += (w * xv) * Vec3(i - ax.frac, j - ay.frac, kk - az.frac);
        }
      }
    grad *= gscale;
  };
  auto conductance = [&](std::uint32_t p) { return j_[p] * volume0_[p] * point_conductivity(p); };
  // A x restricted to the active nodes.
  auto apply = [&](const std::vector<Real>& x, std::vector<Real>& y) {
    parallel_for(
        nodes, [&](std::size_t k) { y[k] = mass[k] > 0 ? mass[k] / dtb * x[k] : 0; }, 1 << 14);
    scatter(
        y, [&](std::uint32_t p, const Axis& ax, const Axis& ay, const Axis& az, Real& a, Vec3& gv, Real& da, Real& dg) {
          Real value;
          Vec3 grad;
          gather(x, ax, ay, az, value, grad);
          a = exchange_[p] * value;
          gv = conductance(p) * gscale * grad;
          da = dg = 0;
        });
  };
  // Node vectors of the solve, kept between steps (no per-step allocation once sized).
  ImplicitHeat& h = implicit_heat_;
  for (std::vector<Real>* v : {&h.rhs, &h.diag, &h.x}) v->assign(nodes, 0);
  std::vector<Real>&rhs = h.rhs, &diag = h.diag, &x = h.x;
  // Right-hand side and the Jacobi diagonal.
  scatter(rhs, [&](std::uint32_t p, const Axis&, const Axis&, const Axis&, Real& a, Vec3& gv, Real& da, Real& dg) {
    a = exchange_t_[p];
    gv.setZero();
    da = dg = 0;
  });
  scatter(diag, [&](std::uint32_t p, const Axis&, const Axis&, const Axis&, Real& a, Vec3& gv, Real& da, Real& dg) {
    a = 0;
    gv.setZero();
    da = exchange_[p];
    dg = conductance(p) * gscale * gscale;
  });
  parallel_for(
      nodes,
      [&](std::size_t k) {
        if (mass[k] > 0) {
          const Real theta_n = heat_state_[k].theta - heat_state_[k].dtheta;
          rhs[k] += mass[k] / dtb * theta_n;
          diag[k] += mass[k] / dtb;
          x[k] = theta_n;
        } else {
          rhs[k] = 0, diag[k] = 1;
        }
      },
      1 << 14);
  // Conjugate gradients (core/pcg.hpp, shared with the SPH implicit viscosity)
  // over the nodes with heat capacity; the rest keep a unit diagonal.
  const Real rhs2 = pcg_sum<Real>(nodes, [&](std::size_t k) { return rhs[k] * rhs[k]; });
  const Real stop = setup_.settings.heat_tolerance * std::sqrt(rhs2);
  const PcgResult<Real> result = solve_pcg<Real>(
      nodes, apply, [&](std::size_t k) { return mass[k] > 0; }, diag, rhs, x, stop * stop,
      setup_.settings.heat_max_iterations, implicit_heat_.pcg);
  implicit_heat_.iterations = result.iterations;
  require_acceptable(
      result, rhs2, [&] { return fmt::format("mpm step {} (t = {:.6g} s): implicit heat", steps_ + 1, time_); },
      "solver.mpm.heat_max_iterations");
  const Real energy = deterministic_reduce(
      nodes, Real(0),
      [&](std::size_t b, std::size_t e) {
        Real sum = 0;
        for (std::size_t k = b; k < e; ++k) {
          if (!(mass[k] > 0)) continue;
          HeatState& f = heat_state_[k];
          const Real theta_n = f.theta - f.dtheta;
          f.dtheta = x[k] - theta_n;
          f.theta = x[k];
          sum += mass[k] * f.dtheta;
        }
        return sum;
      },
      [](Real a, Real b) { return a + b; });
  budget_.heat_in += energy;
}

}  // namespace bakesim::mpm
