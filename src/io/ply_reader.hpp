#pragma once
// A reader for binary little-endian and ASCII PLY files: every element with
// its scalar properties (as double) and list properties (as uint32 lists).
// Malformed input throws InputError naming `where`; it never reads past the
// end of the bytes (the fuzzing target of issue 7 relies on that).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/particles.hpp"
#include "surface/surface.hpp"

namespace bakesim {

struct PlyProperty {
  std::string name;
  bool is_list = false;
  std::vector<double> values;                      // scalar: one per element item
  std::vector<std::vector<std::uint32_t>> lists;   // list: one per element item
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

// A particle frame written by encode_ply back into a particle set: x/y/z as
// "position", name_x/_y/_z triples as vectors, int properties as integers,
// the rest as scalars.
ParticleSet particles_from_ply(const PlyData& ply, const std::string& where);
// A surface mesh written by encode_mesh_ply (or any PLY with vertex x/y/z and
// a face list of triangles or polygons, which are fanned into triangles).
surface::SurfaceMesh mesh_from_ply(const PlyData& ply, const std::string& where);

}  // namespace bakesim
