// The surface's water law alone (physics/water.hpp, PoreWater::surface_flux): the
// time of one call for a supply-limited face, over faces from wet to dry and from
// 30 to 100 degC (the Zhang loaf's dough), against the free law's one line.
// Run: ./build/bench/bakesim_microbench --benchmark_filter=SurfaceFlux
#include <benchmark/benchmark.h>

#include <vector>

#include "physics/water.hpp"

using namespace bakesim;

namespace {

struct Face {
  Real vapour, celsius, moisture;
};

void surface_flux(benchmark::State& state, PoreWater::SurfaceEvaporation law) {
  PoreWater w;
  w.moisture = 0.537, w.gas_fraction = 0.615, w.liquid_diffusivity = 5e-10, w.surface_evaporation = law;
  // A 2 mm particle of the Zhang dough (301 kg/m^3) facing the air with one face.
  const Real volume = 8e-9, dry = 301 * volume / (1 + w.moisture), area = 4e-6;
  std::vector<Face> faces;
  for (Real theta = 30; theta < 100; theta += 2.5)
    for (Real x = 0.02; x <= 0.537; x += 0.02) faces.push_back({w.vapour_density(theta, x), theta, x});
  for (auto _ : state) {
    Real sum = 0;
    for (const Face& f : faces)
      sum += w.surface_flux(f.vapour, f.celsius, f.moisture, dry, volume, area, 0.0145, 0, 0.5);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(faces.size()));
}

void BM_SurfaceFluxSupplyLimited(benchmark::State& state) {
  surface_flux(state, PoreWater::SurfaceEvaporation::supply_limited);
}
void BM_SurfaceFluxFree(benchmark::State& state) { surface_flux(state, PoreWater::SurfaceEvaporation::free); }

}  // namespace

BENCHMARK(BM_SurfaceFluxSupplyLimited);
BENCHMARK(BM_SurfaceFluxFree);
