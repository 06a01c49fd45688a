#pragma once
// What the machine has, for limits checked before anything is allocated.
#include <unistd.h>

#include <cstddef>

namespace bakesim {

// Physical memory in bytes (0 when the system does not say).
inline double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? double(pages) * double(page) : 0.0;
}

}  // namespace bakesim
