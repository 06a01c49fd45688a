#pragma once
// Particle frames and surface meshes from PLY data (geometry/ply.hpp).
#include <string>

#include "core/particles.hpp"
#include "geometry/ply.hpp"
#include "surface/surface.hpp"

namespace bakesim {

// A particle frame written by encode_ply back into a particle set: x/y/z as
// "position", name_x/_y/_z triples as vectors, int properties as integers,
// the rest as scalars.
ParticleSet particles_from_ply(const PlyData& ply, const std::string& where);
// A surface mesh written by encode_mesh_ply (or any PLY with vertex x/y/z and
// a face list of triangles or polygons, which are fanned into triangles).
surface::SurfaceMesh mesh_from_ply(const PlyData& ply, const std::string& where);

}  // namespace bakesim
