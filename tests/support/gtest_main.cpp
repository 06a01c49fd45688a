// The test binaries' main: GoogleTest's, plus an optional thread limit.
//
// ctest runs as many tests at once as the machine has cores, and each long
// bake would otherwise start a worker per core: two bakes on two cores then
// share four threads, where one each needs no synchronisation (measured on a
// 2-core machine alone: an SPH cookie bake runs at 70% parallel efficiency on
// two threads, an MPM cookie at 85%). tests/CMakeLists.txt
// sets BAKESIM_TEST_THREADS=1 on the GoogleTest binaries; the tests that
// compare one thread against two lift it (support/threads.hpp).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstdlib>
#include <optional>

#include "support/threads.hpp"

namespace {

std::size_t requested_threads() {
  const char* threads = std::getenv("BAKESIM_TEST_THREADS");
  return threads && std::atoi(threads) > 0 ? std::size_t(std::atoi(threads)) : 0;
}

std::optional<tbb::global_control>& thread_limit() {
  static std::optional<tbb::global_control> limit;
  return limit;
}

}  // namespace

namespace bakesim::test_support {

ThreadLimitLifted::ThreadLimitLifted() { thread_limit().reset(); }

ThreadLimitLifted::~ThreadLimitLifted() {
  if (const std::size_t n = requested_threads()) thread_limit().emplace(tbb::global_control::max_allowed_parallelism, n);
}

}  // namespace bakesim::test_support

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (const std::size_t n = requested_threads()) thread_limit().emplace(tbb::global_control::max_allowed_parallelism, n);
  const int result = RUN_ALL_TESTS();
  thread_limit().reset();
  return result;
}
