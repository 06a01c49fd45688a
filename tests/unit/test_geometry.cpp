// Shapes, sampling, meshes and collider geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/errors.hpp"
#include "geometry/colliders.hpp"
#include "geometry/mesh_io.hpp"
#include "geometry/motion.hpp"
#include "geometry/open_space.hpp"
#include "geometry/shapes.hpp"

using namespace bakesim;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / "bakesim_geometry_tests";
  fs::create_directories(d);
  return d;
}

// Unit cube [0,1]^3 as OBJ with quads (outward faces).
fs::path write_cube_obj() {
  const fs::path p = temp_dir() / "cube.obj";
  std::ofstream f(p);
  f << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
       "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
  return p;
}

}  // namespace

TEST(Shapes, LatticeFillsABoxExactly) {
  const auto pts = sample_lattice(BoxShape{Vec3::Zero(), Vec3(0.1, 0.2, 0.05)}, 0.01);
  EXPECT_EQ(pts.size(), 10u * 20u * 5u);
  EXPECT_NEAR(pts.front().x(), 0.005, 1e-12);
}

TEST(Shapes, LatticeVolumesOfSphereAndCylinder) {
  const double s = 0.002;
  const double vs = volume_estimate(SphereShape{Vec3::Zero(), 0.05}, s);
  EXPECT_NEAR(vs, 4.0 / 3.0 * kPi * std::pow(0.05, 3), 0.02 * vs);
  const double vc = volume_estimate(CylinderShape{Vec3::Zero(), Vec3(1, 1, 0).normalized(), 0.03, 0.1}, s);
  EXPECT_NEAR(vc, kPi * 0.03 * 0.03 * 0.1, 0.03 * vc);
}

TEST(Shapes, UnionAndDifference) {
  auto u = std::make_shared<ShapeUnion>();
  u->parts = {BoxShape{Vec3::Zero(), Vec3::Ones()}, SphereShape{Vec3(2, 0, 0), 0.5}};
  const Shape su = std::shared_ptr<const ShapeUnion>(u);
  EXPECT_TRUE(contains(su, Vec3(0.5, 0.5, 0.5)));
  EXPECT_TRUE(contains(su, Vec3(2.2, 0, 0)));
  auto d = std::make_shared<ShapeDifference>();
  d->base = BoxShape{Vec3::Zero(), Vec3::Ones()};
  d->subtract = {SphereShape{Vec3(0.5, 0.5, 0.5), 0.25}};
  const Shape sd = std::shared_ptr<const ShapeDifference>(d);
  EXPECT_FALSE(contains(sd, Vec3(0.5, 0.5, 0.5)));
  EXPECT_TRUE(contains(sd, Vec3(0.1, 0.1, 0.1)));
}

// The lattice holds whole spacings: the tin loaf of scenes/tin-loaf-sph.json
// (radius 57.8 mm, height 47.5 mm) at 3 mm gets 15 layers, 45 mm of its
// height, and with its narrower circle 94.2% of its volume (the figures below
// from the lattice's count against πr²h = 4.985e-4 m³); at 47.5/16 mm, 16
// layers fill it. Exact volumes for the primitives, a finer lattice for a union.
TEST(Shapes, SamplingFillSaysWhatTheLatticeHoldsOfItsShape) {
  EXPECT_NEAR(shape_volume(BoxShape{Vec3::Zero(), Vec3(0.1, 0.2, 0.05)}, 0.01), 1e-3, 1e-18);
  EXPECT_NEAR(shape_volume(SphereShape{Vec3::Zero(), 0.05}, 0.01), 4.0 / 3.0 * kPi * 1.25e-4, 1e-18);
  const CylinderShape tin{Vec3(0, 0.02375, 0), Vec3(0, 1, 0), 0.0578, 0.0475};
  EXPECT_NEAR(shape_volume(tin, 0.003), kPi * 0.0578 * 0.0578 * 0.0475, 1e-18);
  const std::vector<Vec3> coarse = sample_lattice(tin, 0.003);
  const SamplingFill f = sampling_fill(tin, coarse, 0.003);
  EXPECT_EQ(coarse.size(), 17400u);
  EXPECT_NEAR(f.fraction, 17400 * 27e-9 / (kPi * 0.0578 * 0.0578 * 0.0475), 1e-12);
  EXPECT_NEAR(f.fraction, 0.942, 0.001);
  EXPECT_NEAR(f.sampled_extent.y(), 0.045, 1e-12);  // 15 layers
  EXPECT_NEAR(f.shape_extent.y(), 0.0475, 1e-12);
  const std::string w =
      sampling_warning("bodies[0]", "loaf", "particles", coarse.size(), 0.003, f, tin, {"solver.sph.spacing", 1});
  EXPECT_NE(w.find("bodies[0]: body 'loaf' is sampled as 94.2% of its volume"), std::string::npos) << w;
  // The nearest spacing that fills it: 16 layers of its height (47.5/16 mm), not 15 of 47.5/15.
  EXPECT_NEAR(fitting_spacing(tin, 0.003).spacing, 0.0475 / 16, 1e-12);
  EXPECT_NEAR(fitting_spacing(tin, 0.003).fraction, 0.994, 0.0005);
  EXPECT_NE(w.find("; solver.sph.spacing 0.00296875 would fill 99.4%"), std::string::npos) << w;
  const std::string w_mpm = sampling_warning("bodies[0]", "loaf", "material points", coarse.size(), 0.003, f, tin,
                                             {"solver.mpm.cell_size", 2});
  EXPECT_NE(w_mpm.find("; solver.mpm.cell_size 0.0059375 would fill 99.4%"), std::string::npos) << w_mpm;
  EXPECT_NE(w.find("114.0 x 45.0 x 114.0 mm of its 115.6 x 47.5 x 115.6 mm"), std::string::npos) << w;
  const double fitted = 0.0475 / 16;
  const SamplingFill g = sampling_fill(tin, sample_lattice(tin, fitted), fitted);
  EXPECT_NEAR(g.sampled_extent.y(), 0.0475, 1e-12);
  EXPECT_NEAR(g.fraction, 1, kSamplingFillTolerance);
  EXPECT_EQ(sampling_warning("bodies[0]", "loaf", "particles", 1, fitted, g, tin, {"solver.sph.spacing", 1}), "");
  // A union of two overlapping boxes: 1.5 boxes' volume, on the finer lattice.
  auto u = std::make_shared<ShapeUnion>();
  u->parts = {BoxShape{Vec3::Zero(), Vec3::Ones()}, BoxShape{Vec3(0.5, 0, 0), Vec3(1.5, 1, 1)}};
  EXPECT_NEAR(shape_volume(std::shared_ptr<const ShapeUnion>(u), 0.1), 1.5, 1e-9);
}

TEST(Meshes, ObjCubeLoadsAndFillsWithParticles) {
  TriangleMesh m = load_mesh(write_cube_obj().string());
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_NEAR(m.signed_volume(), 1.0, 1e-12);
  m.apply(0.1, Vec3(0, 0, 45), Vec3(1, 2, 3));
  EXPECT_NEAR(m.signed_volume(), 1e-3, 1e-15);
  const MeshShape shape(m);
  // The lattice of a rotated cube still holds its volume.
  const double v = volume_estimate(std::make_shared<const MeshShape>(m), 0.0025);
  EXPECT_NEAR(v, 1e-3, 0.05e-3);
  EXPECT_TRUE(shape.contains(Vec3(1, 2.05, 3.05)));
  EXPECT_FALSE(shape.contains(Vec3(1.2, 2.05, 3.05)));
}

TEST(Meshes, PlyAsciiAndBinaryOfEitherByteOrderAgree) {
  const fs::path a = temp_dir() / "tet_ascii.ply", b = temp_dir() / "tet_binary.ply";
  std::ofstream(a) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  {
    std::ofstream f(b, std::ios::binary);
    f << "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
         "property double z\nelement face 4\nproperty list uchar uint vertex_indices\nend_header\n";
    const double v[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    f.write(reinterpret_cast<const char*>(v), sizeof v);
    const std::uint32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto& t : faces) {
      const unsigned char n = 3;
      f.write(reinterpret_cast<const char*>(&n), 1);
      f.write(reinterpret_cast<const char*>(t), sizeof t);
    }
  }
  // The same tetrahedron big-endian (float coordinates, ushort indices), byte by byte.
  const fs::path c = temp_dir() / "tet_big_endian.ply";
  {
    std::ofstream f(c, std::ios::binary);
    f << "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
         "property float z\nelement face 4\nproperty list uchar ushort vertex_indices\nend_header\n";
    auto put = [&f](const unsigned char* bytes, int n) { f.write(reinterpret_cast<const char*>(bytes), n); };
    const unsigned char zero[4] = {0, 0, 0, 0}, one[4] = {0x3f, 0x80, 0, 0};  // 1.0f big-endian
    const int coords[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int k : coords) put(k ? one : zero, 4);
    const unsigned char faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto& t : faces) {
      const unsigned char n = 3;
      put(&n, 1);
      for (unsigned char i : t) {
        const unsigned char be[2] = {0, i};
        put(be, 2);
      }
    }
  }
  const TriangleMesh ma = load_mesh(a.string()), mb = load_mesh(b.string()), mc = load_mesh(c.string());
  EXPECT_EQ(ma.triangles, mb.triangles);
  EXPECT_EQ(ma.triangles, mc.triangles);
  EXPECT_NEAR(ma.signed_volume(), 1.0 / 6.0, 1e-7);
  EXPECT_NEAR(mb.signed_volume(), 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(mc.signed_volume(), 1.0 / 6.0, 1e-12);
}

TEST(Meshes, BadFilesNameTheirPath) {
  EXPECT_THROW(load_mesh("/no/such/file.obj"), InputError);
  const fs::path bad = temp_dir() / "bad.stl";
  std::ofstream(bad) << "solid x\n";
  try {
    load_mesh(bad.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.stl"), std::string::npos);
  }
  const fs::path idx = temp_dir() / "bad_index.obj";
  std::ofstream(idx) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
  EXPECT_THROW(load_mesh(idx.string()), InputError);
}

TEST(RayTriangle, HitsAndMisses) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const auto hit = intersect_ray_triangle(Vec3(0.2, 0.2, 1), Vec3(0, 0, -1), a, b, c);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(*hit, 1.0, 1e-12);
  EXPECT_FALSE(intersect_ray_triangle(Vec3(0.8, 0.8, 1), Vec3(0, 0, -1), a, b, c));
  EXPECT_FALSE(intersect_ray_triangle(Vec3(0.2, 0.2, 1), Vec3(0, 0, 1), a, b, c));
}

TEST(Colliders, ContainerWallsFaceInwardAndTheTopIsOpen) {
  const ContainerCollider cont{{Vec3(0, 0, 0), Vec3(1, 0.5, 1)}, 0.05};
  int walls = 0;
  for_each_wall(ColliderGeometry(cont), Vec3(0.5, 0.01, 0.5), 0.02, [&](const WallContact& w) {
    ++walls;
    EXPECT_NEAR(w.distance, 0.01, 1e-12);
    EXPECT_TRUE(w.normal.isApprox(Vec3::UnitY()));
  });
  EXPECT_EQ(walls, 1);
  walls = 0;
  for_each_wall(ColliderGeometry(cont), Vec3(0.01, 0.3, 0.5), 0.02, [&](const WallContact& w) {
    ++walls;
    EXPECT_TRUE(w.normal.isApprox(Vec3::UnitX()));
  });
  EXPECT_EQ(walls, 1);
  walls = 0;
  for_each_wall(ColliderGeometry(cont), Vec3(0.5, 0.52, 0.5), 0.01, [&](const WallContact&) { ++walls; });
  EXPECT_EQ(walls, 0);  // above the open top
}

TEST(Meshes, ClosestPointOnTriangleMatchesBruteForce) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.3, 0.8, 0.2);
  for (const Vec3& p : {Vec3(0.2, 0.2, 1), Vec3(-1, -1, 0), Vec3(2, 0.1, 0), Vec3(0.5, 1, -1), Vec3(0.6, -0.5, 0.3)}) {
    const Vec3 q = closest_point_on_triangle(p, a, b, c);
    double best = 1e300;
    for (int i = 0; i <= 400; ++i)
      for (int j = 0; i + j <= 400; ++j) {
        const Vec3 x = a + (b - a) * (i / 400.0) + (c - a) * (j / 400.0);
        best = std::min(best, (x - p).norm());
      }
    EXPECT_NEAR((q - p).norm(), best, 3e-3) << p.transpose();
  }
}

TEST(Colliders, MeshSegmentOnlyHitsFacingTriangles) {
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->vertices = {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(1, 0, 1), Vec3(-1, 0, 1)};
  mesh->triangles = {{0, 2, 1}, {0, 3, 2}};  // normal +y
  ASSERT_TRUE(mesh->normal(0).isApprox(Vec3::UnitY()));
  const MeshCollider mc = MeshCollider::build(*mesh, 0.1);
  EXPECT_EQ(mesh_segment_hits(mc, Vec3(0.3, 0.05, 0.1), Vec3(0.3, -0.01, 0.1), 0.001).hits, 1);
  EXPECT_EQ(mesh_segment_hits(mc, Vec3(0.1, -0.05, 0.1), Vec3(0.1, 0.01, 0.1), 0.001).hits, 0);
  EXPECT_EQ(mesh_segment_hits(mc, Vec3(0.1, 0.05, 0.1), Vec3(0.1, 0.02, 0.1), 0.001).hits, 0);
  // Reach of the particle radius: stops a particle about to touch the plane.
  EXPECT_EQ(mesh_segment_hits(mc, Vec3(0.3, 0.05, 0.1), Vec3(0.3, 0.002, 0.1), 0.004).hits, 1);
}

TEST(Colliders, CylinderSignedDistanceIsExact) {
  const ColliderGeometry g = CylinderCollider{Vec3(0, 1, 0), Vec3::UnitY(), 0.5, 2.0};  // y in [0, 2]
  auto d = [&](const Vec3& p) { return signed_distance(g, p); };
  EXPECT_NEAR(d(Vec3(0, 1, 0)).distance, -0.5, 1e-12);  // centre: nearest is the side
  EXPECT_NEAR(d(Vec3(1.5, 1, 0)).distance, 1.0, 1e-12);
  EXPECT_NEAR(d(Vec3(1.5, 1, 0)).normal.x(), 1.0, 1e-12);
  EXPECT_NEAR(d(Vec3(0.1, 2.3, 0)).distance, 0.3, 1e-12);  // above the cap
  EXPECT_NEAR(d(Vec3(0.1, 2.3, 0)).normal.y(), 1.0, 1e-12);
  EXPECT_NEAR(d(Vec3(0, -0.2, 0.1)).normal.y(), -1.0, 1e-12);  // below
  // Beyond the rim: distance to the circular edge.
  EXPECT_NEAR(d(Vec3(0, 2.4, 0.8)).distance, 0.5, 1e-12);
  EXPECT_NEAR(d(Vec3(0, 2.4, 0.8)).normal.dot(Vec3(0, 0.8, 0.6)), 1.0, 1e-12);
}

TEST(Colliders, CupHasFloorWallAndOptionalTubeAndAnOpenTop) {
  const CupCollider cup{Vec3(0, 0, 0), Vec3::UnitY(), 0.1, 0.05, 0.01, 0.02};
  const ColliderGeometry g = cup;
  auto d = [&](const Vec3& p) { return signed_distance(g, p); };
  EXPECT_NEAR(d(Vec3(0.05, 0.02, 0)).distance, 0.02, 1e-12);  // above the floor, nearest the floor
  EXPECT_NEAR(d(Vec3(0.05, 0.02, 0)).normal.y(), 1.0, 1e-12);
  EXPECT_NEAR(d(Vec3(0.095, 0.03, 0)).distance, 0.005, 1e-12);  // near the wall, inside the cup
  EXPECT_NEAR(d(Vec3(0.095, 0.03, 0)).normal.x(), -1.0, 1e-12);
  EXPECT_NEAR(d(Vec3(0.105, 0.03, 0)).distance, -0.005, 1e-12);  // in the wall
  EXPECT_NEAR(d(Vec3(0.025, 0.03, 0)).distance, 0.005, 1e-12);   // beside the tube
  EXPECT_NEAR(d(Vec3(0.025, 0.03, 0)).normal.x(), 1.0, 1e-12);
  EXPECT_GT(d(Vec3(0.05, 0.2, 0)).distance, 0.1);  // open top: far above, nothing near
  // The same walls through for_each_wall (the SPH view of it).
  int near = 0;
  for_each_wall(g, Vec3(0.095, 0.003, 0), 0.006, [&](const WallContact&) { ++near; });
  EXPECT_EQ(near, 2);  // the floor and the wall at the inner corner
}

// A point inside a wall just above the floor's top must leave through the
// wall's inner or outer face, not through the joint between the parts: that
// joint is inside the solid, and particles pushed onto it slid out through
// the wall (the tilted pancake pitcher lost 3% of its batter that way).
TEST(Colliders, CupAndContainerHaveNoSeamWhereTheWallMeetsTheFloor) {
  const Real t = 0.008, eps = 1e-4;
  const ColliderGeometry cup = CupCollider{Vec3(0, 0, 0), Vec3::UnitY(), 0.03, 0.08, t, 0};
  for (const Real r : {0.0305, 0.032, 0.0335}) {  // inner half of the wall
    const WallContact c = signed_distance(cup, Vec3(r, eps, 0));
    EXPECT_NEAR(c.distance, -(r - 0.03), 1e-12) << r;
    EXPECT_NEAR(c.normal.x(), -1.0, 1e-12) << r;  // back into the cup
  }
  for (const Real r : {0.0345, 0.037}) {  // outer half: out of the cup's side
    const WallContact c = signed_distance(cup, Vec3(r, eps, 0));
    EXPECT_NEAR(c.distance, -(0.038 - r), 1e-12) << r;
    EXPECT_NEAR(c.normal.x(), 1.0, 1e-12) << r;
  }
  // In the floor under the wall: out through the nearest real face.
  const WallContact under = signed_distance(cup, Vec3(0.037, -0.006, 0));
  EXPECT_NEAR(under.distance, -0.001, 1e-12);
  EXPECT_NEAR(under.normal.x(), 1.0, 1e-12);

  const ContainerCollider cont{{Vec3(0, 0, 0), Vec3(0.2, 0.1, 0.2)}, t};
  const ColliderGeometry box = cont;
  const WallContact side = signed_distance(box, Vec3(-0.002, eps, 0.1));  // -x wall, just above the floor's top
  EXPECT_NEAR(side.distance, -0.002, 1e-12);
  EXPECT_NEAR(side.normal.x(), 1.0, 1e-12);
  // In the -z wall next to the -x wall (the vertical edge): not onto the joint.
  const WallContact edge = signed_distance(box, Vec3(eps, 0.05, -0.002));
  EXPECT_NEAR(edge.distance, -0.002, 1e-12);
  EXPECT_NEAR(edge.normal.z(), 1.0, 1e-12);
}

TEST(Colliders, MeshSignedDistanceGridMatchesTheBox) {
  TriangleMesh m = load_mesh(write_cube_obj().string());
  m.apply(0.1, Vec3(0, 0, 0), Vec3(0, 0, 0));  // [0, 0.1]^3
  const MeshCollider mc = MeshCollider::build(m, 0.02).with_signed_distance(0.005, 0.03);
  const Aabb box{Vec3::Zero(), Vec3::Constant(0.1)};
  Real worst = 0;
  int count = 0;
  for (Real x = -0.02; x <= 0.12; x += 0.0073)
    for (Real y = -0.02; y <= 0.12; y += 0.0091)
      for (Real z = 0.011; z <= 0.09; z += 0.017) {
        const Vec3 p(x, y, z);
        const WallContact exact = box_contact(box, p);
        if (std::abs(exact.distance) > 0.02) continue;  // inside the exact band
        const WallContact c = mc.sdf->sample(p);
        worst = std::max(worst, std::abs(c.distance - exact.distance));
        ++count;
        if (std::abs(exact.distance) > 0.006) {
          EXPECT_EQ(c.distance < 0, exact.distance < 0) << p.transpose();
        }
      }
  EXPECT_GT(count, 300);
  // Trilinear sampling of an exact distance: errors of a fraction of the cell
  // near the edges, where the distance bends.
  EXPECT_LT(worst, 0.003);
  // Through the variant: far from the mesh it reports free space.
  EXPECT_GT(signed_distance(ColliderGeometry(mc), Vec3(0.5, 0.5, 0.5)).distance, 0);
  EXPECT_NEAR(signed_distance(ColliderGeometry(mc), Vec3(0.05, 0.11, 0.05)).normal.y(), 1.0, 1e-6);
}

TEST(Motion, KeyframesInterpolateAndVelocityMatchesTheMotion) {
  RigidKeyframe a, b, c;
  a.time = 0;
  b.time = 1;
  b.translation = Vec3(0.2, 0, 0);
  b.rotation = rotation_from_degrees(Vec3(0, 90, 0));
  c.time = 2;
  c.translation = Vec3(0.2, 0.1, 0);
  c.rotation = b.rotation;
  const RigidMotion motion(Vec3(1, 0, 0), {a, b, c});
  const RigidPose mid = motion.at(0.5);
  EXPECT_NEAR(mid.translation.x(), 0.1, 1e-12);
  EXPECT_TRUE(mid.rotation.isApprox(rotation_from_degrees(Vec3(0, 45, 0)), 1e-12));
  EXPECT_NEAR(mid.angular_velocity.y(), M_PI / 2, 1e-12);
  // A point of the body: its velocity is the time derivative of its position.
  const Vec3 rest(1.3, 0.2, -0.4);
  const Real h = 1e-6;
  for (Real t : {0.3, 1.5}) {
    const Vec3 fd = (motion.at(t + h).to_world(rest) - motion.at(t - h).to_world(rest)) / (2 * h);
    const RigidPose p = motion.at(t);
    EXPECT_TRUE(p.velocity_at(p.to_world(rest)).isApprox(fd, 1e-6)) << t;
    EXPECT_TRUE(p.to_rest(p.to_world(rest)).isApprox(rest, 1e-12));
  }
  // Held after the last keyframe, at rest.
  EXPECT_TRUE(motion.at(5).velocity.isZero());
  EXPECT_NEAR(motion.at(5).translation.y(), 0.1, 1e-12);
}

// OpenSpaceGrid: a lattice cube with a closed cavity (a 3×3×3 block of
// lattice sites left out at its centre) and a channel: the space round the
// cube is open, the cavity is not; opened by a channel to the outside, it is.
TEST(OpenSpace, TheSpaceRoundABodyIsOpenAndAClosedCavityIsNot) {
  const Real s = 0.001;
  auto cube = [&](bool channel) {
    std::vector<Vec3> x;
    for (int i = 0; i < 15; ++i)
      for (int j = 0; j < 15; ++j)
        for (int k = 0; k < 15; ++k) {
          const bool cavity = std::abs(i - 7) <= 2 && std::abs(j - 7) <= 2 && std::abs(k - 7) <= 2;
          const bool tunnel = channel && std::abs(i - 7) <= 2 && std::abs(k - 7) <= 2 && j > 7;
          if (!cavity && !tunnel) x.emplace_back(i * s, j * s, k * s);
        }
    return x;
  };
  const Vec3 centre(7 * s, 7 * s, 7 * s), up(0, 1, 0);
  for (const bool channel : {false, true}) {
    const std::vector<Vec3> x = cube(channel);
    const std::vector<Real> radii(x.size(), s);
    OpenSpaceGrid grid;
    grid.build(x, radii, s);
    EXPECT_TRUE(grid.open_at(Vec3(7 * s, 18 * s, 7 * s)));  // above the cube
    EXPECT_TRUE(grid.open_at(Vec3(-3 * s, 7 * s, 7 * s)));  // beside it
    EXPECT_TRUE(grid.open_at(Vec3(1, 1, 1)));               // far outside the grid
    EXPECT_EQ(grid.open_at(centre), channel) << "channel " << channel;
    // A particle on the cube's top face sees open space within its size and two spacings; one deep inside does not.
    EXPECT_TRUE(grid.open_along(Vec3(3 * s, 14 * s, 3 * s), up, 3 * s));
    EXPECT_FALSE(grid.open_along(Vec3(3 * s, 3 * s, 3 * s), up, 3 * s));
    // The cavity's wall, looking into the cavity (down from its roof).
    EXPECT_EQ(grid.open_along(Vec3(7 * s, 10 * s, 7 * s), -up, 3 * s), channel);
  }
}
