// The water, vapour and latent-heat law (physics/water.hpp) alone, against
// outside numbers: the IAPWS-IF97 saturation line, the ideal-gas vapour
// density, the Oswin isotherm's own inverse, energy conservation of the
// boiling cap, and the Chilton–Colburn coefficient of the spec.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "physics/heat.hpp"
#include "physics/water.hpp"

using namespace bakesim;

TEST(Water, SaturationPressureFollowsTheSteamTablesWithinOnePercent) {
  // IAPWS-IF97 saturation pressures, kPa.
  const std::pair<double, double> table[] = {{20, 2.3392},  {60, 19.946},  {100, 101.42},
                                             {120, 198.67}, {150, 476.16}, {180, 1002.8}};
  for (const auto& [celsius, kpa] : table)
    EXPECT_NEAR(saturation_vapour_pressure(celsius) / 1000, kpa, 0.01 * kpa) << celsius << " degC";
  // The slope is the derivative of the same correlation (central difference), ~3.6 kPa/K at 100 degC.
  for (const double c : {40.0, 80.0, 99.0, 130.0}) {
    const double fd = (saturation_vapour_pressure(c + 1e-4) - saturation_vapour_pressure(c - 1e-4)) / 2e-4;
    EXPECT_NEAR(saturation_vapour_pressure_slope(c), fd, 1e-6 * fd) << c;
  }
  EXPECT_NEAR(saturation_vapour_pressure_slope(99.9), 3616, 0.03 * 3616);  // steam tables: 3.62 kPa/K
}

TEST(Water, BoilingPointFollowsTheSteamTablesUnderThePressure) {
  // Free water boils where p_sat(θ) is the air's pressure: exactly 100 degC at 1 atm, and at the
  // IAPWS-IF97 saturation temperatures of lower and higher pressures (kPa).
  EXPECT_DOUBLE_EQ(boiling_point_at(kAtmosphere), 100.0);
  const std::pair<double, double> table[] = {{47.416, 80}, {70.183, 90}, {84.609, 95}, {143.38, 110}};
  for (const auto& [kpa, celsius] : table) EXPECT_NEAR(boiling_point_at(1000 * kpa), celsius, 0.1) << kpa << " kPa";
  // The same equation both ways.
  for (const double c : {60.0, 93.0, 99.0})
    EXPECT_NEAR(saturation_temperature(saturation_vapour_pressure(c)), c, 1e-9) << c;
}

TEST(Water, LowerAirPressureSpeedsTheVapourAndItsSurfaceTransfer) {
  // Binary diffusion goes as 1/p (Chapman–Enskog), and the Chilton–Colburn h_m as 1/ρ_air.
  PoreWater sea, up;
  up.air_pressure = 0.8 * kAtmosphere;
  EXPECT_NEAR(up.vapour_conductance(80) / sea.vapour_conductance(80), 1.25, 1e-12);
  sea.moisture = up.moisture = 0.5;
  EXPECT_NEAR(up.cell_conductivity(80, 0.5, 0.6) / sea.cell_conductivity(80, 0.5, 0.6), 1.25, 1e-12);
  EXPECT_NEAR(mass_transfer_coefficient(10, 190, 0.8 * kAtmosphere) / mass_transfer_coefficient(10, 190), 1.25, 1e-12);
}

TEST(Water, SaturationPressureIsContinuousWhereItsTwoBranchesMeet) {
  const double meet = 108.26631;
  EXPECT_NEAR(saturation_vapour_pressure(meet + 1e-7) / saturation_vapour_pressure(meet - 1e-7), 1.0, 1e-6);
  EXPECT_NEAR(saturation_vapour_pressure(100 + 1e-9) / saturation_vapour_pressure(100 - 1e-9), 1.0, 1e-9);
}

TEST(Water, BoundWaterBoilsOntoItsLineWhenTheBoilingPointIsBelow100) {
  // At 235 m (98.5 kPa, water boils at 99.2 degC) the boiling line of bound water crosses 100 degC:
  // X_b falls smoothly through it, and a particle boiled from just above its line ends on the line
  // of the water it keeps (with the branches switched at 100 degC, X_b jumped from 0.309 to 0.284
  // there and dough at X = 0.30 ended 6 K below its line, at 94 degC).
  PoreWater pw;
  pw.moisture = 0.56;
  pw.boiling_point = boiling_point_at(98534);
  EXPECT_NEAR(pw.boiling_point, 99.22, 0.01);
  double previous = pw.boiling_moisture(99.5);
  for (double t = 99.55; t < 101.0; t += 0.05) {
    const double x = pw.boiling_moisture(t);
    EXPECT_LT(x, previous) << t;
    EXPECT_GT(x, 0.93 * previous) << t;  // no jump
    previous = x;
  }
  const double mass = 1e-6, dry = pw.dry_mass(mass), heat_capacity = 1892 * mass;
  for (const double x : {0.33, 0.31, 0.30, 0.29}) {
    const double line = pw.boiling_temperature(x);
    const Boiling b = boil_bound(pw, heat_capacity, line + 0.05, x * dry, dry);
    EXPECT_NEAR(b.temperature, pw.boiling_temperature(b.water / dry), 1e-6) << x;
    EXPECT_GT(b.temperature, line) << x;
  }
}

TEST(Water, PowerOneAndThreeQuartersIsPowsWithinRoundOff) {
  // The vapour diffusivity's (T/298.15)^1.75 with square roots, over the bake's range (-50 to 300 degC).
  for (const double r : {0.7, 0.9, 1.0, 1.25, 1.5, 1.9})
    EXPECT_NEAR(power_1_75(r), std::pow(r, 1.75), 4e-16 * std::pow(r, 1.75)) << r;
}

TEST(Water, VapourDensityIsTheIdealGasAtTheActivityAndStopsAtTheBoilingPoint) {
  PoreWater w;
  w.moisture = 0.5;
  // Saturated steam at 100 degC: 0.598 kg/m^3 (steam tables); the ideal gas gives 0.589 at 1 atm.
  const double wet = 20.0;  // a_w = 1 to 2e-5 at X = 20 with the default isotherm
  EXPECT_NEAR(w.sorption.activity(wet, 100), 1.0, 1e-4);
  EXPECT_NEAR(w.vapour_density(100, wet), 0.598, 0.02 * 0.598);
  EXPECT_EQ(w.vapour_density(140, wet), w.vapour_density(100, wet));
  const double a = w.sorption.activity(0.1, 60);
  EXPECT_NEAR(w.vapour_density(60, 0.1), a * saturation_vapour_pressure(60) * 0.018015 / (8.314462618 * 333.15), 1e-12);
  EXPECT_EQ(w.vapour_density(60, 0), 0.0);
}

TEST(Water, OswinActivityInvertsTheIsothermAndFallsAsTheDoughDries) {
  SorptionIsotherm s;
  s.oswin_a_slope = -0.0056, s.oswin_a_offset = 5.5, s.oswin_exponent = 0.38;
  for (const double aw : {0.1, 0.5, 0.9, 0.99})
    for (const double celsius : {25.0, 90.0}) {
      const double a = std::exp(s.oswin_a_slope * (celsius + 273.15) + s.oswin_a_offset);
      const double x = a / 100 * std::pow(aw / (1 - aw), s.oswin_exponent);  // the isotherm, forwards
      EXPECT_NEAR(s.activity(x, celsius), aw, 1e-12);
    }
  const SorptionIsotherm defaults;
  EXPECT_NEAR(defaults.activity(0.3, 25), 0.97, 0.005);  // moist crumb
  EXPECT_GT(defaults.activity(0.5, 25), 0.99);
  EXPECT_NEAR(defaults.activity(0.1, 25), 0.45, 0.01);
  EXPECT_LT(defaults.activity(0.03, 25), 0.02);  // a dry crust
}

TEST(Water, BoilingCapConservesEnergyAndOnlyDryDoughHeatsPastIt) {
  const double c = 2.0, hfg = 2.257e6;  // J/K, J/kg
  // Enough water: the particle stays at the boiling point and the excess boils off.
  Boiling b = boil(c, 130, 1e-3, 100, hfg);
  EXPECT_EQ(b.temperature, 100.0);
  EXPECT_NEAR(b.boiled, c * 30 / hfg, 1e-18);
  EXPECT_NEAR(c * 130, c * b.temperature + hfg * b.boiled, 1e-9);
  EXPECT_NEAR(b.water + b.boiled, 1e-3, 1e-18);
  // Too little: it boils dry and the rest heats it.
  b = boil(c, 130, 1e-5, 100, hfg);
  EXPECT_EQ(b.water, 0.0);
  EXPECT_NEAR(b.temperature, 130 - hfg * 1e-5 / c, 1e-9);
  EXPECT_NEAR(c * 130, c * b.temperature + hfg * b.boiled, 1e-9);
  // Below the boiling point or dry: untouched.
  EXPECT_EQ(boil(c, 99, 1e-3, 100, hfg).boiled, 0.0);
  EXPECT_EQ(boil(c, 150, 0, 100, hfg).temperature, 150.0);
}

// Bound water: above θ_b dough keeps the moisture its isotherm binds where
// a_w(X, θ) p_sat(θ) = p_sat(θ_b) (the pores open to the oven's pressure).
TEST(Water, BoundWaterBoilsOnTheIsothermsBoilingLine) {
  PoreWater w;
  w.moisture = 0.5;
  const double ambient = saturation_vapour_pressure(100);
  for (const double theta : {100.5, 110.0, 130.0, 160.0, 200.0}) {
    const double x = w.boiling_moisture(theta);
    EXPECT_NEAR(w.sorption.activity(x, theta) * saturation_vapour_pressure(theta), ambient, 1e-10 * ambient) << theta;
    EXPECT_NEAR(w.boiling_temperature(x), theta, 1e-8) << theta;
    const double d = 1e-4, fd = (w.boiling_moisture(theta + d) - w.boiling_moisture(theta - d)) / (2 * d);
    EXPECT_NEAR(w.boiling_moisture_slope(theta), fd, 1e-6 * std::abs(fd)) << theta;
    EXPECT_LT(w.boiling_moisture_slope(theta), 0.0);
  }
  EXPECT_TRUE(std::isinf(w.boiling_moisture(100.0)));  // free water boils at θ_b
  EXPECT_LT(w.boiling_temperature(0.5) - 100, 0.2);    // moist crumb (a_w 0.994): 0.16 K of elevation
  EXPECT_GT(w.boiling_temperature(0.3) - 100, 0.5);    // a_w 0.97: about 0.8 K
  EXPECT_LT(w.boiling_temperature(0.3) - 100, 1.2);
  // A crust at 160 degC keeps a few per cent (dry basis; the default isotherm: 0.065).
  EXPECT_GT(w.boiling_moisture(160), 0.05);
  EXPECT_LT(w.boiling_moisture(160), 0.08);
  // A temperature-dependent isotherm (a falls with T, the same at 100 degC): the same line equation holds.
  PoreWater t = w;
  t.sorption.oswin_a_slope = -0.004;
  t.sorption.oswin_a_offset = w.sorption.oswin_a_offset + 0.004 * 373.15;
  for (const double theta : {105.0, 150.0}) {
    const double x = t.boiling_moisture(theta);
    EXPECT_NEAR(t.sorption.activity(x, theta) * saturation_vapour_pressure(theta), ambient, 1e-10 * ambient);
    EXPECT_NEAR(t.boiling_temperature(x), theta, 1e-6) << theta;
    const double d = 1e-4, fd = (t.boiling_moisture(theta + d) - t.boiling_moisture(theta - d)) / (2 * d);
    EXPECT_NEAR(t.boiling_moisture_slope(theta), fd, 1e-6 * std::abs(fd)) << theta;
  }
}

TEST(Water, TheBoundWaterCapConservesEnergyAndLeavesTheParticleOnItsLine) {
  PoreWater w;
  w.moisture = 0.5;
  const double c = 2.0, dry = 0.01, h = w.latent_heat;
  for (const double water : {0.005, 0.001, 2e-4}) {  // X = 0.5, 0.1, 0.02
    for (const double heated : {100.05, 101.0, 130.0, 300.0}) {
      const Boiling b = boil_bound(w, c, heated, water, dry);
      EXPECT_NEAR(c * heated, c * b.temperature + h * b.boiled, 1e-9) << water << " " << heated;
      EXPECT_NEAR(b.water + b.boiled, water, 1e-18);
      EXPECT_GE(b.water, 0.0);
      EXPECT_GE(b.boiled, 0.0);
      if (b.boiled > 0) {  // it boiled down to its line: the water left is what the line binds there
        // (to 1e-6 K along the line: Newton's last step is taken on the tangent)
        EXPECT_NEAR(b.water, dry * w.boiling_moisture(b.temperature), 1e-6 * water) << water << " " << heated;
        EXPECT_GT(b.water, 0.0);  // bound water stays
      } else {                    // all of it bound at this temperature
        EXPECT_LE(water, dry * w.boiling_moisture(heated));
        EXPECT_EQ(b.temperature, heated);
      }
    }
  }
  // Moist dough a little past its line boils off the excess, as free water would (to 1%).
  const double line = w.boiling_temperature(0.5);
  const Boiling plateau = boil_bound(w, c, line + 0.01, 0.005, dry);
  EXPECT_NEAR(plateau.boiled, c * 0.01 / h, 0.01 * c * 0.01 / h);
  EXPECT_NEAR(plateau.temperature, line, 1e-3);
  // A crust at 150 degC with X = 0.03 (its line binds 0.07): nothing boils; dry dough: untouched.
  EXPECT_EQ(boil_bound(w, c, 150, 3e-4, dry).boiled, 0.0);
  EXPECT_EQ(boil_bound(w, c, 150, 0, dry).temperature, 150.0);
  EXPECT_EQ(boil_bound(w, c, 99, 0.005, dry).boiled, 0.0);
}

TEST(Water, ChiltonColburnGivesTheSpecsMassTransferCoefficient) {
  // shared/spec: rho_air c_p,air ~ 760 J/(m^3 K) at 190 degC and Le 0.85, so h = 10 gives h_m ~ 0.015 m/s.
  EXPECT_NEAR(mass_transfer_coefficient(10, 190), 0.015, 0.05 * 0.015);
  EXPECT_NEAR(mass_transfer_coefficient(20, 190), 2 * mass_transfer_coefficient(10, 190), 1e-15);
  EXPECT_GT(mass_transfer_coefficient(10, 250), mass_transfer_coefficient(10, 150));  // thinner air
}

TEST(Water, TheStepBoundsDiffusivityGrowsTowardsTheBoilingPoint) {
  PoreWater w;
  w.moisture = 0.54;
  const double rc = 677e3, dry = 196;
  const double d40 = w.effective_diffusivity(40, 0.54, rc, dry), d95 = w.effective_diffusivity(95, 0.54, rc, dry);
  EXPECT_GT(d95, 5 * d40);
  // The heat-pipe conductivity h_fg phi_g D drho/dT at 95 degC: of order 0.5 W/(m K) (shared/spec: crumb heats ~3x faster).
  const double k_vapour = d95 * rc;
  EXPECT_GT(k_vapour, 0.2);
  EXPECT_LT(k_vapour, 3.0);
}

// Found by the SPH apple-skin preset (no pores): a 1% density fluctuation made its step 10⁴ times too small.
TEST(Water, TheStepBoundIsThatOfTheExpandedParticleEvenWithoutPores) {
  PoreWater w;
  w.moisture = 5.9, w.liquid_diffusivity = 2e-9;
  const double rho = 1048, c = 3810, dry = rho / (1 + w.moisture);
  for (const double phi0 : {0.0, 0.1, 0.6}) {
    w.gas_fraction = phi0;
    for (const double j : {1.0, 1.01, 2.0}) {
      // By hand: the law of a particle at J times its volume, with gas fraction 1 − (1 − φ₀)/J.
      PoreWater e = w;
      e.gas_fraction = std::min(std::max(1 - (1 - phi0) / j, phi0), 0.95);
      double expected = 0;
      for (const double x : {1.0, 0.5, 0.2, 0.05})
        expected = std::max(expected, e.effective_diffusivity(95, x * w.moisture, rho * c / j, dry / j));
      EXPECT_NEAR(w.step_diffusivity(95, rho, c, j), expected, 1e-12 * expected) << phi0 << " " << j;
    }
  }
  w.gas_fraction = 0;
  // Without pores a 1% expansion adds 1% gas: the bound stays within a few times the liquid's and the unexpanded one.
  EXPECT_LT(w.step_diffusivity(95, rho, c, 1.01), 10 * w.step_diffusivity(95, rho, c, 1.0) + 1e-7);
}

TEST(Water, CellHeatPipeIsTheVapourConductivityAcrossACellAndStopsWhenDryOrBoiling) {
  PoreWater w;
  w.moisture = 0.54;
  const double phi = 0.6, theta = 90;
  // φ h_fg D(θ) a_w dρ_sat/dθ by hand: ideal-gas vapour at the Antoine pressure.
  const double tk = theta + 273.15, p = saturation_vapour_pressure(theta), dp = saturation_vapour_pressure_slope(theta);
  const double drho = 0.018015 / (8.314462618 * tk) * (dp - p / tk);
  const double expected =
      phi * 2.257e6 * 2.6e-5 * std::pow(tk / 298.15, 1.75) * w.sorption.activity(0.54, theta) * drho;
  EXPECT_NEAR(w.cell_conductivity(theta, 0.54, phi), expected, 1e-12 * expected);
  EXPECT_GT(expected, 0.3);  // several times a crumb's 0.2 W/(m K) near 90 degC
  EXPECT_EQ(w.cell_conductivity(100, 0.54, phi), 0.0);
  EXPECT_EQ(w.cell_conductivity(90, 0, phi), 0.0);
  w.cell_heat_pipe = 0;
  EXPECT_EQ(w.cell_conductivity(theta, 0.54, phi), 0.0);
}

// The MPM constitutive phase takes both from one call: the same numbers to the
// bit as the two laws, below, at and above the boiling point, dry or not.
TEST(Water, PoreVapourIsTheVapourDensityAndTheCellHeatPipeTogether) {
  PoreWater w;
  w.moisture = 0.54;
  w.sorption.oswin_a_slope = -0.002;  // a temperature-dependent isotherm
  w.sorption.oswin_a_offset = 3.0;
  for (const double pipe : {1.0, 0.0}) {
    w.cell_heat_pipe = pipe;
    for (const double theta : {-10.0, 25.0, 90.0, 99.99, 100.0, 130.0})
      for (const double x : {0.0, 0.05, 0.3, 0.54})
        for (const double phi : {0.2, 0.6}) {
          const PoreWater::PoreVapour both = w.pore_vapour(theta, x, phi);
          EXPECT_EQ(both.density, w.vapour_density(theta, x)) << theta << " degC, X " << x;
          EXPECT_EQ(both.cell_conductivity, w.cell_conductivity(theta, x, phi)) << theta << " degC, X " << x;
        }
  }
}

TEST(Water, DriedDoughConductsLikeTheCrustAndGasGrowsWithExpansion) {
  PoreWater w;
  w.moisture = 0.8;
  EXPECT_EQ(w.drying_conductivity_change(0.4, 0.4), 0.0);  // no dry value given: k stays
  w.dry_conductivity = 0.1;
  EXPECT_NEAR(w.drying_conductivity_change(0.4, 0.8), 0.0, 1e-15);
  EXPECT_NEAR(w.drying_conductivity_change(0.4, 0.4), -0.15, 1e-15);
  EXPECT_NEAR(w.drying_conductivity_change(0.4, 0.0), -0.3, 1e-15);
  w.gas_fraction = 0.1;
  EXPECT_NEAR(w.expanded_gas_fraction(1.0), 0.1, 1e-15);
  EXPECT_NEAR(w.expanded_gas_fraction(3.0), 0.7, 1e-15);  // the doubled volume is gas
  EXPECT_NEAR(w.expanded_gas_fraction(100.0), 0.95, 1e-15);
}

TEST(Water, CondensingVapourGivesItsLatentHeatBeforeTheBoilingCap) {
  PoreWater w;
  w.moisture = 0.5;
  EXPECT_NEAR(w.initial_water(3.0), 1.0, 1e-15);  // 3 kg of dough at X0 = 0.5: 2 kg solid, 1 kg water
  EXPECT_NEAR(w.moisture_of(1.0, 3.0), 0.5, 1e-15);
  const double c = 2.0, mass = 0.03;  // 20 g of solid and 10 g of water (X = 0.5)
  // 1 g condenses at 99 degC: it would heat the particle far past 100, so most of it boils off again,
  // leaving it on its boiling line (X near 0.5: within 0.3 K of 100 degC).
  const PhaseChange p = condense_and_boil(w, c, 99, 0.01, 1e-3, mass);
  EXPECT_GT(p.temperature, 100.0);
  EXPECT_LT(p.temperature, 100.3);
  EXPECT_NEAR(p.temperature, w.boiling_temperature(w.moisture_of(p.water, mass)), 1e-6);
  EXPECT_NEAR(c * 99 - p.latent, c * p.temperature, 1e-9);  // energy: what the water took is the latent term
  EXPECT_NEAR(p.boiled, (w.latent_heat * 1e-3 - c * (p.temperature - 99)) / w.latent_heat, 1e-15);
  // Evaporating 1 mg cools it by h_fg 1e-6 / C; nothing boils below 100.
  const PhaseChange q = condense_and_boil(w, c, 60, 0.01, -1e-6, mass);
  EXPECT_NEAR(q.temperature, 60 - w.latent_heat * 1e-6 / c, 1e-12);
  EXPECT_EQ(q.boiled, 0.0);
  EXPECT_NEAR(q.latent, w.latent_heat * 1e-6, 1e-12);
}

// The crust face (physics/heat.hpp): a wet face stays at the boiling point, a
// dried layer over a pinned front passes the face's heat by conduction, the
// face is continuous when the last water goes, and a dry particle's exchange
// is the series of the air's and its half-layer's resistances.
TEST(Water, CrustFaceBalancesTheAirsHeatAgainstTheCrustOverTheBoilingFront) {
  const Real air = 220, h = 25, L = 1.6e-3, kc = 0.11, km = 0.9;
  CrustFace face;
  face.face_distance = L;
  face.crust_conductivity = kc;
  face.moist_conductivity = km;
  face.moist = true;
  face.dried_fraction = 0;
  EXPECT_DOUBLE_EQ(face.temperature(100, air, h), 100);  // evaporating face
  // A quarter of the water gone: crust to half the half-layer, front pinned at 100 °C.
  face.dried_fraction = 0.25;
  const Real crust = 0.5 * L, tf = face.temperature(100, air, h);
  EXPECT_NEAR(h * (air - tf), kc * (tf - 100) / crust, 1e-9 * h * air);
  EXPECT_GT(tf, 100);
  // Below the boiling point with nothing pinned, the two layers in series.
  const Real cold = face.temperature(40, air, h), r = crust / kc + (L - crust) / km;
  EXPECT_NEAR(h * (air - cold), (cold - 40) / r, 1e-9 * h * air);
  // The last water goes: the moist face at f → 1 is the dry particle's face at the same temperature.
  face.dried_fraction = 1;
  const Real last = face.temperature(100, air, h);
  CrustFace dry = face;
  dry.moist = false;
  EXPECT_NEAR(dry.temperature(100, air, h), last, 1e-9);
  // The drier, the hotter the face.
  Real previous = 0;
  for (Real f : {0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 1.0}) {
    face.dried_fraction = f;
    EXPECT_GE(face.temperature(100, air, h), previous) << f;
    previous = face.temperature(100, air, h);
  }
  // A dry particle takes h (θ_out − θ_f) = (θ_out − θ) / (1/h + L/k_c).
  EXPECT_NEAR(dry.coefficient_to_centre(150, air, h), 1 / (1 / h + L / kc), 1e-9);
  // k_m = ∞ (MPM): with no crust the point stands for its face.
  CrustFace nodal = face;
  nodal.moist_conductivity = std::numeric_limits<Real>::infinity();
  nodal.dried_fraction = 0;
  EXPECT_DOUBLE_EQ(nodal.temperature(70, air, h), 70);
}

namespace {
// The Zhang loaf's dough (scenes/zhang-loaf-*.json): X0 0.537 at 301 kg/m^3, so 195.8 kg/m^3 of dry solid.
PoreWater supply_limited_dough(Real liquid_diffusivity) {
  PoreWater w;
  w.moisture = 0.537, w.gas_fraction = 0.615, w.liquid_diffusivity = liquid_diffusivity;
  w.surface_evaporation = PoreWater::SurfaceEvaporation::supply_limited;
  return w;
}
}  // namespace

TEST(Water, AFreeSurfaceLosesItsMeanVapourAndASupplyLimitedOneDoesSoOnlyWhileWet) {
  PoreWater free = supply_limited_dough(1e-9);
  free.surface_evaporation = PoreWater::SurfaceEvaporation::free;
  const Real h_m = 0.0145, theta = 60, dry = 1e-3, volume = dry / 195.8, area = volume / 2e-3;
  const Real mean = free.vapour_density(theta, 0.537);
  EXPECT_EQ(free.surface_flux(mean, theta, 0.537, dry, volume, area, h_m, 0.01), h_m * (mean - 0.01));
  // A face that has lost nothing (the law's floor: a nanometre's worth) is wet: the free rate within 0.1%.
  const PoreWater limited = supply_limited_dough(1e-9);
  EXPECT_NEAR(limited.surface_flux(mean, theta, 0.537, dry, volume, area, h_m, 0), h_m * mean, 1e-3 * h_m * mean);
  // Humid air condenses on it as on the free surface (the supply limits what leaves, not what arrives).
  const Real humid = 2 * mean;
  EXPECT_EQ(limited.surface_flux(mean, theta, 0.537, dry, volume, area, h_m, humid), h_m * (mean - humid));
  // Without liquid diffusion nothing reaches a face that has dried.
  EXPECT_EQ(supply_limited_dough(0).surface_flux(mean, theta, 0.5, dry, volume, area, h_m, 0), 0);
}

// A layer thick enough that the depletion stays inside it, its face swept by air that pulls far harder than
// the liquid can follow: its loss per area must follow Fick's semi-infinite desorption with the face at its
// (small) moisture X_s, M(t) = 2 rho_d (X0 - X_s) sqrt(D t / pi) (Crank 1975, The Mathematics of Diffusion,
// Eq 3.14 integrated over time), integrated here step by step from the flux alone.
TEST(Water, ASupplyLimitedFaceLosesWaterAsFicksErfcProfileOfASemiInfiniteLayer) {
  const Real diffusivity = 1e-9, theta = 80, h_m = 1.0;  // D_w(80 degC) = 0.8e-9
  const PoreWater w = supply_limited_dough(diffusivity);
  // 10 cm deep: the layer (sqrt(pi D t) = 1.2 mm after 10 minutes) stays far inside it.
  const Real area = 1, depth = 0.1, volume = area * depth, dry = 195.8 * volume;
  const Real rho_dry = dry / volume, d = w.liquid_diffusion(theta), end = 600;
  // Small steps with the instantaneous rate, and steps of 30 s with the rate taken over the step.
  for (const auto& [dt, over_the_step] : {std::pair{0.01, false}, std::pair{30.0, true}}) {
    Real water = w.initial_water(dry * (1 + w.moisture)), lost_per_area = 0, face_moisture_sum = 0;
    int steps = 0;
    for (Real t = 0; t < end - 0.5 * dt; t += dt, ++steps) {
      const Real x = water / dry;
      const Real flux =
          w.surface_flux(w.vapour_density(theta, x), theta, x, dry, volume, area, h_m, 0, over_the_step ? dt : 0);
      water -= flux * area * dt;
      lost_per_area += flux * dt;
      // The face moisture the flux stands for: the isotherm's X at a_w = flux / (h_m rho_sat).
      face_moisture_sum += w.sorption.moisture_at(flux / (h_m * w.vapour_density(theta, 1e3)), theta);
    }
    const Real face = face_moisture_sum / steps;
    EXPECT_LT(face, 0.05 * w.moisture);  // the air keeps the face nearly dry
    const Real erfc_loss = 2 * rho_dry * (w.moisture - face) * std::sqrt(d * end / kPi);
    std::printf("steps of %g s: loss per area after %g s %.5g kg/m^2, erfc solution %.5g (face X %.4f)\n", dt, end,
                lost_per_area, erfc_loss, face);
    EXPECT_NEAR(lost_per_area / erfc_loss, 1.0, 0.01) << "steps of " << dt << " s";
  }
}

// moisture.expanded_conductivity: parallel. Risen dough conducts through less
// solid. Against the bread crumb of Zanoni, Peri & Gianotti (1995, J Food Eng
// 26:497), whose measured diffusivity and density follow the porosity ε (%)
// as α = exp(0.01 ε − 15.25) m²/s and ρ = 979 − 9.90 ε kg/m³: between the
// Zhang dough's 61.5% and the 76% it has once risen 1.6 times, k = α ρ c falls
// to 0.708 of its value (c the same); the parallel model gives 0.674.
TEST(Water, RisenDoughConductsThroughLessSolidAsMeasuredOnBreadCrumb) {
  PoreWater w;
  w.moisture = 0.537;
  w.gas_fraction = 0.615;
  const double k0 = 0.196, j = 1.6;
  const double phi = w.expanded_gas_fraction(j);
  EXPECT_NEAR(phi, 0.759375, 1e-12);
  EXPECT_EQ(w.matrix_conductivity_change(k0, 0.537, phi), 0.0);  // constant: the seeds' k whatever the volume
  w.expanded_conductivity = PoreWater::ExpandedConductivity::parallel;
  EXPECT_NEAR(w.matrix_conductivity_change(k0, 0.537, 0.615), 0.0, 1e-15);  // unexpanded: the material's k
  EXPECT_NEAR(w.matrix_conductivity_change(k0, 0.537, 0.5), 0.0, 1e-15);    // compressed: not raised
  const auto measured_k = [](double porosity_percent) {
    return std::exp(0.01 * porosity_percent - 15.25) * (979 - 9.90 * porosity_percent);
  };
  const double measured = measured_k(100 * phi) / measured_k(61.5);
  const double parallel = (k0 + w.matrix_conductivity_change(k0, 0.537, phi)) / k0;
  EXPECT_NEAR(measured, 0.708, 0.002);
  EXPECT_NEAR(parallel, measured, 0.05);
  // Analytic: (k0 − k_g φ0)(1 − φ)/(1 − φ0) + k_g φ.
  const double kg = PoreWater::kGasConductivity;
  EXPECT_NEAR(k0 * parallel, (k0 - kg * 0.615) * (1 - phi) / (1 - 0.615) + kg * phi, 1e-15);
  // A dried crust expands from its dry conductivity: drying first, then the solid share.
  w.dry_conductivity = 0.1;
  const double dried = k0 + w.matrix_conductivity_change(k0, 0.0, phi);
  EXPECT_NEAR(dried, (0.1 - kg * 0.615) * (1 - phi) / (1 - 0.615) + kg * phi, 1e-15);
}

// moisture.pore_opening_temperature: the closed-cell heat pipe stops as the
// crumb's cells open. The share still closed is 1/2 − atan((θ − θ_open)/w)/π:
// a half at θ_open, 3/4 and 1/4 one width either side (atan 1 = π/4), and the
// heat pipe scales with it; without an opening temperature nothing changes.
TEST(Water, TheClosedCellHeatPipeStopsAsTheCrumbsCellsOpen) {
  PoreWater w;
  w.moisture = 0.5;
  w.gas_fraction = 0.6;
  const double closed = w.cell_conductivity(90.0, 0.5, 0.6);
  EXPECT_GT(closed, 0.3);
  EXPECT_EQ(w.closed_cell_share(90.0), 1.0);
  w.pore_opening_temperature = 75.0;
  w.pore_opening_width = 10.0;
  EXPECT_NEAR(w.closed_cell_share(75.0), 0.5, 1e-15);
  EXPECT_NEAR(w.closed_cell_share(65.0), 0.75, 1e-15);
  EXPECT_NEAR(w.closed_cell_share(85.0), 0.25, 1e-15);
  EXPECT_GT(w.closed_cell_share(20.0), 0.94);  // 1/2 + atan(5.5)/π = 0.943
  EXPECT_NEAR(w.cell_conductivity(90.0, 0.5, 0.6), closed * w.closed_cell_share(90.0), 1e-12 * closed);
  EXPECT_NEAR(w.pore_vapour(90.0, 0.5, 0.6).cell_conductivity, w.cell_conductivity(90.0, 0.5, 0.6), 1e-15);
  w.pore_opening_width = 1.25;  // the sharper opening
  EXPECT_LT(w.closed_cell_share(85.0), 0.04);
}
