// Colliders as meshes (geometry/collider_mesh.hpp), for pictures and export:
// each shape's mesh is closed and outward, lies on the collider's surface (its
// signed distance is zero at every vertex) and holds the solid's volume (exact
// for flat faces, the inscribed polygon's for round ones); moving colliders'
// meshes follow their motion; domain walls and hidden colliders are not drawn
// as colliders, and the domain drawn as a tank has the walls a viewer looks into.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "core/errors.hpp"
#include "geometry/collider_mesh.hpp"

using namespace bakesim;

namespace {

// Every edge of a closed, consistently oriented mesh is used once in each direction.
bool closed_and_oriented(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, count] : edges) {
    const auto back = edges.find({e.second, e.first});
    if (count != 1 || back == edges.end() || back->second != 1) return false;
  }
  return true;
}

// Area of the regular n-gon inscribed in a circle of radius r.
double polygon(double r, int n) { return 0.5 * n * r * r * std::sin(2 * kPi / n); }

void expect_on_surface(const ColliderGeometry& g, const TriangleMesh& m) {
  for (const Vec3& v : m.vertices) ASSERT_NEAR(signed_distance(g, v).distance, 0.0, 1e-12) << v.transpose();
}

// Parts that meet (a cup's tube standing on its floor) have faces inside the solid: no vertex is outside it.
void expect_not_outside(const ColliderGeometry& g, const TriangleMesh& m) {
  for (const Vec3& v : m.vertices) ASSERT_LE(signed_distance(g, v).distance, 1e-12) << v.transpose();
}

}  // namespace

TEST(ColliderMeshes, BoxesAndContainersAreClosedOnTheSurfaceAndHoldTheSolid) {
  const BoxCollider box{{Vec3(-0.1, 0, -0.05), Vec3(0.1, 0.01, 0.05)}};
  const TriangleMesh b = collider_rest_mesh(box, Vec3::Zero(), 1);
  EXPECT_TRUE(closed_and_oriented(b));
  EXPECT_NEAR(b.signed_volume(), 0.2 * 0.01 * 0.1, 1e-15);
  expect_on_surface(box, b);

  const ContainerCollider tin{{Vec3(-0.05, 0, -0.03), Vec3(0.05, 0.06, 0.03)}, 0.004};
  const TriangleMesh c = collider_rest_mesh(tin, Vec3::Zero(), 1);
  EXPECT_TRUE(closed_and_oriented(c));
  // The solid: the outer box (open top at the rim) less the free inside.
  const double outer = (0.1 + 0.008) * (0.06 + 0.004) * (0.06 + 0.008), inner = 0.1 * 0.06 * 0.06;
  EXPECT_NEAR(c.signed_volume(), outer - inner, 1e-14);
  expect_on_surface(tin, c);
}

TEST(ColliderMeshes, RoundShapesAreTheInscribedPolygonsSolid) {
  const int n = 64;
  const CylinderCollider pin{Vec3(0.01, 0.02, 0.03), Vec3(1, 1, 0).normalized(), 0.02, 0.3};
  const TriangleMesh p = collider_rest_mesh(pin, Vec3::Zero(), 1, n);
  EXPECT_TRUE(closed_and_oriented(p));
  EXPECT_NEAR(p.signed_volume(), polygon(0.02, n) * 0.3, 1e-12);
  EXPECT_NEAR(p.signed_volume() / (kPi * 0.02 * 0.02 * 0.3), 1.0, 0.002);  // the true cylinder's
  expect_on_surface(pin, p);

  const CupCollider pan{Vec3(0, 0.01, 0), Vec3(0, 1, 0), 0.1, 0.05, 0.003, 0.02};
  const TriangleMesh c = collider_rest_mesh(pan, Vec3::Zero(), 1, n);
  EXPECT_TRUE(closed_and_oriented(c));
  const double floor = polygon(0.103, n) * 0.003, wall = (polygon(0.103, n) - polygon(0.1, n)) * 0.05,
               tube = polygon(0.02, n) * 0.05;
  EXPECT_NEAR(c.signed_volume(), floor + wall + tube, 1e-12);
  expect_not_outside(pan, c);
}

TEST(ColliderMeshes, APlaneIsASlabUnderTheFocusWithItsTopOnThePlane) {
  const PlaneCollider floor{Vec3(0, 0.02, 0), Vec3(0, 1, 0)};
  const Vec3 focus(0.3, 0.5, -0.2);
  const Real half = 0.25;
  const TriangleMesh m = collider_rest_mesh(floor, focus, half);
  EXPECT_TRUE(closed_and_oriented(m));
  const Real depth = kPlaneSlabThickness * half;
  EXPECT_NEAR(m.signed_volume(), 4 * half * half * depth, 1e-14);
  const Aabb box = m.bounds();
  EXPECT_NEAR(box.max.y(), 0.02, 1e-15);
  EXPECT_NEAR(box.min.y(), 0.02 - depth, 1e-15);
  EXPECT_NEAR(0.5 * (box.min.x() + box.max.x()), focus.x(), 1e-12);
  EXPECT_NEAR(0.5 * (box.min.z() + box.max.z()), focus.z(), 1e-12);
  EXPECT_FALSE(collider_rest_bounds(floor).has_value());
}

TEST(ColliderMeshes, AMovingColliderIsDrawnAtItsPose) {
  Collider c;
  c.geometry = BoxCollider{{Vec3(0, 0, 0), Vec3(0.02, 0.01, 0.03)}};
  RigidKeyframe k0, k1;
  k1.time = 2.0;
  k1.translation = Vec3(0.1, 0.05, 0);
  k1.rotation = rotation_from_degrees(Vec3(0, 90, 0));
  c.motion = RigidMotion(Vec3(0.01, 0, 0), {k0, k1});
  const TriangleMesh rest = collider_rest_mesh(c.geometry, Vec3::Zero(), 1);
  const TriangleMesh at = collider_mesh_at(c, 0.7, Vec3::Zero(), 1);
  const RigidPose pose = c.motion.at(0.7);
  ASSERT_EQ(at.vertices.size(), rest.vertices.size());
  for (std::size_t i = 0; i < rest.vertices.size(); ++i)
    EXPECT_LT((at.vertices[i] - pose.to_world(rest.vertices[i])).norm(), 1e-15);
  EXPECT_NEAR(at.signed_volume(), rest.signed_volume(), 1e-15);  // rigid
  // Before the first keyframe it is where the scene put it.
  const TriangleMesh before = collider_mesh_at(c, 0.0, Vec3::Zero(), 1);
  for (std::size_t i = 0; i < rest.vertices.size(); ++i)
    EXPECT_LT((before.vertices[i] - rest.vertices[i]).norm(), 1e-15);
}

TEST(ColliderMeshes, LooksDefaultByShapeAndUnknownNamesAreErrors) {
  EXPECT_EQ(default_look(PlaneCollider{Vec3::Zero(), Vec3::UnitY()}), ColliderLook::wood);
  EXPECT_EQ(default_look(CupCollider{Vec3::Zero(), Vec3::UnitY(), 0.1, 0.1, 0.01}), ColliderLook::metal);
  EXPECT_EQ(default_look(InsideBoxCollider{}), ColliderLook::hidden);
  const ColliderGeometry box = BoxCollider{};
  EXPECT_EQ(parse_collider_look("auto", box, "x"), ColliderLook::metal);
  EXPECT_EQ(parse_collider_look("glass", box, "x"), ColliderLook::glass);
  try {
    parse_collider_look("plastic", box, "scene.json: colliders[0].look");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "scene.json: colliders[0].look");
  }
  // The domain walls would hide the scene: no mesh.
  EXPECT_TRUE(collider_rest_mesh(InsideBoxCollider{{Vec3::Zero(), Vec3::Ones()}}, Vec3::Zero(), 1).triangles.empty());
}

// Issue 23: the domain as an open tank seen from a viewer outside, right, in
// front and above: the floor, the left and the back wall, each a closed slab
// outside the domain; nothing on a periodic axis; from inside, all six.
TEST(ColliderMeshes, TheDomainTankHasTheFloorAndTheWallsWhoseInsideTheViewerSees) {
  const Aabb domain{Vec3(0, 0, 0), Vec3(1, 0.5, 0.2)};
  const Real t = 0.01;
  const TriangleMesh tank = domain_tank_mesh(domain, {false, false, false}, Vec3(2, 1.5, 1), t);
  ASSERT_EQ(tank.triangles.size(), 3u * 12u);
  ASSERT_EQ(tank.vertices.size(), 3u * 8u);
  EXPECT_TRUE(closed_and_oriented(tank));
  std::vector<Aabb> slabs;
  for (std::size_t k = 0; k < 3; ++k) {
    Aabb b = Aabb::empty_box();
    for (std::size_t v = 8 * k; v < 8 * k + 8; ++v) b.expand(tank.vertices[v]);
    slabs.push_back(b);
    // Outside the domain: the slab touches at most its face.
    const Vec3 lo = b.min.cwiseMax(domain.min), hi = b.max.cwiseMin(domain.max);
    EXPECT_LE((hi - lo).minCoeff(), 1e-15) << "slab " << k << " reaches inside";
  }
  const auto has = [&](const Vec3& lo, const Vec3& hi) {
    return std::any_of(slabs.begin(), slabs.end(),
                       [&](const Aabb& b) { return (b.min - lo).norm() < 1e-12 && (b.max - hi).norm() < 1e-12; });
  };
  EXPECT_TRUE(has(Vec3(-t, -t, -t), Vec3(0, 0.5 + t, 0.2 + t)));  // the wall at x = 0 (far from the viewer)
  EXPECT_TRUE(has(Vec3(-t, -t, -t), Vec3(1 + t, 0, 0.2 + t)));    // the floor
  EXPECT_TRUE(has(Vec3(-t, -t, -t), Vec3(1 + t, 0.5 + t, 0)));    // the wall at z = 0
  EXPECT_EQ(tank.signed_volume() > 0, true);
  // Periodic along x: no wall across it.
  EXPECT_EQ(domain_tank_mesh(domain, {true, false, false}, Vec3(2, 1.5, 1), t).triangles.size(), 2u * 12u);
  // From inside: every face; from below a floorless view: no floor.
  EXPECT_EQ(domain_tank_mesh(domain, {false, false, false}, Vec3(0.5, 0.25, 0.1), t).triangles.size(), 6u * 12u);
  EXPECT_EQ(domain_tank_mesh(domain, {false, false, false}, Vec3(0.5, -1, 0.1), t).triangles.size(), 5u * 12u);
}
