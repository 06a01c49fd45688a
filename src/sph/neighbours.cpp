#include "sph/neighbours.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <atomic>
#include <memory>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "core/buffers.hpp"
#include "core/errors.hpp"
#include "core/parallel.hpp"

namespace bakesim::sph {

NeighbourMethod parse_neighbour_method(const std::string& s) {
  if (s == "grid") return NeighbourMethod::grid;
  if (s == "kdtree") return NeighbourMethod::kdtree;
  throw Error("unknown neighbour search method '" + s + "'");
}

std::string to_string(NeighbourMethod m) { return m == NeighbourMethod::grid ? "grid" : "kdtree"; }

std::size_t NeighbourLists::max_count() const {
  return count_.empty() ? 0 : *std::max_element(count_.begin(), count_.end());
}

double NeighbourLists::mean_count() const {
  if (count_.empty()) return 0.0;
  return double(std::accumulate(count_.begin(), count_.end(), std::uint64_t(0))) / double(count_.size());
}

void CellGrid::configure(const Aabb& box, Real cell_size) {
  cell_ = cell_size;
  inv_cell_ = 1.0 / cell_size;
  // One spare cell on each side for particles slightly outside the domain.
  box_.min = box.min - Vec3::Constant(cell_size);
  box_.max = box.max + Vec3::Constant(cell_size);
  const Vec3 ext = box_.extent();
  nx_ = std::max(1, int(std::ceil(ext.x() * inv_cell_)));
  ny_ = std::max(1, int(std::ceil(ext.y() * inv_cell_)));
  nz_ = std::max(1, int(std::ceil(ext.z() * inv_cell_)));
  const double cells = double(nx_) * ny_ * nz_;
  if (cells > 4e8)
    throw InputError("solver.sph.spacing", fmt::format("the neighbour grid over the domain would need {:.3g} cells "
                                                       "(at most 4e8): the domain is too large for this spacing",
                                                       cells));
  cell_start_.assign(std::size_t(nx_) * ny_ * nz_ + 1, 0);
}

void CellGrid::cell_coords(const Vec3& p, int& cx, int& cy, int& cz) const {
  auto c = clamp_cell;
  cx = c((p.x() - box_.min.x()) * inv_cell_, nx_);
  cy = c((p.y() - box_.min.y()) * inv_cell_, ny_);
  cz = c((p.z() - box_.min.z()) * inv_cell_, nz_);
}

std::int64_t CellGrid::cell_of(const Vec3& p) const {
  int cx, cy, cz;
  cell_coords(p, cx, cy, cz);
  return std::int64_t(cx) + std::int64_t(nx_) * (std::int64_t(cy) + std::int64_t(ny_) * cz);
}

void CellGrid::sort(const std::vector<Vec3>& x, std::vector<std::uint32_t>& order) {
  const std::size_t n = x.size();
  cell_index_.resize(n);
  parallel_for(
      n, [&](std::size_t i) { cell_index_[i] = static_cast<std::uint32_t>(cell_of(x[i])); }, 4096);
  std::fill(cell_start_.begin(), cell_start_.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) ++cell_start_[cell_index_[i] + 1];
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  order.resize(n);
  // Stable placement keeps the previous order inside each cell: deterministic.
  cell_fill_.assign(cell_start_.begin(), cell_start_.end() - 1);  // kept: a sort allocates nothing
  for (std::size_t i = 0; i < n; ++i) order[cell_fill_[cell_index_[i]]++] = static_cast<std::uint32_t>(i);
}

NeighbourSearch::NeighbourSearch(NeighbourMethod method, const Aabb& domain, Real support)
    : method_(method), h_(support) {
  grid_.configure(domain, 0.5 * support);
}

void NeighbourSearch::sort_order(const std::vector<Vec3>& x, std::vector<std::uint32_t>& order) {
  grid_.sort(x, order);
}

template <class Query>
void NeighbourSearch::fill(std::size_t n, NeighbourLists& lists, Query&& query) {
  lists.count_.assign(n, 0);
  for (;;) {
    resize_with_headroom(lists.ids_, n * lists.stride_);
    resize_with_headroom(lists.dist_, n * lists.stride_);
    std::atomic<std::size_t> overflow{0};
    const std::size_t stride = lists.stride_;
    parallel_blocks(n, [&](std::size_t b, std::size_t e) {
      std::size_t local_max = 0;
      for (std::size_t i = b; i < e; ++i) {
        std::uint32_t* out = lists.ids_.data() + i * stride;
        float* out_d = lists.dist_.data() + i * stride;
        std::size_t c = 0;
        query(i, [&](std::uint32_t j, Real d2) {
          if (c < stride) {
            out[c] = j;
            out_d[c] = static_cast<float>(std::sqrt(d2));
          }
          ++c;
        });
        lists.count_[i] = static_cast<std::uint32_t>(std::min(c, stride));
        local_max = std::max(local_max, c);
      }
      std::size_t cur = overflow.load();
      while (local_max > stride && local_max > cur && !overflow.compare_exchange_weak(cur, local_max)) {
      }
    });
    if (overflow.load() == 0) return;
    lists.stride_ = overflow.load() + overflow.load() / 4 + 8;  // rare: grow and redo
  }
}

namespace {
struct PointCloud {
  const std::vector<Vec3>& x;
  std::size_t kdtree_get_point_count() const { return x.size(); }
  Real kdtree_get_pt(std::size_t i, std::size_t d) const { return x[i][int(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};
using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<Real, PointCloud>, PointCloud, 3, std::uint32_t>;

// Result set that forwards each hit to a callback instead of storing it.
template <class Fn>
struct ForwardingResultSet {
  Real radius2;
  std::uint32_t self;
  Fn& fn;
  std::size_t found = 0;
  void init() {}
  void clear() {}
  std::size_t size() const { return found; }
  bool full() const { return true; }
  bool addPoint(Real dist, std::uint32_t index) {
    if (dist < radius2 && index != self) {
      fn(index, dist);
      ++found;
    }
    return true;
  }
  Real worstDist() const { return radius2; }
};
}  // namespace

void NeighbourSearch::find(const std::vector<Vec3>& x, const std::vector<Real>& support, NeighbourLists& lists,
                           Real skin) {
  const std::size_t n = x.size();
  Real h_max = 0;
  for (Real h : support) h_max = std::max(h_max, h);
  PointCloud cloud{x};
  std::unique_ptr<KdTree> tree;
  if (method_ == NeighbourMethod::kdtree) {
    tree = std::make_unique<KdTree>(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree->buildIndex();
  }
  fill(n, lists, [&](std::size_t i, auto&& emit) {
    const Vec3 xi = x[i];
    const Real hi = support[i];
    // No pair reaches beyond (h_i + h_max)/2 + skin.
    const Real radius = 0.5 * (hi + h_max) + skin;
    auto test = [&](std::uint32_t j, Real d2) {
      const Real hij = 0.5 * (hi + support[j]) + skin;
      if (d2 < hij * hij && j != i) emit(j, d2);
    };
    for_each_image(xi, radius, [&](const Vec3& shift) {
      const Vec3 q = xi + shift;
      if (!tree) {
        grid_.for_each_within(q, radius, [&](std::uint32_t j) { test(j, (q - x[j]).squaredNorm()); });
      } else {
        ForwardingResultSet<decltype(test)> rs{radius * radius, static_cast<std::uint32_t>(i), test};
        tree->findNeighbors(rs, q.data(), nanoflann::SearchParams(32, 0, false));
      }
    });
  });
  if (tree || periodicity_.any()) sort_lists(lists);
}

void NeighbourSearch::find(const std::vector<Vec3>& x, NeighbourLists& lists, Real skin) {
  const Real reach = h_ + skin;
  const Real h2 = reach * reach;
  const std::size_t n = x.size();
  if (method_ == NeighbourMethod::grid) {
    fill(n, lists, [&](std::size_t i, auto&& emit) {
      const Vec3 xi = x[i];
      // Branch-free candidate test into a local buffer: about a third of the
      // candidates are neighbours, so a branch here mispredicts often.
      constexpr std::size_t kBuf = 1024;
      std::uint32_t buf[kBuf];
      Real buf_d2[kBuf];
      std::size_t c = 0;
      for_each_image(xi, reach, [&](const Vec3& shift) {
        const Vec3 q = xi + shift;
        grid_.for_each_within(q, reach, [&](std::uint32_t j) {
          const Vec3 d = q - x[j];
          const Real d2 = d.squaredNorm();
          buf[c] = j;
          buf_d2[c] = d2;
          c += static_cast<std::size_t>((d2 < h2) & (j != i));
          if (c == kBuf) {
            for (std::size_t k = 0; k < c; ++k) emit(buf[k], buf_d2[k]);
            c = 0;
          }
        });
      });
      for (std::size_t k = 0; k < c; ++k) emit(buf[k], buf_d2[k]);
    });
    if (periodicity_.any()) sort_lists(lists);
  } else {
    PointCloud cloud{x};
    KdTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree.buildIndex();
    fill(n, lists, [&](std::size_t i, auto&& emit) {
      for_each_image(x[i], reach, [&](const Vec3& shift) {
        const Vec3 q = x[i] + shift;
        ForwardingResultSet<std::remove_reference_t<decltype(emit)>> rs{h2, static_cast<std::uint32_t>(i), emit};
        tree.findNeighbors(rs, q.data(), nanoflann::SearchParams(32, 0, false));
      });
    });
    sort_lists(lists);
  }
}

template <class Within>
void NeighbourSearch::keep(const NeighbourLists& candidates, const std::vector<Vec3>& x, NeighbourLists& lists,
                           Within&& within) const {
  const std::size_t n = candidates.size();
  const std::size_t stride = candidates.stride_;
  lists.stride_ = stride;
  lists.count_.resize(n);
  resize_with_headroom(lists.ids_, n * stride);
  resize_with_headroom(lists.dist_, n * stride);
  const bool periodic = periodicity_.any();
  parallel_blocks(n, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const std::uint32_t* cand = candidates.begin(i);
      const std::uint32_t count = candidates.count_[i];
      std::uint32_t* out = lists.ids_.data() + i * stride;
      float* out_d = lists.dist_.data() + i * stride;
      const Vec3 xi = x[i];
      // Branch-free compaction (most candidates are kept, but which ones is
      // random), in chunks whose kept squared distances wait in a buffer for
      // one vectorised square root.
      constexpr std::uint32_t kChunk = 128;
      Real kept_d2[kChunk];
      std::uint32_t c = 0;
      for (std::uint32_t k0 = 0; k0 < count; k0 += kChunk) {
        const std::uint32_t k1 = std::min(count, k0 + kChunk);
        std::uint32_t kept = 0;
        for (std::uint32_t k = k0; k < k1; ++k) {
          const std::uint32_t j = cand[k];
          const Vec3 d = periodic ? periodicity_.nearest_image(xi - x[j]) : (xi - x[j]).eval();
          const Real d2 = d.squaredNorm();
          out[c + kept] = j;
          kept_d2[kept] = d2;
          kept += static_cast<std::uint32_t>(within(i, j, d2));
        }
        for (std::uint32_t k = 0; k < kept; ++k) out_d[c + k] = static_cast<float>(std::sqrt(kept_d2[k]));
        c += kept;
      }
      lists.count_[i] = c;
    }
  });
}

void NeighbourSearch::keep_within(const NeighbourLists& candidates, const std::vector<Vec3>& x,
                                  NeighbourLists& lists) const {
  const Real h2 = h_ * h_;
  keep(candidates, x, lists, [h2](std::size_t, std::uint32_t, Real d2) { return d2 < h2; });
}

void NeighbourSearch::keep_within(const NeighbourLists& candidates, const std::vector<Vec3>& x,
                                  const std::vector<Real>& support, NeighbourLists& lists) const {
  keep(candidates, x, lists, [&support](std::size_t i, std::uint32_t j, Real d2) {
    const Real hij = 0.5 * (support[i] + support[j]);
    return d2 < hij * hij;
  });
}

// Sorts each list (with its distances) so the summation order of the kd-tree
// search matches the grid search's.
void NeighbourSearch::sort_lists(NeighbourLists& lists) {
  parallel_blocks(lists.size(), [&](std::size_t b, std::size_t e) {
    std::vector<std::pair<std::uint32_t, float>> pairs;
    for (std::size_t i = b; i < e; ++i) {
      std::uint32_t* ids = lists.ids_.data() + i * lists.stride_;
      float* dist = lists.dist_.data() + i * lists.stride_;
      pairs.clear();
      for (std::uint32_t k = 0; k < lists.count_[i]; ++k) pairs.emplace_back(ids[k], dist[k]);
      std::sort(pairs.begin(), pairs.end());
      for (std::uint32_t k = 0; k < lists.count_[i]; ++k) {
        ids[k] = pairs[k].first;
        dist[k] = pairs[k].second;
      }
    }
  });
}

NeighbourLists brute_force_neighbours(const std::vector<Vec3>& x, Real support) {
  std::vector<std::vector<std::uint32_t>> all(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = 0; j < x.size(); ++j)
      if (i != j && (x[i] - x[j]).squaredNorm() < support * support) all[i].push_back(std::uint32_t(j));
  return NeighbourLists::from_lists(all);
}

NeighbourLists NeighbourLists::from_lists(const std::vector<std::vector<std::uint32_t>>& lists) {
  NeighbourLists out;
  out.stride_ = 1;
  for (const auto& l : lists) out.stride_ = std::max(out.stride_, l.size());
  out.count_.resize(lists.size());
  out.ids_.assign(lists.size() * out.stride_, 0);
  out.dist_.assign(lists.size() * out.stride_, 0.0f);  // not known here
  for (std::size_t i = 0; i < lists.size(); ++i) {
    out.count_[i] = static_cast<std::uint32_t>(lists[i].size());
    std::copy(lists[i].begin(), lists[i].end(), out.ids_.begin() + i * out.stride_);
  }
  return out;
}

}  // namespace bakesim::sph
