// Neighbour search against brute force on random sets (thesis 3.1.2).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/errors.hpp"
#include "core/particles.hpp"
#include "sph/neighbours.hpp"

using namespace bakesim;
using namespace bakesim::sph;

namespace {

std::vector<Vec3> random_points(std::size_t n, const Aabb& box, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> x(n);
  for (auto& p : x)
    for (int k = 0; k < 3; ++k) p[k] = box.min[k] + u(rng) * (box.max[k] - box.min[k]);
  return x;
}

void expect_same_lists(const NeighbourLists& a, const NeighbourLists& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    std::vector<std::uint32_t> la(a.begin(i), a.end(i)), lb(b.begin(i), b.end(i));
    std::sort(la.begin(), la.end());
    std::sort(lb.begin(), lb.end());
    ASSERT_EQ(la, lb) << "particle " << i;
  }
}

// Sorts the points by cell as the solver does, then finds neighbours.
NeighbourLists sort_and_find(NeighbourSearch& search, const std::vector<Vec3>& x, std::vector<Vec3>& sorted) {
  std::vector<std::uint32_t> order;
  search.sort_order(x, order);
  sorted.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) sorted[i] = x[order[i]];
  NeighbourLists lists;
  search.find(sorted, lists);
  return lists;
}

}  // namespace

// Outside the anonymous namespace: the test classes derive from it (unity builds warn otherwise).
class NeighbourMethods : public ::testing::TestWithParam<NeighbourMethod> {};

TEST_P(NeighbourMethods, MatchesBruteForceOnRandomSets) {
  const Aabb domain{Vec3(-0.3, 0.0, -0.1), Vec3(0.5, 0.4, 0.2)};
  for (unsigned seed : {1u, 2u, 3u}) {
    const double h = 0.05 + 0.01 * seed;
    std::vector<Vec3> x = random_points(3000, domain, seed);
    NeighbourSearch search(GetParam(), domain, h);
    std::vector<Vec3> sorted;
    const NeighbourLists lists = sort_and_find(search, x, sorted);
    expect_same_lists(lists, brute_force_neighbours(sorted, h));
    // Lists are in ascending order, so sums do not depend on the method.
    for (std::size_t i = 0; i < lists.size(); ++i) EXPECT_TRUE(std::is_sorted(lists.begin(i), lists.end(i)));
  }
}

TEST_P(NeighbourMethods, HandlesPointsOutsideTheDomainAndDenseClusters) {
  const Aabb domain{Vec3::Zero(), Vec3::Ones()};
  std::vector<Vec3> x = random_points(500, Aabb{Vec3::Constant(-0.2), Vec3::Constant(1.2)}, 7);
  // A dense cluster forces the list stride to grow.
  for (int i = 0; i < 400; ++i) x.push_back(Vec3(0.5, 0.5, 0.5) + 1e-4 * Vec3(i % 7, i % 11, i % 13));
  NeighbourSearch search(GetParam(), domain, 0.1);
  std::vector<Vec3> sorted;
  const NeighbourLists lists = sort_and_find(search, x, sorted);
  expect_same_lists(lists, brute_force_neighbours(sorted, 0.1));
  EXPECT_GE(lists.max_count(), 399u);
}

// Eq 3.56: with per-particle supports, j neighbours i when r < (h_i + h_j)/2.
TEST_P(NeighbourMethods, VariableSupportMatchesBruteForce) {
  const Aabb domain{Vec3(-0.3, 0.0, -0.1), Vec3(0.5, 0.4, 0.2)};
  const double h0 = 0.05;
  std::vector<Vec3> x = random_points(2500, domain, 11);
  NeighbourSearch search(GetParam(), domain, h0);
  std::vector<std::uint32_t> order;
  search.sort_order(x, order);
  std::vector<Vec3> sorted(x.size());
  std::vector<Real> support(x.size());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.8, 1.5);
  for (std::size_t i = 0; i < x.size(); ++i) {
    sorted[i] = x[order[i]];
    support[i] = u(rng) * h0;
  }
  NeighbourLists lists;
  search.find(sorted, support, lists);
  std::vector<std::vector<std::uint32_t>> expected(x.size());
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = 0; j < x.size(); ++j) {
      const double hij = 0.5 * (support[i] + support[j]);
      if (i != j && (sorted[i] - sorted[j]).squaredNorm() < hij * hij) {
        expected[i].push_back(std::uint32_t(j));
        ++pairs;
      }
    }
  EXPECT_GT(pairs, 10 * x.size());
  expect_same_lists(lists, NeighbourLists::from_lists(expected));
  for (std::size_t i = 0; i < lists.size(); ++i) {
    EXPECT_TRUE(std::is_sorted(lists.begin(i), lists.end(i)));
    const float* d = lists.distances(i);
    for (std::uint32_t k = 0; k < lists.count(i); ++k)
      EXPECT_NEAR(d[k], (sorted[i] - sorted[lists.begin(i)[k]]).norm(), 1e-6);
  }
}

// Verlet lists: candidates found with a skin s, then every point moved by less
// than s/2 (wrapped into the periodic box), keep exactly the pairs within h now,
// in ascending order, at their nearest-image distances; moved further, pairs
// are missed (the solver searches again before that).
TEST_P(NeighbourMethods, VerletListsKeepThePairsWithinTheSupportWhileMovesStayUnderHalfTheSkin) {
  const Aabb box{Vec3(0, 0, 0), Vec3(0.8, 0.6, 0.5)};
  const Real h = 0.08, skin = 0.2 * h;
  for (bool periodic : {false, true}) {
    const Periodicity periodicity{box, {periodic, false, periodic}};
    NeighbourSearch search(GetParam(), box, h);
    search.set_periodicity(periodicity);
    std::vector<Vec3> anchors;
    sort_and_find(search, random_points(3000, box, 21), anchors);
    NeighbourLists candidates;
    search.find(anchors, candidates, skin);
    for (Real move : {0.49 * skin, 1.5 * skin}) {
      std::mt19937 rng(9);
      std::normal_distribution<double> g(0.0, 1.0);
      std::vector<Vec3> x(anchors.size());
      for (std::size_t i = 0; i < x.size(); ++i) {
        const Vec3 dir = Vec3(g(rng), g(rng), g(rng)).normalized();
        x[i] = periodicity.wrap(anchors[i] + move * dir);  // every point moves the full distance
      }
      NeighbourLists lists;
      search.keep_within(candidates, x, lists);
      std::size_t pairs = 0, missed = 0;
      for (std::size_t i = 0; i < x.size(); ++i) {
        std::vector<std::uint32_t> expected;
        for (std::size_t j = 0; j < x.size(); ++j)
          if (j != i && periodicity.nearest_image(x[i] - x[j]).norm() < h) expected.push_back(std::uint32_t(j));
        pairs += expected.size();
        const std::vector<std::uint32_t> got(lists.begin(i), lists.end(i));
        EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
        for (std::uint32_t k = 0; k < lists.count(i); ++k)
          EXPECT_NEAR(lists.distances(i)[k], periodicity.nearest_image(x[i] - x[got[k]]).norm(), 1e-6);
        if (move < 0.5 * skin)
          ASSERT_EQ(got, expected) << "particle " << i << (periodic ? ", periodic" : "");
        else
          missed += expected.size() - got.size();
      }
      EXPECT_GT(pairs, 20 * x.size());
      if (move > skin) {
        EXPECT_GT(missed, 0u) << "moved past the skin, the candidates cannot hold every pair";
      }
    }
  }
}

// With per-particle supports, a candidate search with skin s covers moves d
// and support growth g while 2d + g < s.
TEST_P(NeighbourMethods, VerletListsWithVariableSupportCoverMovesAndGrowth) {
  const Aabb box{Vec3(-0.3, 0.0, -0.1), Vec3(0.5, 0.4, 0.2)};
  const Real h0 = 0.05, skin = 0.25 * h0;
  NeighbourSearch search(GetParam(), box, h0);
  std::vector<Vec3> anchors;
  sort_and_find(search, random_points(2500, box, 13), anchors);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.8, 1.4);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Real> support(anchors.size());
  for (Real& s : support) s = u(rng) * h0;
  NeighbourLists candidates;
  search.find(anchors, support, candidates, skin);
  // Moves of 0.3 s and growth of 0.35 s: 2 · 0.3 + 0.35 = 0.95 < 1.
  std::vector<Vec3> x(anchors.size());
  std::vector<Real> grown(support);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = anchors[i] + 0.3 * skin * Vec3(g(rng), g(rng), g(rng)).normalized();
    grown[i] += 0.35 * skin * (i % 3 == 0 ? 1.0 : -0.5);
  }
  NeighbourLists lists;
  search.keep_within(candidates, x, grown, lists);
  std::vector<std::vector<std::uint32_t>> expected(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = 0; j < x.size(); ++j) {
      const Real hij = 0.5 * (grown[i] + grown[j]);
      if (i != j && (x[i] - x[j]).squaredNorm() < hij * hij) expected[i].push_back(std::uint32_t(j));
    }
  for (std::size_t i = 0; i < x.size(); ++i)
    ASSERT_EQ(std::vector<std::uint32_t>(lists.begin(i), lists.end(i)), expected[i]) << "particle " << i;
}

INSTANTIATE_TEST_SUITE_P(Search, NeighbourMethods, ::testing::Values(NeighbourMethod::grid, NeighbourMethod::kdtree),
                         [](const auto& info) { return to_string(info.param); });

TEST(ParticleSet, PermuteReordersEveryAttribute) {
  ParticleSet ps;
  auto& a = ps.add_scalar("a", "");
  auto& v = ps.add_vector("v", "m/s");
  auto& id = ps.add_int("id");
  ps.resize(4);
  for (int i = 0; i < 4; ++i) {
    a[i] = i;
    v[i] = Vec3::Constant(i);
    id[i] = i;
  }
  ps.permute({3, 1, 0, 2});
  EXPECT_EQ(a[0], 3);
  EXPECT_EQ(v[3], Vec3::Constant(2));
  EXPECT_EQ(id[2], 0);
  EXPECT_THROW(ps.add_scalar("a", ""), Error);
}

// Periodic axes: pairs across the faces are found, at their nearest-image
// distance, exactly as brute force over the images finds them.
TEST(NeighbourSearch, PeriodicAxesFindPairsAcrossTheFacesAtTheirImageDistance) {
  const Aabb box{Vec3(0, 0, 0), Vec3(1.0, 0.6, 0.8)};
  const Real h = 0.12;
  const Periodicity periodic{box, {true, false, true}};
  const auto x = random_points(1500, box, 7);
  for (NeighbourMethod method : {NeighbourMethod::grid, NeighbourMethod::kdtree}) {
    NeighbourSearch search(method, box, h);
    search.set_periodicity(periodic);
    std::vector<Vec3> sorted;
    const NeighbourLists lists = sort_and_find(search, x, sorted);
    std::size_t across = 0;
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      std::vector<std::pair<std::uint32_t, float>> expected;
      for (std::size_t j = 0; j < sorted.size(); ++j) {
        const Real r = periodic.nearest_image(sorted[i] - sorted[j]).norm();
        if (j != i && r < h) expected.emplace_back(std::uint32_t(j), float(r));
      }
      ASSERT_EQ(lists.count(i), expected.size()) << to_string(method) << ", particle " << i;
      for (std::uint32_t k = 0; k < lists.count(i); ++k) {
        ASSERT_EQ(lists.begin(i)[k], expected[k].first) << "lists are in ascending index order";
        EXPECT_NEAR(lists.distances(i)[k], expected[k].second, 1e-6);
        across += (sorted[i] - sorted[expected[k].first]).norm() >= h;
      }
    }
    EXPECT_GT(across, 100u) << "the test set has pairs across the faces";
  }
}

TEST(Periodicity, WrapsIntoTheBoxAndPicksTheNearestImage) {
  const Periodicity p{Aabb{Vec3(-1, 0, 0), Vec3(1, 2, 3)}, {true, false, true}};
  const Vec3 w = p.wrap(Vec3(1.25, 5.0, -0.5));
  EXPECT_NEAR(w.x(), -0.75, 1e-12);
  EXPECT_EQ(w.y(), 5.0);  // not periodic: left alone
  EXPECT_NEAR(w.z(), 2.5, 1e-12);
  EXPECT_EQ(p.wrap(Vec3(1.0, 0, 3.0)), Vec3(-1.0, 0, 0));  // the max face is the min face
  EXPECT_EQ(p.wrap(Vec3(-1e-18, 0, -1e-18)).z(), 0.0);     // never lands on max by rounding
  const Vec3 d = p.nearest_image(Vec3(1.8, 1.9, -2.9));
  EXPECT_NEAR(d.x(), -0.2, 1e-12);
  EXPECT_EQ(d.y(), 1.9);
  EXPECT_NEAR(d.z(), 0.1, 1e-12);
  EXPECT_EQ(p.describe(), "x, z");
}
