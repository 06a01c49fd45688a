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

// The particle frame formats a scene can ask for (output.particles), as a
// table: a new format is a row here and a name in the schema's enum.
struct ParticleFormat {
  const char* name;                           // as in output.particles
  const char* extension;                      // ".ply"
  std::string (*encode)(const ParticleSet&);  // the whole file
  bool paraview_series;                       // listed in particles.pvd
};
const std::vector<ParticleFormat>& particle_formats();

struct PvdEntry {
  double time;
  std::string file;  // relative to the .pvd
};
std::string encode_pvd(const std::vector<PvdEntry>& entries);

}  // namespace bakesim
