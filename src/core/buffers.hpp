#pragma once
// Buffers that grow during a run without taking memory in the step that grows them.
#include <cstddef>
#include <vector>

namespace bakesim {

// Resizes v to `size`; when that needs more than its capacity, reserves half as
// much again first, so a later growth by up to a half takes no memory from the
// heap (issue 25: no allocation in a step). For per-pair buffers laid out in a
// neighbour-list stride that grows by a quarter when the most-neighboured
// particle outgrows it (a dough compressing as it bakes).
template <class T>
void resize_with_headroom(std::vector<T>& v, std::size_t size) {
  if (size > v.capacity()) v.reserve(size + size / 2);
  v.resize(size);
}

}  // namespace bakesim
