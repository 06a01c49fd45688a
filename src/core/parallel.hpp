#pragma once
// Parallel loops over index ranges (oneTBB underneath) and reductions whose
// result does not depend on the number of threads: the range is cut into
// fixed-size chunks independent of the thread count, each chunk is reduced
// sequentially, and the chunk results are combined in order.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace bakesim {

template <class Fn>
void parallel_for(std::size_t n, Fn&& fn, std::size_t grain = 256) {
  if (n == 0) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
  });
}

// Calls fn(begin, end) on contiguous blocks; for loops that keep per-block scratch.
template <class Fn>
void parallel_blocks(std::size_t n, Fn&& fn, std::size_t grain = 256) {
  if (n == 0) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) { fn(r.begin(), r.end()); });
}

inline constexpr std::size_t kReductionChunk = 4096;
// Chunk results of up to this many chunks (a million items) stay on the
// stack: a reduction inside a step allocates nothing.
inline constexpr std::size_t kStackChunks = 256;

// Deterministic reduction. `chunk_fn(begin, end) -> T` reduces one chunk;
// `combine(T, T) -> T` merges two chunk results, always in index order.
template <class T, class ChunkFn, class Combine>
T deterministic_reduce(std::size_t n, T identity, ChunkFn&& chunk_fn, Combine&& combine) {
  const std::size_t chunks = (n + kReductionChunk - 1) / kReductionChunk;
  auto reduce_into = [&](T* partial) {
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      const std::size_t b = c * kReductionChunk;
      const std::size_t e = std::min(n, b + kReductionChunk);
      partial[c] = chunk_fn(b, e);
    });
    T result = identity;
    for (std::size_t c = 0; c < chunks; ++c) result = combine(result, partial[c]);
    return result;
  };
  if constexpr (std::is_default_constructible_v<T>) {
    if (chunks <= kStackChunks) {
      std::array<T, kStackChunks> partial;
      return reduce_into(partial.data());
    }
  }
  std::vector<T> partial(chunks, identity);
  return reduce_into(partial.data());
}

// Σ term(i) over [0, n) of any type with + (a number, a vector), starting
// from `zero`, summed in the same order on any thread count.
template <class T, class Term>
T deterministic_sum_of(std::size_t n, const T& zero, Term&& term) {
  return deterministic_reduce(
      n, zero,
      [&](std::size_t b, std::size_t e) {
        T sum = zero;
        for (std::size_t i = b; i < e; ++i) sum += term(i);
        return sum;
      },
      [](const T& a, const T& b) { return T(a + b); });
}

// Σ term(i) over [0, n) in double precision.
template <class Term>
double deterministic_sum(std::size_t n, Term&& term) {
  return deterministic_sum_of(n, 0.0, term);
}

}  // namespace bakesim
