// Health checks (docs/reliability.md): a NaN planted in one MPM particle's
// velocity stops the very next step with a message naming the step, a
// particle and the quantity (the SPH twin is in test_conservation.cpp).
#include <gtest/gtest.h>

#include <limits>

#include "core/errors.hpp"
#include "helpers.hpp"

using namespace bakesim;
using json = nlohmann::json;

namespace {

json block(const std::string& solver) {
  json s = {{"type", solver}};
  if (solver == "mpm")
    s["mpm"] = {{"cell_size", 0.01}};
  else
    s["sph"] = {{"spacing", 0.01}};
  return {
      {"solver", s},
      {"time", {{"end", 1.0}}},
      {"domain", {{"min", {0, 0, 0}}, {"max", {0.2, 0.2, 0.2}}}},
      {"materials",
       {{"dough", solver == "mpm" ? json{{"density", 1000.0}, {"youngs_modulus", 1e4}} : json{{"density", 1000.0}}}}},
      {"bodies",
       json::array({{{"name", "block"},
                     {"material", "dough"},
                     {"shape", {{"type", "box"}, {"min", {0.05, 0.02, 0.05}}, {"max", {0.1, 0.07, 0.1}}}}}})}};
}

void expect_caught_at_planted_step(Solver& solver, ParticleSet& particles, const std::string& step_word) {
  for (int i = 0; i < 5; ++i) solver.step(0.5 * solver.max_stable_dt());
  const std::size_t victim = particles.size() / 2;
  particles.vector("velocity")[victim].x() = std::numeric_limits<double>::quiet_NaN();
  try {
    solver.step(0.5 * solver.max_stable_dt());
    FAIL() << "the planted NaN was not caught";
  } catch (const SimulationError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(step_word + " 6 "), std::string::npos) << m;  // the sixth step, where it appeared
    EXPECT_NE(m.find("particle"), std::string::npos) << m;
    // The first bad particle is the planted one or a neighbour it poisoned;
    // either way the message names a non-finite quantity.
    EXPECT_TRUE(m.find("non-finite") != std::string::npos || m.find("invalid") != std::string::npos) << m;
  }
}

}  // namespace

TEST(Health, PlantedNanStopsTheMpmStepItAppearsIn) {
  auto solver = test_support::make_mpm(block("mpm"));
  expect_caught_at_planted_step(*solver, solver->particles_for_restore(), "mpm step");
}
