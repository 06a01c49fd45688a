#pragma once
// The thread limit BAKESIM_TEST_THREADS puts on a test binary
// (support/gtest_main.cpp), and a scope that lifts it: a test that compares
// one thread against two must really get two.

namespace bakesim::test_support {

class ThreadLimitLifted {
 public:
  ThreadLimitLifted();
  ~ThreadLimitLifted();
  ThreadLimitLifted(const ThreadLimitLifted&) = delete;
  ThreadLimitLifted& operator=(const ThreadLimitLifted&) = delete;
};

}  // namespace bakesim::test_support
