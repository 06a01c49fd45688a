#pragma once
// Surface mesh files: binary PLY with normals, vertex colours and UVs (s, t),
// and Wavefront OBJ + MTL with vertex colours (the common "v x y z r g b"
// extension), UVs, normals and the gradient texture as map_Kd.
#include <string>

#include "io/image.hpp"
#include "surface/surface.hpp"

namespace bakesim {

std::string encode_mesh_ply(const surface::SurfaceMesh& mesh);
std::string encode_mesh_obj(const surface::SurfaceMesh& mesh, const std::string& mtl_file, const std::string& material);
std::string encode_mtl(const std::string& material, const std::string& texture_file);

// The thesis's diagonal gradient texture (4.4): texel (u, v) has the palette
// colour at (u + v)/2, so a vertex with U = V = value shows palette(value).
Image gradient_texture(surface::Palette palette, int size = 256);

}  // namespace bakesim
