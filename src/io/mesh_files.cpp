#include "io/mesh_files.hpp"

#include <fmt/format.h>

#include "io/binary.hpp"

#include <cstring>

namespace bakesim {

std::string encode_mesh_ply(const surface::SurfaceMesh& m) {
  const bool colours = m.colours.size() == m.vertices.size();
  const bool uv = m.uv.size() == m.vertices.size();
  const bool normals = m.normals.size() == m.vertices.size();
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment bakesim surface mesh\n";
  out += fmt::format("element vertex {}\n", m.vertices.size());
  out += "property float x\nproperty float y\nproperty float z\n";
  if (normals) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (colours) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (uv) out += "property float s\nproperty float t\n";
  out += fmt::format("element face {}\nproperty list uchar int vertex_indices\nend_header\n", m.triangles.size());
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) put_bytes(out, m.vertices[i][k]);
    if (normals)
      for (int k = 0; k < 3; ++k) put_bytes(out, m.normals[i][k]);
    if (colours)
      for (int k = 0; k < 3; ++k) put_bytes(out, m.colours[i][std::size_t(k)]);
    if (uv) put_bytes(out, m.uv[i]), put_bytes(out, m.uv[i]);
  }
  for (const auto& t : m.triangles) {
    put_bytes(out, std::uint8_t(3));
    for (auto v : t) put_bytes(out, std::int32_t(v));
  }
  return out;
}

std::string encode_mesh_obj(const surface::SurfaceMesh& m, const std::string& mtl_file, const std::string& material) {
  const bool colours = m.colours.size() == m.vertices.size();
  const bool uv = m.uv.size() == m.vertices.size();
  const bool normals = m.normals.size() == m.vertices.size();
  std::string out = "# bakesim surface mesh\n";
  if (!mtl_file.empty()) out += fmt::format("mtllib {}\nusemtl {}\n", mtl_file, material);
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    const auto& v = m.vertices[i];
    if (colours)
      out += fmt::format("v {:.6g} {:.6g} {:.6g} {:.4f} {:.4f} {:.4f}\n", v.x(), v.y(), v.z(), m.colours[i][0] / 255.0,
                         m.colours[i][1] / 255.0, m.colours[i][2] / 255.0);
    else
      out += fmt::format("v {:.6g} {:.6g} {:.6g}\n", v.x(), v.y(), v.z());
  }
  if (uv)
    for (float u : m.uv) out += fmt::format("vt {:.5f} {:.5f}\n", u, u);
  if (normals)
    for (const auto& n : m.normals) out += fmt::format("vn {:.5f} {:.5f} {:.5f}\n", n.x(), n.y(), n.z());
  for (const auto& t : m.triangles) {
    out += 'f';
    for (auto v : t) {
      const std::uint32_t k = v + 1;
      if (uv && normals)
        out += fmt::format(" {}/{}/{}", k, k, k);
      else if (uv)
        out += fmt::format(" {}/{}", k, k);
      else if (normals)
        out += fmt::format(" {}//{}", k, k);
      else
        out += fmt::format(" {}", k);
    }
    out += '\n';
  }
  return out;
}

std::string encode_mtl(const std::string& material, const std::string& texture_file) {
  return fmt::format(
      "# bakesim surface material\nnewmtl {}\nKa 0 0 0\nKd 1 1 1\nKs 0.05 0.05 0.05\nNs 20\nd 1\nillum 2\nmap_Kd {}\n",
      material, texture_file);
}

Image gradient_texture(surface::Palette palette, int size) {
  Image img(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size, v = 1.0 - (y + 0.5) / size;  // image rows run top-down, v bottom-up
      img.set(x, y, surface::palette_colour(palette, surface::value_of_colour_coordinate(0.5 * (u + v))));
    }
  return img;
}

}  // namespace bakesim
