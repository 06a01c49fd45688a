#pragma once
// Appending plain values to a byte string (little-endian host) for the binary
// file writers.
#include <cstring>
#include <string>

namespace bakesim {

template <class T>
void put_bytes(std::string& out, T v) {
  char buf[sizeof(T)];
  std::memcpy(buf, &v, sizeof(T));
  out.append(buf, sizeof(T));
}

}  // namespace bakesim
