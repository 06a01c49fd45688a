#pragma once
#include <string>

#include "geometry/mesh.hpp"

namespace bakesim {

// Loads a triangle mesh from an OBJ or PLY (ASCII or binary) file; polygons are
// fan-triangulated. Throws InputError naming the path on any problem.
TriangleMesh load_mesh(const std::string& path);
TriangleMesh load_obj(const std::string& path);
TriangleMesh load_ply(const std::string& path);

}  // namespace bakesim
