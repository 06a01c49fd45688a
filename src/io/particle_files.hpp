#pragma once
// Particle frame formats. Every exported attribute of the particle set is
// written: vectors as three float components (PLY: name_x/_y/_z; VTU: a
// 3-component array), scalars as float, integers as int32.
#include <string>
#include <vector>

#include "core/particles.hpp"

namespace bakesim {

// Binary little-endian PLY with one vertex element.
std::string encode_ply(const ParticleSet& particles);
// VTK XML UnstructuredGrid (one vertex cell per particle), raw appended data.
std::string encode_vtu(const ParticleSet& particles);

struct PvdEntry {
  double time;
  std::string file;  // relative to the .pvd
};
std::string encode_pvd(const std::vector<PvdEntry>& entries);

}  // namespace bakesim
