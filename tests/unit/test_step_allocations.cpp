// No allocation in a step (issue 25): once a solver has run a few steps, its
// step() and max_stable_dt() take no memory from the heap. Counted by
// replacing the global operator new for this test binary (every std::vector
// growth, std::string and std::function goes through it); the count is only
// taken between the two marks below. Shipped scenes in their preview form
// cover both solvers with heat, water and vapour, implicit viscosity and
// heat, colliders, moving grips and several materials.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <string>

#include "io/scene.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

// GCC takes the replaced operator new for the built-in one and warns that
// free() meets it; both are replaced here, so they match.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace bakesim;

class StepAllocations : public ::testing::TestWithParam<std::string> {};

namespace {

void expect_none_once_warm(const std::string& name, std::vector<SceneOverride> overrides = {}) {
  std::string path = BAKESIM_SOURCE_DIR;  // appended in steps: GCC 12 warns falsely on a + b + c + d at -O1
  path += "/scenes/" + name + ".json";
  const Scene scene = load_scene(path, std::move(overrides), true);
  auto solver = make_solver(scene);
  // Warm: scratch vectors, neighbour lists and solver workspaces reach their sizes.
  for (int k = 0; k < 30; ++k) solver->step(solver->max_stable_dt());
  g_allocations = 0;
  g_counting = true;
  for (int k = 0; k < 60; ++k) solver->step(solver->max_stable_dt());
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0) << name << ": heap allocations in 60 steps";
  // The counter sees allocations at all (a test that cannot fail is no test).
  g_counting = true;
  const std::string probe(64, 'x');
  g_counting = false;
  EXPECT_GE(g_allocations.load(), 1);
}

}  // namespace

TEST_P(StepAllocations, NoneOnceWarm) { expect_none_once_warm(GetParam()); }

// The surface phase's open-space grid (solver.sph.surface.open_space) keeps its buffers too.
TEST(StepAllocations, NoneOnceWarmWithTheOpenSpaceTest) {
  expect_none_once_warm("zhang-loaf-unrisen-sph", {parse_override("solver.sph.surface.open_space=true")});
}

// The stress-form operator with an elastic dough: the gradient correction
// shared by the stress phase, the forces and the solve, and the Maxwell
// stress's corrected divergence keep their buffers too.
TEST(StepAllocations, NoneOnceWarmWithTheStressFormAndElasticity) {
  expect_none_once_warm("bread-roll", {parse_override("solver.sph.viscosity_operator=stress")});
}

INSTANTIATE_TEST_SUITE_P(ShippedPreviews, StepAllocations,
                         ::testing::Values("cookie-on-a-tray", "cookie-on-a-tray-sph", "dam-break",
                                           "zhang-loaf-unrisen-sph", "zhang-loaf-unrisen-mpm", "dough-pull-twist",
                                           "lava-cake", "smore", "bread-roll", "volcano", "zhang-loaf-sph",
                                           "zhang-loaf-mpm", "bread-loaf"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });
