// Phase sort: particles by grid block, memory reordered every few steps.
#include "mpm/solver.hpp"

#include <algorithm>

namespace bakesim::mpm {

// Particles grouped by grid block (grid.hpp); every reorder_every steps the
// particle memory itself follows, so P2G and G2P walk memory in order.
void MpmSolver::phase_sort() {
  ScopedPhase t(timers_, t_sort_);
  blocks_.sort(x_, grid_origin_, inv_dx_);
  const int every = std::max(1, setup_.settings.reorder_every);
  if (steps_ % every == 0) {
    particles_.permute(blocks_.order());
    blocks_.set_identity();
    group_by_material();
  }
  blocks_.colour();
}

void MpmSolver::group_by_material() {
  material_members_.resize(setup_.materials.size());
  for (auto& members : material_members_) members.clear();
  for (std::size_t i = 0; i < x_.size(); ++i) material_members_[material_[i]].push_back(static_cast<std::uint32_t>(i));
}

}  // namespace bakesim::mpm
