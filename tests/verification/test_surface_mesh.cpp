// Surface reconstruction (src/surface): a particle sphere meshes to a closed,
// consistently oriented surface whose volume is within 5% of the sphere's,
// and a slowly moving or expanding body gives consecutive meshes within one
// particle spacing of each other (the thesis's temporal-coherence complaint
// about Poisson and RIMLS reconstructions, 3.5).
#include <gtest/gtest.h>

#include <cmath>

#include "helpers.hpp"
#include "surface/surface.hpp"

using namespace bakesim;
using namespace bakesim::surface;

namespace {

SurfaceParticles ball(Real radius, Real s, Vec3 centre, Real density_ratio = 1.0) {
  return test_support::lattice_ball(radius, s, centre, density_ratio);
}

void expect_closed_sphere(SurfaceMethod method) {
  const Real s = 0.004, radius = 0.04;
  const SurfaceParticles p = ball(radius, s, Vec3(0.1, 0.2, -0.05));
  SurfaceOptions o;
  o.method = method;
  const SurfaceMesh mesh = reconstruct_surface(p, o);
  ASSERT_GT(mesh.triangles.size(), 1000u);
  const MeshQuality q = check_mesh(mesh);
  EXPECT_EQ(q.boundary_edges, 0u);
  EXPECT_EQ(q.non_manifold_edges, 0u);
  EXPECT_EQ(q.misoriented_edges, 0u);
  const Real sphere = 4.0 / 3.0 * kPi * radius * radius * radius;
  EXPECT_NEAR(q.volume / sphere, 1.0, 0.05) << to_string(method) << ": mesh " << q.volume << " m³, sphere " << sphere;
  // Outward normals: every vertex normal points away from the centre.
  std::size_t inward = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (mesh.normals[v].dot(mesh.vertices[v] - Eigen::Vector3f(0.1f, 0.2f, -0.05f)) < 0) ++inward;
  EXPECT_EQ(inward, 0u);
}

}  // namespace

TEST(SurfaceMesh, LevelSetSphereIsClosedOrientedAndHasTheSphereVolume) {
  expect_closed_sphere(SurfaceMethod::levelset);
}
TEST(SurfaceMesh, WyvillSphereIsClosedOrientedAndHasTheSphereVolume) { expect_closed_sphere(SurfaceMethod::wyvill); }

TEST(SurfaceMesh, WyvillInteriorValueMatchesALatticeSum) {
  // Deep inside a lattice the field sum approaches the integral.
  const Real b = 2.0;  // in spacings
  Real sum = 0;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k) sum += wyvill_field((Vec3(i, j, k) + Vec3(0.3, 0.1, 0.2)).norm(), b);
  EXPECT_NEAR(sum / wyvill_interior_value(b), 1.0, 0.02);
}

TEST(SurfaceMesh, ConsecutiveFramesOfAMovingRisingBodyStayWithinOneSpacing) {
  const Real s = 0.004, radius = 0.03;
  for (SurfaceMethod method : {SurfaceMethod::levelset, SurfaceMethod::wyvill}) {
    SurfaceOptions o;
    o.method = method;
    SurfaceMesh previous;
    for (int frame = 0; frame < 5; ++frame) {
      // Drifts 0.2 s and expands 2% in volume per frame.
      const SurfaceParticles p = ball(radius, s, Vec3(0.2 * s * frame, 0, 0), 1.0 + 0.02 * frame);
      SurfaceMesh mesh = reconstruct_surface(p, o);
      if (frame > 0) {
        const Real d = hausdorff_distance(previous, mesh);
        EXPECT_LT(d, s) << to_string(method) << " frame " << frame << ": Hausdorff " << d;
      }
      previous = std::move(mesh);
    }
  }
}

TEST(SurfaceMesh, ColouringFollowsTheParticlesAndTellsBubblesFromDough) {
  const Real s = 0.004;
  const SurfaceParticles p = ball(0.03, s, Vec3::Zero());
  SurfaceMesh mesh = reconstruct_surface(p, SurfaceOptions{});
  ColourSamples samples;
  samples.position = p.position;
  samples.volume.assign(p.position.size(), s * s * s);
  // Hot (value 1) on the +x side, cold (0) on the −x side; −y half are bubbles.
  for (const Vec3& x : p.position) {
    samples.value.push_back(x.x() > 0 ? 1.0 : 0.0);
    samples.bubble.push_back(x.y() < 0 ? 1 : 0);
  }
  assign_uv(mesh, samples, 2 * s);
  colour_vertices(mesh, Palette::baking);
  Real hot_dough = 0, cold_dough = 0, hot_bubble = 0;
  int nh = 0, nc = 0, nb = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const auto& x = mesh.vertices[v];
    if (x.x() > 0.01 && x.y() > 0.01) hot_dough += mesh.uv[v], ++nh;
    if (x.x() < -0.01 && x.y() > 0.01) cold_dough += mesh.uv[v], ++nc;
    if (x.x() > 0.01 && x.y() < -0.01) hot_bubble += mesh.uv[v], ++nb;
  }
  ASSERT_GT(nh * nc * nb, 0);
  // Eq 4.7: dough G = 0.1 + 0.8 v + 0.05, bubble G = 0.8 v + 0.05.
  EXPECT_NEAR(hot_dough / nh, 0.95, 0.02);
  EXPECT_NEAR(cold_dough / nc, 0.15, 0.02);
  EXPECT_NEAR(hot_bubble / nb, 0.85, 0.02);
  // Browner = darker in the baking palette (the colours colour_vertices gives these U).
  const auto pale = palette_colour(Palette::baking, value_of_colour_coordinate(cold_dough / nc)),
             brown = palette_colour(Palette::baking, value_of_colour_coordinate(hot_dough / nh));
  EXPECT_GT(int(pale[0]) + pale[1] + pale[2], int(brown[0]) + brown[1] + brown[2] + 200);
}

// Two foods side by side, one with its own raw colour (chocolate, L* 17.4): each vertex takes the raw
// colour of the particles under it (ColourSamples::raw, from the materials' raw_colour), so the chocolate
// half is drawn dark and the dough half in the dough's palette, both unbrowned here.
TEST(SurfaceMesh, EachFoodIsDrawnFromItsOwnRawColour) {
  const Real s = 0.004;
  const SurfaceParticles p = ball(0.03, s, Vec3::Zero());
  SurfaceMesh mesh = reconstruct_surface(p, SurfaceOptions{});
  const Lab chocolate{17.4, 2.6, 1.4};
  ColourSamples samples;
  samples.position = p.position;
  samples.volume.assign(p.position.size(), s * s * s);
  for (const Vec3& x : p.position) {
    samples.value.push_back(0.0);
    samples.raw.push_back(x.x() < 0 ? chocolate : dough_lab());
  }
  assign_uv(mesh, samples, 2 * s);
  colour_vertices(mesh, Palette::baking);
  ASSERT_EQ(mesh.raw_colour.size(), mesh.vertices.size());
  const auto dark = baking_colour(chocolate, 0), pale = palette_colour(Palette::baking, 0);
  int nd = 0, np = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Real x = mesh.vertices[v].x();
    if (std::abs(x) < 3 * s) continue;  // where the two meet, the colours blend over the support
    const auto want = x < 0 ? dark : pale;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mesh.colours[v][k], want[k], 1) << x;
    ++(x < 0 ? nd : np);
  }
  EXPECT_GT(nd, 100);
  EXPECT_GT(np, 100);
  // Without raw colours every vertex is the dough's.
  samples.raw.clear();
  assign_uv(mesh, samples, 2 * s);
  colour_vertices(mesh, Palette::baking);
  EXPECT_TRUE(mesh.raw_colour.empty());
  for (const auto& c : mesh.colours)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], pale[k], 1);
}

// The crust is what one sees: a ball whose outer particle layer is browned
// (value 1, flagged as the surface) over a pale interior (0). Without the
// flags every vertex mixes the crust with the crumb under it within the
// support; with them (ColourSamples::face, what `bakesim mesh` and `render`
// set for browning from the SPH surface particles) it shows the crust's colour.
TEST(SurfaceMesh, BrowningShowsTheCrustParticlesNotTheCrumbUnderThem) {
  const Real s = 0.004;
  const SurfaceParticles p = ball(0.03, s, Vec3::Zero());
  SurfaceMesh mesh = reconstruct_surface(p, SurfaceOptions{});
  Real rmax = 0;
  for (const Vec3& x : p.position) rmax = std::max(rmax, x.norm());
  ColourSamples samples;
  samples.position = p.position;
  samples.volume.assign(p.position.size(), s * s * s);
  for (const Vec3& x : p.position) {
    const bool crust = x.norm() > rmax - 0.9 * s;
    samples.value.push_back(crust ? 1.0 : 0.0);
    samples.face.push_back(crust ? 1 : 0);
  }
  auto mean_uv = [&](const ColourSamples& c) {
    assign_uv(mesh, c, 2 * s);
    Real sum = 0;
    for (float u : mesh.uv) sum += u;
    return sum / Real(mesh.uv.size());
  };
  const Real with_flags = mean_uv(samples);
  samples.face.clear();
  const Real mixed = mean_uv(samples);
  std::printf("mean vertex U: %.3f with the surface particles alone, %.3f mixed with the crumb\n", with_flags, mixed);
  EXPECT_NEAR(with_flags, 0.95, 0.01);  // Eq 4.7: 0.1 + 0.8 · 1 + 0.05
  EXPECT_LT(mixed, 0.93);               // measured 0.897: a fifth of the crust colour lost
}

// Issue 23: no lattice banding on flat faces. A box of lattice particles (20 ×
// 12 × 16 spacings) meshed by the levelset method: on its front face, away from
// the edges, the vertex normals' RMS angle from the face normal measures the
// bumps each particle row leaves. Measured 6.4° without smoothing and 0.87°
// with the default four mean-curvature steps (the face's mean position moves
// by under 0.01 s); position noise 0.079 s → 0.011 s.
TEST(SurfaceMesh, AFlatFaceOfALatticeBoxIsFlatWithinTwoDegrees) {
  const Real s = 0.004;
  surface::SurfaceParticles p;
  p.spacing = s;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = 0; k < 16; ++k)
        p.position.push_back(Vec3((i + 0.5) * s, (j + 0.5) * s, (k + 0.5) * s)), p.density_ratio.push_back(1);
  auto face_noise = [&](int iterations) {
    surface::SurfaceOptions o;
    o.smoothing_iterations = iterations;
    const surface::SurfaceMesh m = surface::reconstruct_surface(p, o);
    double angle2 = 0, z = 0;
    int n = 0;
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
      const auto& x = m.vertices[v];
      if (x.z() < 14 * s || x.x() < 3 * s || x.x() > 17 * s || x.y() < 3 * s || x.y() > 9 * s) continue;
      angle2 += std::pow(std::acos(std::min(1.0f, std::abs(m.normals[v].z()))) * 180 / kPi, 2);
      z += x.z(), ++n;
    }
    EXPECT_GT(n, 100);
    return std::make_pair(std::sqrt(angle2 / n), z / n / s);
  };
  const auto [raw, raw_face] = face_noise(0);
  const auto [smooth, smooth_face] = face_noise(surface::SurfaceOptions{}.smoothing_iterations);
  RecordProperty("normal_rms_deg", std::to_string(smooth));
  EXPECT_GT(raw, 4.0);  // the measure sees the banding
  EXPECT_LT(smooth, 2.0);
  EXPECT_NEAR(smooth_face, raw_face, 0.1);
  EXPECT_NEAR(smooth_face, 16.0, 0.3);  // the face where the box ends
}
