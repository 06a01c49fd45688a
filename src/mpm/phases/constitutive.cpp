// Phase constitutive: per material group, setting, CO2, the return mapping of
// the plastic law, the Kirchhoff stress with the mixture pressures, and the
// heat and water terms of the next P2G (spec 2, 3.1–3.4, 4.2, 4.3).
#include "mpm/solver.hpp"

#include <algorithm>

#include "core/parallel.hpp"
#include "physics/constants.hpp"
#include "physics/heat.hpp"
#include "physics/porosity.hpp"

namespace bakesim::mpm {

// Spec 3.1–3.4: per material group, the gelatinization flag and the
// temperature-dependent τ_y(θ), η(θ); CO2 generation (3.3); the return mapping
// of the plastic law on the trial F^E; the Kirchhoff stress
// τ = τ_E − J (c λ (θ − θ_ref) + P_g + ξ (s − s₀)) I for the next P2G; the
// cooling by thermal expansion −c λ θ_K ∇·v / (ρ c) (spec 2, on the particle);
// and the heat and water terms of the next P2G (spec 4.2, 4.3).
void MpmSolver::phase_plasticity(Real dt) {
  ScopedPhase t(timers_, t_plastic_);
  const Settings& st = setup_.settings;
  const bool heat = thermal(), mixture = heat && !st.baseline;
  const Real dtb = setup_.oven.bake_step(dt);
  const Real flux_scale = 4.0 * inv_dx_;
  const Real mass_transfer = setup_.oven.mass_transfer_at(time_), air_vapour = setup_.oven.air_vapour_density;
  for (std::size_t mi = 0; mi < setup_.materials.size(); ++mi) {
    const Material& mat = setup_.materials[mi];
    const bool gas = mixture && mat.gas.active(), wet = mixture && mat.water.active();
    const bool moist = wet && mat.moisture.active();
    const Real expansion = mat.thermal_expansion * mat.lame.lambda;
    std::visit(
        [&](const auto& elastic) {
          std::visit(
              [&](const auto& plastic_law) {
                using P = std::decay_t<decltype(plastic_law)>;
                const std::vector<std::uint32_t>& members = material_members_[mi];
                // Four particles at a time: their SVDs, Hencky strains and returned
                // stretches run as one on 4-lane vectors (svd3x4, hencky_strain_x4,
                // hencky_stretch_x4), the plastic return and the stress particle by particle.
                parallel_for(
                    (members.size() + 3) / 4,
                    [&](std::size_t chunk) {
                      const std::size_t first = 4 * chunk, count = std::min<std::size_t>(4, members.size() - first);
                      Mat3 chunk_f[4];
                      Svd3 chunk_svd[4];
                      for (std::size_t l = 0; l < 4; ++l)
                        chunk_f[l] = l < count ? deformation_gradient(members[first + l]) : Mat3::Identity();
                      svd3x4(chunk_f, chunk_svd);
                      // Hencky: the principal strains once, for the return and the stress.
                      constexpr bool kHencky = std::is_same_v<std::decay_t<decltype(elastic)>, Hencky>;
                      Vec3 chunk_strain[4];
                      if constexpr (kHencky) hencky_strain_x4(chunk_svd, chunk_strain);
                      // The leavener's temperature factor of the four at once (physics/leavening.hpp).
                      Lane4 leavening = Lane4::Zero();
                      if (gas)
                        leavening = mat.gas.profile(Lane4::NullaryExpr([&](Eigen::Index l) {
                          return std::size_t(l) < count ? temperature_[members[first + l]] : mat.gas.peak_temperature;
                        }));
                      // The plastic return on each particle's strains (its Newton solve is
                      // scalar), then the new stretches e^ε of the four at once.
                      if constexpr (!std::is_same_v<P, NoPlasticity>) {
                        bool yielded[4] = {false, false, false, false};
                        for (std::size_t l = 0; l < count; ++l) {
                          const std::size_t i = members[first + l];
                          const Real theta = temperature_[i];
                          P law = plastic_law;
                          if (heat && mat.setting) {
                            peak_temperature_[i] = std::max(peak_temperature_[i], theta);
                            if (!gelatinized_[i] && mat.set.is_set(peak_temperature_[i]))
                              gelatinized_[i] = 1, jp_set_[i] = jp_[i];
                            const Real te = mat.set.property_temperature(theta, peak_temperature_[i]);
                            law.yield_stress = mat.setting->yield_stress(te);
                            law.viscosity = mat.setting->viscosity(te);
                          }
                          if constexpr (std::is_same_v<P, CamClay>) {
                            if (heat && st.baseline)
                              law.cohesion_slope = 0;  // baseline: no porosity in the yield surface
                            // τ_y is a Cauchy stress: in Kirchhoff stress the surface grows with the
                            // plastic dilation, so gas (whose Kirchhoff pressure n R θ / n_p barely
                            // falls as pores grow) expands a dough to a finite size.
                            law.yield_stress *= jp_[i];
                            // Brittle set crust (a departure, docs/physics.md): dilation after setting weakens it.
                            if (wet && mat.setting && gelatinized_[i]) {
                              const Real water_lost =
                                  1 - water_[i] / (mat.water.saturation * mat.water.water_density * volume0_[i]);
                              law.yield_stress *= mat.setting->softening_factor(jp_[i], jp_set_[i], water_lost);
                            }
                          }
                          if constexpr (kHencky) {
                            yielded[l] = return_strain(law, mat.lame, dt, jp_[i], chunk_strain[l]);
                          } else {  // refused by the scene check (plasticity needs Hencky); kept general
                            Svd3& s = chunk_svd[l];
                            const Vec3 trial = s.sigma;
                            s = return_map(law, mat.lame, dt, jp_[i], s);
                            if (s.sigma != trial) chunk_f[l] = compose(s), set_deformation_gradient(i, chunk_f[l]);
                          }
                        }
                        if constexpr (kHencky) {
                          if (yielded[0] || yielded[1] || yielded[2] || yielded[3]) {
                            Vec3 returned[4], stretch[4];
                            for (int l = 0; l < 4; ++l) returned[l] = yielded[l] ? chunk_strain[l] : Vec3::Zero();
                            hencky_stretch_x4(returned, stretch);
                            for (std::size_t l = 0; l < count; ++l)
                              if (yielded[l]) {
                                chunk_svd[l].sigma = stretch[l];
                                set_deformation_gradient(members[first + l], compose(chunk_svd[l]));
                              }
                          }
                        }
                        for (std::size_t l = 0; l < count; ++l) {
                          const std::size_t i = members[first + l];
                          jp_[i] = j_[i] / chunk_svd[l].sigma.prod();
                        }
                      }
                      for (std::size_t l = 0; l < count; ++l) {
                        const std::size_t i = members[first + l];
                        const Real theta = temperature_[i];
                        const Mat3& f = chunk_f[l];
                        const Svd3& s = chunk_svd[l];
                        const Vec3& strain = chunk_strain[l];
                        Mat3 tau;
                        if constexpr (kHencky)
                          tau = hencky_stress(elastic.lame, strain, s.u);
                        else
                          tau = kirchhoff_stress(elastic, f, s);
                        if (heat) {
                          const Real j = j_[i], volume = j * volume0_[i];
                          Real kirchhoff_pressure = 0;
                          if (expansion != 0) {
                            const Real theta_ref = setup_.bodies[body_[i]].temperature;
                            kirchhoff_pressure += j * expansion * (theta - theta_ref);
                            // Spec 2: ρ c Dθ/Dt = −c λ θ_K ∇·v (mechanical time; ∇·v = tr C).
                            const Real div_v = c0_[i].x() + c1_[i].y() + c2_[i].z();
                            temperature_[i] -=
                                dt * expansion * (theta + kZeroCelsius) * div_v * volume / heat_capacity_[i];
                          }
                          if (gas) {
                            co2_[i] = mat.gas.generated_at(co2_[i], dtb, leavening[l], mat.density);
                            const Real jp_gas = Leavening::kirchhoff_pressure(
                                co2_[i], theta, gas_porosity(jp_[i], mat.initial_porosity));
                            gas_pressure_[i] = jp_gas / j;
                            kirchhoff_pressure += jp_gas;
                          }
                          Real sat = 0;
                          if (wet) {
                            sat = water_[i] / (mat.water.water_density * volume);
                            saturation_[i] = sat;
                            kirchhoff_pressure += j * mat.water.pressure(sat);
                            water_src_[i] = -mat.water.evaporation_flux_below(theta, sat, air_depth_[i]) * air_area_[i];
                            water_vec_[i] = -(volume * mat.water.diffusion_coefficient(theta) *
                                              mat.water.water_density * flux_scale) *
                                            grad_s_[i];
                            if (moist) {
                              // physics/water.hpp: the vapour in equilibrium with the moisture,
                              // its flux through the pores and what leaves through the surface.
                              const PoreWater& pw = mat.moisture;
                              const Real x = pw.moisture_of(water_[i], m_[i]);
                              const Real phi = pw.expanded_gas_fraction(j);  // risen dough holds more gas
                              const PoreWater::PoreVapour vapour = pw.pore_vapour(theta, x, phi);
                              moisture_[i] = x;
                              vapour_density_[i] = vapour.density;
                              vapour_src_[i] =
                                  air_area_[i] > 0
                                      ? -air_area_[i] * pw.surface_flux(vapour.density, theta, x, pw.dry_mass(m_[i]),
                                                                        volume, air_area_[i], mass_transfer, air_vapour,
                                                                        dtb)
                                      : 0;
                              cell_k_[i] =
                                  vapour.cell_conductivity + pw.matrix_conductivity_change(mat.conductivity, x, phi);
                              vapour_vec_[i] =
                                  -(volume * pw.vapour_conductance(theta, phi) * flux_scale) * grad_vapour_[i];
                            }
                          }
                          tau.diagonal().array() -= kirchhoff_pressure;
                          heat_src_[i] = SurfaceExchange{exchange_[i], exchange_t_[i]}.heat_rate(temperature_[i]);
                          heat_vec_[i] = -(volume * (mat.conductivity + cell_k_[i]) * flux_scale) * grad_theta_[i];
                        }
                        tau_diag_[i] = tau.diagonal();
                        tau_off_[i] = Vec3(tau(0, 1), tau(0, 2), tau(1, 2));
                      }
                    },
                    256);
              },
              mat.plastic);
        },
        mat.elastic);
  }
}

}  // namespace bakesim::mpm
