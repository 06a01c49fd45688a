// OpenVDB frames (surface::encode_vdb, `bakesim mesh --vdb`): read back with
// OpenVDB's own I/O, the file holds the level set "surface" and one float grid
// per quantity; each float grid has exactly the voxels within the support of a
// particle, and each voxel's value is the Shepard average computed here by
// brute force; a linear temperature field comes back linear inside the body.
#include <gtest/gtest.h>

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <cmath>
#include <set>
#include <sstream>
#include <tuple>

#include "helpers.hpp"
#include "surface/surface.hpp"

using namespace bakesim;

namespace {

Real cubic_spline(Real r, Real support) {  // the colouring's kernel (unnormalised)
  const Real q = 2.0 * r / support;
  if (q >= 2) return 0;
  if (q >= 1) return 0.25 * (2 - q) * (2 - q) * (2 - q);
  return 1 - 1.5 * q * q + 0.75 * q * q * q;
}

}  // namespace

TEST(Vdb, ReadBackGridsHoldTheVoxelsAndValuesOfTheParticles) {
  const Real s = 0.004, radius = 0.02, support = 2 * s;
  const surface::SurfaceParticles p = test_support::lattice_ball(radius, s, Vec3(0, radius, 0));
  std::vector<Real> temperature;
  for (const Vec3& x : p.position) temperature.push_back(100 + 1000 * x.x());  // 1 K per mm along x
  surface::SurfaceOptions options;
  const std::string bytes = surface::encode_vdb(p, options, {{"temperature", "degC", temperature}}, support);

  openvdb::initialize();
  std::istringstream in(bytes, std::ios_base::binary);
  openvdb::io::Stream stream(in);
  const openvdb::GridPtrVecPtr grids = stream.getGrids();
  ASSERT_EQ(grids->size(), 2u);
  const auto level = openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[0]);
  const auto temp = openvdb::gridPtrCast<openvdb::FloatGrid>((*grids)[1]);
  ASSERT_TRUE(level && temp);
  EXPECT_EQ(level->getName(), "surface");
  EXPECT_EQ(level->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(temp->getName(), "temperature");
  EXPECT_EQ(temp->metaValue<std::string>("unit"), "degC");
  const Real voxel = level->voxelSize()[0];
  EXPECT_NEAR(voxel, 0.75 * s, 1e-12);
  // The level set is negative at the ball's centre and positive outside it.
  auto la = level->getConstAccessor();
  EXPECT_LT(la.getValue(level->transform().worldToIndexCellCentered(openvdb::Vec3d(0, radius, 0))), 0.0f);
  EXPECT_GT(la.getValue(level->transform().worldToIndexCellCentered(openvdb::Vec3d(0, 3 * radius, 0))), 0.0f);

  // The voxels within the support of some particle, by brute force.
  std::set<std::tuple<int, int, int>> expected;
  for (const Vec3& x : p.position) {
    const Vec3 lo = (x.array() - support) / voxel, hi = (x.array() + support) / voxel;
    for (int k = int(std::ceil(lo.z())); k <= int(std::floor(hi.z())); ++k)
      for (int j = int(std::ceil(lo.y())); j <= int(std::floor(hi.y())); ++j)
        for (int i = int(std::ceil(lo.x())); i <= int(std::floor(hi.x())); ++i)
          if ((Vec3(i, j, k) * voxel - x).norm() < support) expected.insert({i, j, k});
  }
  EXPECT_EQ(temp->activeVoxelCount(), openvdb::Index64(expected.size()));
  // Every voxel's value is the Shepard average; a linear field stays linear
  // where the support lies inside the ball.
  const Real volume = s * s * s;
  Real worst = 0, worst_inside = 0;
  std::size_t checked = 0;
  for (auto it = temp->cbeginValueOn(); it; ++it) {
    const openvdb::Coord c = it.getCoord();
    const Vec3 x = Vec3(c.x(), c.y(), c.z()) * voxel;
    if (checked++ % 7 == 0) {  // a sample of the voxels against the brute-force sum
      Real num = 0, den = 0;
      for (std::size_t i = 0; i < p.position.size(); ++i) {
        const Real w = volume * cubic_spline((x - p.position[i]).norm(), support);
        num += w * temperature[i], den += w;
      }
      worst = std::max(worst, std::abs(*it - num / den));
    }
    if ((x - Vec3(0, radius, 0)).norm() < radius - support - s)
      worst_inside = std::max(worst_inside, std::abs(*it - (100 + 1000 * x.x())));
  }
  EXPECT_LT(worst, 1e-3);         // float storage of values near 100
  EXPECT_LT(worst_inside, 0.05);  // K, against a field spanning 40 K
  RecordProperty("worst_inside_K", std::to_string(worst_inside));
}
