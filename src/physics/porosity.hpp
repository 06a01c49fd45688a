#pragma once
// Gas porosity of the porous dough (spec mpm-baking.md 3.2).
#include <algorithm>

#include "core/types.hpp"

namespace bakesim {

// n = (J^P − 1 + n₀) / J^P, clamped to [0, 0.95].
inline Real gas_porosity(Real plastic_j, Real initial_porosity) {
  return std::clamp((plastic_j - 1 + initial_porosity) / plastic_j, Real(0), Real(0.95));
}

}  // namespace bakesim
