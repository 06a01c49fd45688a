#include "geometry/mesh_io.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/errors.hpp"
#include "geometry/ply.hpp"

namespace bakesim {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

void check_readable(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path, "mesh file not found");
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "mesh path is not a regular file");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "mesh file cannot be opened for reading");
}

void validate(const TriangleMesh& m, const std::string& path) {
  if (m.triangles.empty()) throw InputError(path, "mesh has no triangles");
  const int n = static_cast<int>(m.vertices.size());
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      if (t[k] < 0 || t[k] >= n)
        throw InputError(path, "face refers to vertex " + std::to_string(t[k]) + " but the mesh has " +
                                   std::to_string(n) + " vertices");
  for (const Vec3& v : m.vertices)
    if (!v.allFinite()) throw InputError(path, "mesh has a non-finite vertex coordinate");
}

}  // namespace

TriangleMesh load_ply(const std::string& path) {
  check_readable(path);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  const PlyData ply = parse_ply(bytes.str(), path);
  const PlyElement* vertex = ply.find("vertex");
  if (!vertex) throw InputError(path, "PLY file has no vertex element");
  const PlyProperty *x = vertex->find("x"), *y = vertex->find("y"), *z = vertex->find("z");
  if (!x || !y || !z || x->is_list || y->is_list || z->is_list)
    throw InputError(path, "PLY vertex element lacks x, y or z");
  const PlyElement* face = ply.find("face");
  const PlyProperty* indices = face ? face->find("vertex_indices") : nullptr;
  if (face && !indices) indices = face->find("vertex_index");
  if (!indices || !indices->is_list) throw InputError(path, "PLY file has no face element with a vertex_indices list");
  TriangleMesh mesh;
  mesh.vertices.reserve(vertex->count);
  for (std::size_t i = 0; i < vertex->count; ++i) mesh.vertices.emplace_back(x->values[i], y->values[i], z->values[i]);
  for (const auto& polygon : indices->lists) {
    // parse_ply bounds indices to uint32; validate() checks them against the vertex count.
    auto index = [&](std::size_t k) {
      return polygon[k] > std::uint32_t(std::numeric_limits<int>::max()) ? -1 : int(polygon[k]);
    };
    for (std::size_t q = 1; q + 1 < polygon.size(); ++q) mesh.triangles.push_back({index(0), index(q), index(q + 1)});
  }
  validate(mesh, path);
  return mesh;
}

// tinyobjloader reads a coordinate it cannot parse ("nan", "1e999", "x") as
// 0 without a word; every number of every vertex line must be finite (as the
// PLY reader demands).
void check_obj_vertices(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (long number = 1; std::getline(in, line); ++number) {
    if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
    std::istringstream fields(line.substr(2));
    std::string field;
    int count = 0;
    while (fields >> field) {
      char* end = nullptr;
      const double value = std::strtod(field.c_str(), &end);
      if (end != field.c_str() + field.size() || !std::isfinite(value))
        throw InputError(path + ":" + std::to_string(number),
                         "vertex coordinate '" + field.substr(0, 32) + "' is not a finite number");
      ++count;
    }
    if (count < 3) throw InputError(path + ":" + std::to_string(number), "a vertex needs three coordinates");
  }
}

TriangleMesh load_obj(const std::string& path) {
  check_readable(path);
  check_obj_vertices(path);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, cfg)) throw InputError(path, "cannot parse OBJ: " + reader.Error());
  TriangleMesh mesh;
  const auto& v = reader.GetAttrib().vertices;
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) mesh.vertices.emplace_back(v[i], v[i + 1], v[i + 2]);
  for (const auto& shape : reader.GetShapes()) {
    const auto& idx = shape.mesh.indices;
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3)
      mesh.triangles.push_back({idx[i].vertex_index, idx[i + 1].vertex_index, idx[i + 2].vertex_index});
  }
  validate(mesh, path);
  return mesh;
}

TriangleMesh load_mesh(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return load_obj(path);
  if (ext == ".ply") return load_ply(path);
  check_readable(path);
  throw InputError(path, "unsupported mesh format '" + ext + "' (use .obj or .ply)");
}

}  // namespace bakesim
