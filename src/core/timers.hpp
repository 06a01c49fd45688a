#pragma once
// Named phase timers: each solver phase is timed so `bakesim run`/`bench` can
// report where the time goes.
#include <chrono>
#include <string>
#include <vector>

namespace bakesim {

class PhaseTimers {
 public:
  // Returns a stable id for a phase name; call once at solver construction.
  int add(const std::string& name);
  void accumulate(int id, double seconds) { seconds_[id] += seconds; }
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<double>& seconds() const { return seconds_; }
  double total() const;
  void reset();
  // The time spent since `earlier` (a copy taken before), phase by phase.
  PhaseTimers since(const PhaseTimers& earlier) const;
  std::string report(long steps) const;

 private:
  std::vector<std::string> names_;
  std::vector<double> seconds_;
};

// RAII scope that adds its lifetime to a phase.
class ScopedPhase {
 public:
  ScopedPhase(PhaseTimers& timers, int id) : timers_(timers), id_(id), start_(std::chrono::steady_clock::now()) {}
  ~ScopedPhase() {
    timers_.accumulate(id_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedPhase(const ScopedPhase&) = delete;
  ScopedPhase& operator=(const ScopedPhase&) = delete;

 private:
  PhaseTimers& timers_;
  int id_;
  std::chrono::steady_clock::time_point start_;
};

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace bakesim
