// Phases heat (conduction Eq 3.45–3.46, surface exchange Eq 3.42–3.43) and
// browning (Zanoni et al. 1995), both on the bake clock.
#include "sph/solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.hpp"
#include "physics/heat.hpp"

namespace bakesim::sph {

namespace {
// The smallest kernel moment the corrected Laplacian divides by (a fourfold rate at most).
constexpr Real kMinLaplacianMoment = 0.25;
}  // namespace

// The support's moment a_i = −(1/3) Σ_j V_j x_ij·∇W_ij (1 when full), what the
// corrected Laplacian below divides by; all 1 when the scene turns it off.
void SphSolver::update_laplacian_moments() {
  const std::size_t n = x_.size();
  laplacian_moment_.resize(n);
  if (!setup_.settings.corrected_laplacian) {
    std::fill(laplacian_moment_.begin(), laplacian_moment_.end(), Real(1));
    return;
  }
  parallel_for(
      n,
      [&](std::size_t i) {
        const std::uint32_t* nb = lists_.begin(i);
        const float* r = lists_.distances(i);
        const float* pd = pair_dwr_.data() + i * lists_.stride();
        Real a = 0;
        for (std::uint32_t k = 0; k < lists_.count(i); ++k)
          a -= volume_[nb[k]] * Real(r[k]) * Real(r[k]) * Real(pd[k]);  // x_ij·∇W_ij = r² W'(r)/r
        // Below a quarter (a particle almost alone) the sum says little: no more than fourfold.
        laplacian_moment_[i] = std::clamp(a / 3, kMinLaplacianMoment, Real(1));
      },
      4096);
}

// The pair weights of the corrected Laplacian, x_ij·∇W_ij/(r² + η²) ·
// 2/(a_i + a_j), once a step for the heat and the water phases (two
// divisions a pair, which the phases' loops otherwise each paid). Kept in
// single precision like the kernel derivative they are made of; the same
// rounding for (i, j) and (j, i), so the exchanges stay equal and opposite.
void SphSolver::update_diffusion_weights() {
  const std::size_t n = x_.size();
  const std::size_t stride = lists_.stride();
  resize_with_headroom(pair_diffusion_, n * stride);
  const Real eta2_fixed = 0.01 * h_ * h_;
  parallel_for(n, [&](std::size_t i) {
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* pr = lists_.distances(i);
    const float* pd = pair_dwr_.data() + i * stride;
    float* w = pair_diffusion_.data() + i * stride;
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const Real hij = 0.5 * (smoothing_[i] + smoothing_[j]);
      const Real eta2 = adaptive_ ? 0.01 * hij * hij : eta2_fixed;
      w[k] = float(pair_diffusion_weight(Real(pd[k]), Real(pr[k]), eta2) * laplacian_correction(i, j));
    }
  });
}

// Eq 3.45–3.46: ρ c_p dT/dt = ∇·(k∇T). The kernel Laplacian of Eq 3.46
// changes sign inside the support (heat could flow from cold to hot for close
// pairs), so the Laplacian is taken in the Cleary–Monaghan form
//   (∇·k∇T)_i = Σ_j V_j (k_i + k_j)(T_i − T_j) x_ij·∇W_ij / (r² + η²) · 2/(a_i + a_j),
// which is always diffusive and exchanges heat pairwise (energy is conserved).
// a_i = −(1/3) Σ_j V_j x_ij·∇W_ij is the support's moment, 1 when it is full:
// the sum is exact for a quadratic field only then, and risen crumb, whose
// bubbles grew apart, holds a third of it (docs/physics.md, Heat conduction).
// Dividing by the pair's mean moment (the scalar renormalisation of the CSPM,
// Chen, Beraun & Carney 1999, kept symmetric) restores the rate.
// Then Eq 3.42–3.43 at surface particles, taken at the particle's face:
// m c_p dT/dt = h A (T_ext − T_face) (crust_face below, physics/heat.hpp) with
// T_ext the touching collider's temperature, or the oven air's. Heat runs on
// the bake clock: dt_bake = scale · dt.
void SphSolver::phase_heat(Real dt, bool& weights_ready) {
  ScopedPhase t(timers_, t_heat_);
  const Oven& oven = setup_.oven;
  const Real dt_bake = oven.bake_step(dt);
  const std::size_t n = x_.size();
  // Nothing flows in an isothermal state (a common case: water at room
  // temperature); without water to move either, the Laplacian's weights are
  // not needed this step (they were 13 of 360 ms a step of a 100K-particle
  // dam break).
  bool isothermal = false;
  if (setup_.settings.heat_conduction) {
    using Range = std::pair<Real, Real>;
    const Real inf = std::numeric_limits<Real>::infinity();
    const Range range = deterministic_reduce(
        n, Range{inf, -inf},
        [&](std::size_t b, std::size_t e) {
          Range r{inf, -inf};
          for (std::size_t i = b; i < e; ++i) {
            r.first = std::min(r.first, temperature_[i]);
            r.second = std::max(r.second, temperature_[i]);
          }
          return r;
        },
        [](Range a, Range b) {
          return Range{std::min(a.first, b.first), std::max(a.second, b.second)};
        });
    isothermal = !(range.second > range.first);
  }
  if (((setup_.settings.heat_conduction && !isothermal) || moist_) && !weights_ready) {  // the water phase's too
    update_laplacian_moments();
    update_diffusion_weights();
    weights_ready = true;
  }
  if (setup_.settings.heat_conduction && !isothermal) {
    const Real* temp = temperature_.data();
    const Real* vol = volume_.data();
    // With moisture: the closed-cell heat pipe of moist dough adds to k (physics/water.hpp).
    if (moist_)
      parallel_for(
          n,
          [&](std::size_t i) {
            const Material& mi = setup_.materials[material_[i]];
            const PoreWater& pw = mi.moisture;
            particle_k_[i] = mi.conductivity;
            if (pw.active() && !setup_.bodies[body_[i]].hold_temperature) {
              const Real phi = pw.expanded_gas_fraction(mi.rest_density / rho_[i]);
              particle_k_[i] += pw.cell_conductivity(temp[i], (*moisture_)[i], phi) +
                                pw.matrix_conductivity_change(mi.conductivity, (*moisture_)[i], phi);
            }
          },
          4096);
    parallel_for(n, [&](std::size_t i) {
      const Material& mi = setup_.materials[material_[i]];
      const Real ti = temp[i], ki = moist_ ? particle_k_[i] : mi.conductivity;
      const std::uint32_t* nb = lists_.begin(i);
      const std::uint32_t count = lists_.count(i);
      const float* w = pair_diffusion_.data() + i * lists_.stride();
      Real sum = 0;
      for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint32_t j = nb[k];
        const Real kj = moist_ ? particle_k_[j] : conductivity_[material_[j]];
        sum += pair_conduction_weighted(vol[j], ki, kj, ti, temp[j], Real(w[k]));
      }
      dtemp_[i] = setup_.bodies[body_[i]].hold_temperature ? 0.0 : dt_bake * sum / (rho_[i] * mi.specific_heat);
    });
    parallel_for(
        n, [&](std::size_t i) { temperature_[i] += dtemp_[i]; }, 4096);
  }
  // External exchange (Eq 3.42 with the sign and heat capacity restored).
  const Real air = oven.air_temperature(bake_time());
  const Real touch = setup_.settings.spacing;  // contact: within one spacing of the collider surface
  // Collider temperatures at this bake time, read once (walls, then meshes).
  wall_temperatures_.read(
      walls_.size(), [&](std::size_t c) -> const auto& { return walls_[c].temperature; }, bake_time());
  mesh_temperatures_.read(
      meshes_.size(), [&](std::size_t c) -> const auto& { return meshes_[c].temperature; }, bake_time());
  parallel_for(
      n,
      [&](std::size_t i) {
        dtemp_[i] = 0.0;
        air_facing_[i] = 0;
        face_share_[i] = 0;
        face_coefficient_[i] = 0;  // no face: the browning phase takes the particle's temperature
        if (!surface_[i] || area_[i] <= 0 || setup_.bodies[body_[i]].hold_temperature) return;
        // The area splits by what it faces, as MPM splits a node's boundary
        // area: the share facing a collider is the colour gradient's component
        // along the collider's normal (the area vector projected on it), so a
        // layer on a tray gives the tray its footprint and an edge particle
        // gives the air its side. Colliders without a temperature insulate
        // their share; the domain's walls (no temperature) are skipped: in MPM
        // the air reaches a face on them. A mesh collider is found along the
        // outward normal and its share is the same projection on the normals
        // of the faces hit. (Before, a particle touching a heated collider gave
        // it its whole area: the slab's bottom edge gave the tray its sides.)
        // A surface particle's area is V |∇C| / S > 0, so its normal exists.
        const Vec3 inward = colour_grad_[i].normalized();
        Real insulated = 0;
        SurfaceExchange toward;  // the heated colliders' parts: Σ share β and Σ share β θ
        Real heated = 0;         // Σ share
        for (std::size_t ci = kDomainWall + 1; ci < walls_.size(); ++ci) {
          const Collider& c = walls_[ci];
          Real part = 0;
          for_each_wall_of(ci, x_[i], touch, [&](const WallContact& w, const Vec3&) {
            part = std::max(part, std::clamp(inward.dot(w.normal), Real(0), Real(1)));
          });
          if (!(part > 0)) continue;
          if (!c.temperature) {
            insulated = std::max(insulated, part);
          } else {
            heated += part;
            toward.add(part, c.heat_transfer_coefficient, wall_temperatures_[ci]);
          }
        }
        if (heated_colliders_) {
          for (std::size_t ci = 0; ci < meshes_.size(); ++ci) {
            const Collider& c = meshes_[ci];
            if (!c.temperature) continue;
            const SegmentHit hit =
                mesh_segment_hits(std::get<MeshCollider>(c.geometry), x_[i], x_[i] - touch * inward, 0.0);
            if (hit.hits == 0) continue;
            const Real nn = hit.normal_sum.norm();
            const Real part = nn > 0 ? std::abs(inward.dot(hit.normal_sum) / nn) : Real(1);
            heated += part;
            toward.add(part, c.heat_transfer_coefficient, mesh_temperatures_[ci]);
          }
        }
        // The colliders' mean coefficient and temperature over their parts; a
        // corner against two heated faces gives them all of its area (the
        // parts summed, at most one).
        const Real collider_beta = heated > 0 ? toward.conductance / heated : 0;
        const Real collider_outside = toward.conductance > 0 ? toward.drive / toward.conductance : air;
        heated = std::min(heated, Real(1));
        const Real air_share = std::max(Real(0), 1 - heated - insulated);
        face_share_[i] = air_share;
        if (!(air_share > 0) && !(heated > 0)) return;  // against insulating walls all round: no exchange
        air_facing_[i] = air_share > 0 && air_share >= heated;
        const Real capacity = m_[i] * setup_.materials[material_[i]].specific_heat;
        const Real before = temperature_[i];
        const Real air_beta = oven.surface_coefficient(before, air);
        // The face the browning reads: the larger of the air's and the colliders'.
        const bool collider_face = heated > air_share;
        face_outside_[i] = collider_face ? collider_outside : air;
        face_coefficient_[i] = collider_face ? collider_beta : air_beta;
        // Each face takes β (θ_out − θ_f) and passes it to the particle through its half-layer.
        const CrustFace face = crust_face(i);
        SurfaceExchange exchange;
        if (air_share > 0) exchange.add(air_share * area_[i], face.coefficient_to_centre(before, air, air_beta), air);
        if (heated > 0 && collider_beta > 0)
          exchange.add(heated * area_[i] * contact_area_scale(i),
                       face.coefficient_to_centre(before, collider_outside, collider_beta), collider_outside);
        if (!(exchange.conductance > 0)) return;  // coefficients of zero (no air exchange in the scene)
        temperature_[i] = SurfaceExchange::relax(before, exchange.drive / exchange.conductance, exchange.conductance,
                                                 1.0, capacity, dt_bake);
        dtemp_[i] = exchanged_energy(before, temperature_[i], capacity);
      },
      1024);
  exchanged_heat_ += deterministic_sum(n, [&](std::size_t i) { return dtemp_[i]; });
}

// The layer from particle i to its face: half its width, V^(1/3)/2; a moist
// particle's dried share is crust (the material's dry_conductivity), the rest
// conducts with the material's k and the closed-cell heat pipe.
CrustFace SphSolver::crust_face(std::size_t i) const {
  const Material& mi = setup_.materials[material_[i]];
  const PoreWater& pw = mi.moisture;
  // Without water (none carried, or a dry material) the profile is the dry half-cell with the material's k.
  Real x = 0, water = 0, heat_pipe = 0;
  if (moist_ && pw.active()) {
    x = (*moisture_)[i], water = (*water_)[i];
    heat_pipe = pw.cell_conductivity(temperature_[i], x, pw.expanded_gas_fraction(mi.rest_density / rho_[i]));
  }
  return pw.crust_face(0.5 * std::cbrt(volume_[i]), x, water, mi.conductivity, mi.conductivity + heat_pipe);
}

// The area S is calibrated on a free face, whose volumes m/ρ come from the
// summed density alone. Near a wall the density has the wall half-space's mass
// too (the wall density correction): right for the area a particle turns to the
// air, where the wall stands in for the material beside the face as a
// continued face's particles would, but 15% short for the area it turns to the
// wall itself (a slab's layer on its tray: 3.40e-6 against 4.00e-6 m² at 2 mm
// spacing). Its shares against colliders take the area times this ratio, the
// corrected density over the summed one (≥ 1).
Real SphSolver::contact_area_scale(std::size_t i) const {
  if (!setup_.settings.wall_density_correction) return 1;
  const Real summed = rho_[i] - setup_.materials[material_[i]].rest_density * wall_share(x_[i], nullptr);
  return summed > 0 ? rho_[i] / summed : 1;
}

// Crust colour (Zanoni et al. 1995, physics/browning.hpp) on the bake clock.
// A surface particle browns at its face's temperature (crust_face above), any
// other at its own; moist dough only above its boiling point (the dried crust).
void SphSolver::phase_browning(Real dt) {
  ScopedPhase t(timers_, t_browning_);
  const BrowningKinetics& kinetics = setup_.oven.browning;
  const Real dt_bake = setup_.oven.bake_step(dt);
  parallel_for(
      x_.size(),
      [&](std::size_t i) {
        const Real theta = temperature_[i];
        surface_temperature_[i] =
            face_coefficient_[i] > 0 ? crust_face(i).temperature(theta, face_outside_[i], face_coefficient_[i]) : theta;
        const Real from = setup_.materials[material_[i]].moisture.browning_threshold(moist_);
        browning_[i] = kinetics.advance_above(browning_[i], surface_temperature_[i], from, dt_bake);
      },
      4096);
}

}  // namespace bakesim::sph
