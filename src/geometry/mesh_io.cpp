#include "geometry/mesh_io.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/errors.hpp"

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

// ---- PLY -------------------------------------------------------------------
enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

PlyType parse_ply_type(const std::string& s, const std::string& path) {
  if (s == "char" || s == "int8") return PlyType::i8;
  if (s == "uchar" || s == "uint8") return PlyType::u8;
  if (s == "short" || s == "int16") return PlyType::i16;
  if (s == "ushort" || s == "uint16") return PlyType::u16;
  if (s == "int" || s == "int32") return PlyType::i32;
  if (s == "uint" || s == "uint32") return PlyType::u32;
  if (s == "float" || s == "float32") return PlyType::f32;
  if (s == "double" || s == "float64") return PlyType::f64;
  throw InputError(path, "unknown PLY property type '" + s + "'");
}

int ply_size(PlyType t) {
  switch (t) {
    case PlyType::i8: case PlyType::u8: return 1;
    case PlyType::i16: case PlyType::u16: return 2;
    case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
    case PlyType::f64: return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::f32;
  bool is_list = false;
  PlyType count_type = PlyType::u8;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> props;
};

class PlyReader {
 public:
  PlyReader(std::istream& in, bool binary, bool big_endian, const std::string& path)
      : in_(in), binary_(binary), swap_(big_endian != (std::endian::native == std::endian::big)), path_(path) {}

  double read(PlyType t) {
    if (!binary_) {
      double v;
      if (!(in_ >> v)) throw InputError(path_, "PLY body ends early or holds a non-number");
      return v;
    }
    unsigned char buf[8];
    const int n = ply_size(t);
    if (!in_.read(reinterpret_cast<char*>(buf), n)) throw InputError(path_, "PLY body ends early");
    if (swap_) std::reverse(buf, buf + n);
    switch (t) {
      case PlyType::i8: { std::int8_t v; std::memcpy(&v, buf, 1); return v; }
      case PlyType::u8: return buf[0];
      case PlyType::i16: { std::int16_t v; std::memcpy(&v, buf, 2); return v; }
      case PlyType::u16: { std::uint16_t v; std::memcpy(&v, buf, 2); return v; }
      case PlyType::i32: { std::int32_t v; std::memcpy(&v, buf, 4); return v; }
      case PlyType::u32: { std::uint32_t v; std::memcpy(&v, buf, 4); return v; }
      case PlyType::f32: { float v; std::memcpy(&v, buf, 4); return v; }
      case PlyType::f64: { double v; std::memcpy(&v, buf, 8); return v; }
    }
    return 0;
  }

 private:
  std::istream& in_;
  bool binary_;
  bool swap_;
  const std::string& path_;
};

}  // namespace

TriangleMesh load_ply(const std::string& path) {
  check_readable(path);
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0) throw InputError(path, "not a PLY file (first line is not 'ply')");
  bool binary = false, big = false;
  std::vector<PlyElement> elements;
  bool header_done = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      std::string fmt;
      ls >> fmt;
      if (fmt == "ascii") binary = false;
      else if (fmt == "binary_little_endian") { binary = true; big = false; }
      else if (fmt == "binary_big_endian") { binary = true; big = true; }
      else throw InputError(path, "unknown PLY format '" + fmt + "'");
    } else if (word == "element") {
      PlyElement e;
      ls >> e.name >> e.count;
      if (!ls) throw InputError(path, "malformed PLY element line: " + line);
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw InputError(path, "PLY property before any element");
      PlyProperty p;
      std::string t;
      ls >> t;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it >> p.name;
        p.is_list = true;
        p.count_type = parse_ply_type(ct, path);
        p.type = parse_ply_type(it, path);
      } else {
        p.type = parse_ply_type(t, path);
        ls >> p.name;
      }
      elements.back().props.push_back(p);
    } else if (word == "end_header") {
      header_done = true;
      break;
    }
  }
  if (!header_done) throw InputError(path, "PLY header has no end_header");

  TriangleMesh mesh;
  PlyReader reader(in, binary, big, path);
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int ix = -1, iy = -1, iz = -1, iface = -1;
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      if (e.props[k].name == "x") ix = int(k);
      if (e.props[k].name == "y") iy = int(k);
      if (e.props[k].name == "z") iz = int(k);
      if (e.props[k].is_list && (e.props[k].name == "vertex_indices" || e.props[k].name == "vertex_index")) iface = int(k);
    }
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0)) throw InputError(path, "PLY vertex element lacks x, y or z");
    if (is_face && iface < 0) throw InputError(path, "PLY face element lacks a vertex_indices list");
    if (e.count > 500'000'000) throw InputError(path, "PLY element count is implausibly large");
    for (std::size_t r = 0; r < e.count; ++r) {
      Vec3 v = Vec3::Zero();
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& p = e.props[k];
        if (p.is_list) {
          const double cnt = reader.read(p.count_type);
          if (!(cnt >= 0 && cnt <= 1e6)) throw InputError(path, "PLY list has an implausible length");
          std::vector<int> idx(static_cast<std::size_t>(cnt));
          for (auto& i : idx) {
            const double value = reader.read(p.type);  // NaN and out-of-range values must not reach the cast
            if (!(value >= 0 && value <= double(std::numeric_limits<int>::max()))) throw InputError(path, "PLY face has an invalid vertex index");
            i = static_cast<int>(value);
          }
          if (is_face && int(k) == iface)
            for (std::size_t q = 1; q + 1 < idx.size(); ++q) mesh.triangles.push_back({idx[0], idx[q], idx[q + 1]});
        } else {
          const double val = reader.read(p.type);
          if (int(k) == ix) v.x() = val;
          if (int(k) == iy) v.y() = val;
          if (int(k) == iz) v.z() = val;
        }
      }
      if (is_vertex) mesh.vertices.push_back(v);
    }
  }
  validate(mesh, path);
  return mesh;
}

TriangleMesh load_obj(const std::string& path) {
  check_readable(path);
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
