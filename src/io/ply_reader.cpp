#include "io/ply_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "core/errors.hpp"

namespace bakesim {

ParticleSet particles_from_ply(const PlyData& ply, const std::string& where) {
  const PlyElement* v = ply.find("vertex");
  if (!v) throw InputError(where, "no vertex element");
  ParticleSet ps;
  ps.resize(v->count);
  auto scalar_of = [&](const std::string& name) -> const std::vector<double>* {
    const PlyProperty* p = v->find(name);
    return p && !p->is_list ? &p->values : nullptr;
  };
  const auto *x = scalar_of("x"), *y = scalar_of("y"), *z = scalar_of("z");
  if (!x || !y || !z) throw InputError(where, "vertex element has no x, y, z");
  auto& pos = ps.add_vector("position", "m");
  for (std::size_t i = 0; i < v->count; ++i) pos[i] = Vec3((*x)[i], (*y)[i], (*z)[i]);
  for (const auto& p : v->properties) {
    if (p.is_list || p.name == "x" || p.name == "y" || p.name == "z") continue;
    const std::string& n = p.name;
    if (n.size() > 2 && n.compare(n.size() - 2, 2, "_x") == 0) {
      const std::string base = n.substr(0, n.size() - 2);
      const auto *py = scalar_of(base + "_y"), *pz = scalar_of(base + "_z");
      if (py && pz && !ps.has(base)) {
        auto& vec = ps.add_vector(base, "");
        for (std::size_t i = 0; i < v->count; ++i) vec[i] = Vec3(p.values[i], (*py)[i], (*pz)[i]);
        continue;
      }
    }
    if (n.size() > 2 && (n.compare(n.size() - 2, 2, "_y") == 0 || n.compare(n.size() - 2, 2, "_z") == 0) &&
        ps.has(n.substr(0, n.size() - 2)))
      continue;
    if (ps.has(n)) continue;
    auto& s = ps.add_scalar(n, "");
    for (std::size_t i = 0; i < v->count; ++i) s[i] = p.values[i];
  }
  return ps;
}

namespace {
// A colour channel; out-of-range values (a float or int channel) are clamped,
// since converting them to uint8 directly is undefined (found by fuzzing).
std::uint8_t byte_of(double v) { return std::uint8_t(std::isfinite(v) ? std::clamp(v, 0.0, 255.0) : 0.0); }
// Doubles beyond float's range would also be undefined to convert.
float float_of(double v) { return float(std::isnan(v) ? v : std::clamp(v, -3.0e38, 3.0e38)); }
}  // namespace

surface::SurfaceMesh mesh_from_ply(const PlyData& ply, const std::string& where) {
  const PlyElement* v = ply.find("vertex");
  const PlyElement* f = ply.find("face");
  if (!v || !f) throw InputError(where, "a mesh needs vertex and face elements");
  const PlyProperty *x = v->find("x"), *y = v->find("y"), *z = v->find("z");
  if (!x || !y || !z || x->is_list || y->is_list || z->is_list)
    throw InputError(where, "vertex element has no x, y, z");
  surface::SurfaceMesh m;
  for (std::size_t i = 0; i < v->count; ++i)
    m.vertices.emplace_back(float_of(x->values[i]), float_of(y->values[i]), float_of(z->values[i]));
  const PlyProperty *r = v->find("red"), *g = v->find("green"), *b = v->find("blue"), *s = v->find("s");
  if (r && g && b && !r->is_list && !g->is_list && !b->is_list)
    for (std::size_t i = 0; i < v->count; ++i)
      m.colours.push_back({byte_of(r->values[i]), byte_of(g->values[i]), byte_of(b->values[i])});
  if (s && !s->is_list)
    for (std::size_t i = 0; i < v->count; ++i) m.uv.push_back(float_of(s->values[i]));
  const PlyProperty* idx = f->find("vertex_indices");
  if (!idx) idx = f->find("vertex_index");
  if (!idx || !idx->is_list) throw InputError(where, "face element has no vertex_indices list");
  for (const auto& poly : idx->lists) {
    for (auto i : poly)
      if (i >= v->count) throw InputError(where, fmt::format("face refers to vertex {} of {}", i, v->count));
    for (std::size_t k = 2; k < poly.size(); ++k) m.triangles.push_back({poly[0], poly[k - 1], poly[k]});
  }
  const PlyProperty *nx = v->find("nx"), *ny = v->find("ny"), *nz = v->find("nz");
  if (nx && ny && nz && !nx->is_list && !ny->is_list && !nz->is_list) {
    for (std::size_t i = 0; i < v->count; ++i)
      m.normals.emplace_back(float_of(nx->values[i]), float_of(ny->values[i]), float_of(nz->values[i]));
  } else {
    surface::compute_normals(m);
  }
  return m;
}

}  // namespace bakesim
