// Surface reconstruction and picture speed (issue 6 targets: a 200K-particle
// frame meshed in under 5 s and a 1280×720 picture in under 10 s on 2 cores).
// The particles fill a loaf-shaped box on a lattice, slightly jittered, as a
// risen dough frame looks.
#include <benchmark/benchmark.h>

#include <cmath>

#include "render/render.hpp"
#include "surface/surface.hpp"

using namespace bakesim;

namespace {

surface::SurfaceParticles loaf(long target) {
  surface::SurfaceParticles p;
  // A 2:1:1 box with `target` particles at spacing s.
  const double s = 0.002;
  const long nz = std::lround(std::cbrt(double(target) / 4.0)), ny = nz, nx = 4 * nz;
  std::uint32_t seed = 12345;
  auto jitter = [&] {
    seed = seed * 1664525u + 1013904223u;
    return (double(seed >> 8) / 16777216.0 - 0.5) * 0.2 * s;
  };
  for (long i = 0; i < nx; ++i)
    for (long j = 0; j < ny; ++j)
      for (long k = 0; k < nz; ++k) {
        p.position.push_back(Vec3((i + 0.5) * s + jitter(), (j + 0.5) * s + jitter(), (k + 0.5) * s + jitter()));
        p.density_ratio.push_back(1.3);
      }
  p.spacing = s;
  return p;
}

void BM_MeshFrame(benchmark::State& state) {
  const auto p = loaf(state.range(0));
  surface::SurfaceOptions o;
  o.method = state.range(1) == 0 ? surface::SurfaceMethod::levelset : surface::SurfaceMethod::wyvill;
  std::size_t triangles = 0;
  for (auto _ : state) triangles = surface::reconstruct_surface(p, o).triangles.size();
  state.counters["particles"] = double(p.position.size());
  state.counters["triangles"] = double(triangles);
  state.SetLabel(surface::to_string(o.method));
}
BENCHMARK(BM_MeshFrame)->Args({200000, 0})->Args({200000, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RenderMesh1280x720(benchmark::State& state) {
  const auto p = loaf(200000);
  surface::SurfaceMesh mesh = surface::reconstruct_surface(p, {});
  mesh.colours.assign(mesh.vertices.size(), {200, 150, 90});
  render::RenderSettings settings;  // 1280×720, 4 samples per pixel
  const render::TextRenderer text;
  for (auto _ : state) benchmark::DoNotOptimize(render::render_mesh(mesh, settings, text).rgb.data());
  state.counters["triangles"] = double(mesh.triangles.size());
}
BENCHMARK(BM_RenderMesh1280x720)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RenderParticles1280x720(benchmark::State& state) {
  const auto p = loaf(200000);
  render::ParticleView pv;
  pv.position = p.position;
  pv.colour.assign(p.position.size(), {200, 150, 90});
  pv.radius = 0.5 * p.spacing;
  render::RenderSettings settings;
  const render::TextRenderer text;
  for (auto _ : state) benchmark::DoNotOptimize(render::render_particles(pv, settings, text).rgb.data());
  state.counters["particles"] = double(pv.position.size());
}
BENCHMARK(BM_RenderParticles1280x720)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
