#include "core/timers.hpp"

#include <fmt/format.h>

#include <numeric>

namespace bakesim {

int PhaseTimers::add(const std::string& name) {
  for (std::size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return static_cast<int>(i);
  names_.push_back(name);
  seconds_.push_back(0.0);
  return static_cast<int>(names_.size() - 1);
}

double PhaseTimers::total() const { return std::accumulate(seconds_.begin(), seconds_.end(), 0.0); }

PhaseTimers PhaseTimers::since(const PhaseTimers& earlier) const {
  PhaseTimers out = *this;
  for (std::size_t i = 0; i < out.seconds_.size() && i < earlier.seconds_.size(); ++i)
    out.seconds_[i] -= earlier.seconds_[i];
  return out;
}

void PhaseTimers::reset() { std::fill(seconds_.begin(), seconds_.end(), 0.0); }

std::string PhaseTimers::report(long steps) const {
  const double sum = total();
  std::string out;
  for (std::size_t i = 0; i < names_.size(); ++i) {
    out += fmt::format("  {:<14} {:9.3f} ms/step {:5.1f}%\n", names_[i],
                       steps > 0 ? 1e3 * seconds_[i] / double(steps) : 0.0, sum > 0 ? 100.0 * seconds_[i] / sum : 0.0);
  }
  return out;
}

}  // namespace bakesim
