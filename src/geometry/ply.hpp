#pragma once
// A reader for PLY files (ASCII, binary little- or big-endian): every element
// with its scalar properties (as double) and list properties (as uint32
// lists). Malformed input throws InputError naming `where`; it never reads
// past the end of the bytes (the fuzzing targets rely on that). Meshes for
// bodies and colliders (mesh_io), particle frames and surface meshes
// (io/ply_reader) are all read through it.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace bakesim {

struct PlyProperty {
  std::string name;
  bool is_list = false;
  std::vector<double> values;                     // scalar: one per element item
  std::vector<std::vector<std::uint32_t>> lists;  // list: one per element item
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  const PlyProperty* find(const std::string& property) const;
};

struct PlyData {
  std::vector<PlyElement> elements;
  const PlyElement* find(const std::string& element) const;
};

PlyData parse_ply(std::string_view bytes, const std::string& where);

}  // namespace bakesim
