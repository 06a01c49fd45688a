// Phase water (physics/water.hpp, docs/physics.md "Water, vapour and latent
// heat"): liquid water per particle, vapour in equilibrium with it diffusing
// through the pores, the surface's mass transfer to the oven air, latent heat
// and the boiling cap, on the bake clock.
#include "sph/solver.hpp"

#include "core/parallel.hpp"
#include "physics/water.hpp"

namespace bakesim::sph {

// Vapour and liquid move pairwise in the Cleary–Monaghan form of the heat
// phase, so every pair's exchange is equal and opposite and the water is
// conserved:
//   dm_i/dt = V_i Σ_j V_j (D_i + D_j)(c_i − c_j) x_ij·∇W_ij / (r² + η²)
// with c = ρ_v, D = φ_g D_v(θ) for the vapour and c = W/V, D = D_w(θ) for the
// liquid. The water a particle gains as vapour condenses and gives h_fg
// (evaporating takes it); at the surface m = h_m (ρ_v,face − ρ_v,air) A leaves
// (PoreWater::surface_flux: the face at the particle's moisture, or drier),
// where heat goes to the air (not to a heated collider: colliders take no
// vapour). Then the boiling cap: moist dough does not heat past θ_b.
void SphSolver::phase_water(Real dt) {
  ScopedPhase t(timers_, t_water_);
  const Real dtb = setup_.oven.bake_step(dt);
  const std::size_t n = x_.size();
  std::vector<Real>& water = *water_;
  std::vector<Real>& moisture = *moisture_;
  std::vector<Real>& vapour = *vapour_density_;
  liquid_concentration_.resize(n);
  // Per particle: moisture, vapour density and the two coefficients (0 for dry materials and held bodies).
  parallel_for(
      n,
      [&](std::size_t i) {
        const PoreWater& pw = setup_.materials[material_[i]].moisture;
        if (!pw.active() || setup_.bodies[body_[i]].hold_temperature) {
          vapour[i] = 0, water_coefficients_[i] = {0, 0};
          return;
        }
        liquid_concentration_[i] = water[i] / volume_[i];
        const Real x = pw.moisture_of(water[i], m_[i]);
        moisture[i] = x;
        vapour[i] = pw.vapour_density(temperature_[i], x);
        // Risen dough holds more gas: its expansion is ρ0/ρ.
        const Real phi = pw.expanded_gas_fraction(setup_.materials[material_[i]].rest_density / rho_[i]);
        water_coefficients_[i] = {pw.vapour_conductance(temperature_[i], phi), pw.liquid_diffusion(temperature_[i])};
      },
      4096);
  const Real h_m = setup_.oven.mass_transfer_at(time_), air_vapour = setup_.oven.air_vapour_density;
  parallel_for(n, [&](std::size_t i) {
    water_change_[i] = {0, 0};
    const auto [dv_i, dl_i] = water_coefficients_[i];
    if (!(dv_i > 0) && !(dl_i > 0)) return;
    const std::uint32_t* nb = lists_.begin(i);
    const std::uint32_t count = lists_.count(i);
    const float* w = pair_diffusion_.data() + i * lists_.stride();
    const Real ci = liquid_concentration_[i];
    Real vapour_sum = 0, liquid_sum = 0;
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::uint32_t j = nb[k];
      const auto [dv_j, dl_j] = water_coefficients_[j];
      if (!(dv_j > 0) && !(dl_j > 0)) continue;  // a dry material: no pores to share
      // The heat phase's corrected Laplacian (its weights, this step's positions).
      const Real pair = volume_[j] * Real(w[k]);
      vapour_sum += pair * (dv_i + dv_j) * (vapour[i] - vapour[j]);
      liquid_sum += pair * (dl_i + dl_j) * (ci - liquid_concentration_[j]);
    }
    Real gained_as_vapour = dtb * volume_[i] * vapour_sum;
    // The share of its area facing the air (none against a heated collider or an insulating one).
    if (face_share_[i] > 0) {
      const PoreWater& pw = setup_.materials[material_[i]].moisture;
      const Real air_area = face_share_[i] * area_[i];
      // The face's law takes the particle's rest volume m/ρ₀ for its dry density and depth: the summed
      // density of a surface particle lacks its kernel's outer half (about 20% at a flat face), which cost a
      // drying cube a fifth of its early loss (BothSolvers/SurfaceDrying). A risen particle's expansion is not
      // seen by it.
      const Real rest_volume = m_[i] / setup_.materials[material_[i]].rest_density;
      gained_as_vapour -= dtb * air_area *
                          pw.surface_flux(vapour[i], temperature_[i], moisture[i], pw.dry_mass(m_[i]), rest_volume,
                                          air_area, h_m, air_vapour, dtb);
    }
    water_change_[i] = {gained_as_vapour, dtb * volume_[i] * liquid_sum};
  });
  // Apply, with latent heat and the boiling cap; book what left.
  parallel_for(
      n,
      [&](std::size_t i) {
        step_book_[i] = {0, 0, 0};
        const PoreWater& pw = setup_.materials[material_[i]].moisture;
        if (!pw.active() || setup_.bodies[body_[i]].hold_temperature) return;
        const auto [vapour_gain, liquid_gain] = water_change_[i];
        const Real capacity = m_[i] * setup_.materials[material_[i]].specific_heat;
        Real w = water[i] + vapour_gain + liquid_gain, clamped = 0;
        if (w < 0) clamped = -w, w = 0;  // asked for more than the particle held: not removed
        const PhaseChange c = condense_and_boil(pw, capacity, temperature_[i], w, vapour_gain, m_[i]);
        temperature_[i] = c.temperature;
        water[i] = c.water;
        moisture[i] = pw.moisture_of(water[i], m_[i]);
        step_book_[i] = {c.latent, c.boiled, clamped};
      },
      4096);
  const Real latent = deterministic_sum(n, [&](std::size_t i) { return step_book_[i][0]; });
  const Real boiled = deterministic_sum(n, [&](std::size_t i) { return step_book_[i][1]; });
  const Real clamped = deterministic_sum(n, [&](std::size_t i) { return step_book_[i][2]; });
  const Real gained = deterministic_sum(n, [&](std::size_t i) { return water_change_[i][0] + water_change_[i][1]; });
  water_budget_.latent_out += latent;
  water_budget_.boiled += boiled;
  water_budget_.clamped += clamped;
  // What left through the surface is what the particles lost in all (pairs cancel), less what was not there to lose.
  water_budget_.evaporated += boiled - gained - clamped;
}

}  // namespace bakesim::sph
