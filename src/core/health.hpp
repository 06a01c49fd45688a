#pragma once
// Health checks after a step: the first particle (lowest index) whose state
// is invalid, found by a deterministic parallel scan, so the same state names
// the same particle on any thread count. The solver then says which quantity
// is wrong and throws SimulationError with its own context.
#include <algorithm>
#include <cstddef>

#include "core/parallel.hpp"

namespace bakesim {

// Lowest i in [0, n) with !valid(i), or n when every particle is valid.
template <class Valid>
std::size_t first_invalid(std::size_t n, Valid&& valid) {
  return deterministic_reduce(
      n, n,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i)
          if (!valid(i)) return i;
        return n;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
}

}  // namespace bakesim
