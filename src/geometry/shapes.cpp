#include "geometry/shapes.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace bakesim {

MeshShape::MeshShape(TriangleMesh mesh) : mesh_(std::move(mesh)) {
  bounds_ = mesh_.bounds();
  const Vec3 ext = bounds_.extent();
  cell_ = std::max({ext.y(), ext.z(), 1e-9}) / 64.0;
  ny_ = std::max(1, int(std::ceil(ext.y() / cell_)) + 1);
  nz_ = std::max(1, int(std::ceil(ext.z() / cell_)) + 1);
  rows_.assign(std::size_t(ny_) * nz_, {});
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    Aabb b = Aabb::empty_box();
    for (int k = 0; k < 3; ++k) b.expand(mesh_.vertices[mesh_.triangles[t][k]]);
    const int y0 = std::max(0, int((b.min.y() - bounds_.min.y()) / cell_));
    const int y1 = std::min(ny_ - 1, int((b.max.y() - bounds_.min.y()) / cell_));
    const int z0 = std::max(0, int((b.min.z() - bounds_.min.z()) / cell_));
    const int z1 = std::min(nz_ - 1, int((b.max.z() - bounds_.min.z()) / cell_));
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y) rows_[std::size_t(y) + std::size_t(ny_) * z].push_back(std::uint32_t(t));
  }
}

bool MeshShape::contains(const Vec3& p) const {
  if (!bounds_.contains(p)) return false;
  const int y = std::min(ny_ - 1, int((p.y() - bounds_.min.y()) / cell_));
  const int z = std::min(nz_ - 1, int((p.z() - bounds_.min.z()) / cell_));
  // A slightly skewed ray avoids counting a hit on a shared edge twice.
  const Vec3 dir(1.0, 1.3e-7, 2.9e-7);
  int crossings = 0;
  for (std::uint32_t t : rows_[std::size_t(y) + std::size_t(ny_) * z]) {
    const auto& tri = mesh_.triangles[t];
    if (intersect_ray_triangle(p, dir, mesh_.vertices[tri[0]], mesh_.vertices[tri[1]], mesh_.vertices[tri[2]]))
      ++crossings;
  }
  return (crossings & 1) != 0;
}

namespace {

struct ContainsVisitor {
  const Vec3& p;
  bool operator()(const BoxShape& b) const {
    return (p.array() >= b.min.array()).all() && (p.array() <= b.max.array()).all();
  }
  bool operator()(const SphereShape& s) const { return (p - s.center).squaredNorm() <= s.radius * s.radius; }
  bool operator()(const CylinderShape& c) const {
    const Vec3 d = p - c.center;
    const Real along = d.dot(c.axis);
    if (std::abs(along) > 0.5 * c.height) return false;
    return (d - along * c.axis).squaredNorm() <= c.radius * c.radius;
  }
  bool operator()(const std::shared_ptr<const MeshShape>& m) const { return m->contains(p); }
  bool operator()(const std::shared_ptr<const ShapeUnion>& u) const {
    for (const Shape& s : u->parts)
      if (contains(s, p)) return true;
    return false;
  }
  bool operator()(const std::shared_ptr<const ShapeDifference>& d) const {
    if (!contains(d->base, p)) return false;
    for (const Shape& s : d->subtract)
      if (contains(s, p)) return false;
    return true;
  }
};

struct BoundsVisitor {
  Aabb operator()(const BoxShape& b) const { return {b.min, b.max}; }
  Aabb operator()(const SphereShape& s) const {
    return {s.center - Vec3::Constant(s.radius), s.center + Vec3::Constant(s.radius)};
  }
  Aabb operator()(const CylinderShape& c) const {
    // Extent of a disc of radius r with unit normal a along axis k: r*sqrt(1 - a_k^2).
    Vec3 disc;
    for (int k = 0; k < 3; ++k) disc[k] = c.radius * std::sqrt(std::max(0.0, 1.0 - c.axis[k] * c.axis[k]));
    const Vec3 half = 0.5 * c.height * c.axis.cwiseAbs() + disc;
    return {c.center - half, c.center + half};
  }
  Aabb operator()(const std::shared_ptr<const MeshShape>& m) const { return m->bounds(); }
  Aabb operator()(const std::shared_ptr<const ShapeUnion>& u) const {
    Aabb b = Aabb::empty_box();
    for (const Shape& s : u->parts) {
      const Aabb p = bounds(s);
      b.expand(p.min);
      b.expand(p.max);
    }
    return b;
  }
  Aabb operator()(const std::shared_ptr<const ShapeDifference>& d) const { return bounds(d->base); }
};

}  // namespace

bool contains(const Shape& s, const Vec3& p) { return std::visit(ContainsVisitor{p}, s); }
Aabb bounds(const Shape& s) { return std::visit(BoundsVisitor{}, s); }

std::vector<Vec3> sample_lattice(const Shape& s, Real spacing) {
  if (!(spacing > 0)) throw Error("sample_lattice: spacing must be positive");
  const Aabb b = bounds(s);
  const Vec3 ext = b.extent();
  const double cells = (ext.x() / spacing + 1) * (ext.y() / spacing + 1) * (ext.z() / spacing + 1);
  if (cells > 2e9) throw Error("sample_lattice: shape is too large for its spacing");
  const int nx = std::max(0, int(std::floor(ext.x() / spacing + 1e-9)));
  const int ny = std::max(0, int(std::floor(ext.y() / spacing + 1e-9)));
  const int nz = std::max(0, int(std::floor(ext.z() / spacing + 1e-9)));
  // Centre the lattice inside the bounding box.
  const Vec3 start = b.min + 0.5 * (ext - spacing * Vec3(nx, ny, nz)) + Vec3::Constant(0.5 * spacing);
  std::vector<Vec3> points;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec3 p = start + spacing * Vec3(i, j, k);
        if (contains(s, p)) points.push_back(p);
      }
  return points;
}

Real volume_estimate(const Shape& s, Real spacing) {
  return Real(sample_lattice(s, spacing).size()) * spacing * spacing * spacing;
}

Real shape_volume(const Shape& s, Real spacing) {
  struct Visitor {
    Real spacing;
    Real operator()(const BoxShape& b) const { return (b.max - b.min).cwiseMax(0.0).prod(); }
    Real operator()(const SphereShape& b) const { return 4.0 / 3.0 * kPi * b.radius * b.radius * b.radius; }
    Real operator()(const CylinderShape& c) const { return kPi * c.radius * c.radius * c.height; }
    Real operator()(const std::shared_ptr<const MeshShape>& m) const { return std::abs(m->mesh().signed_volume()); }
    Real operator()(const std::shared_ptr<const ShapeUnion>& u) const { return fine(Shape(u)); }
    Real operator()(const std::shared_ptr<const ShapeDifference>& d) const { return fine(Shape(d)); }
    Real fine(const Shape& shape) const {
      const Real cells = bounds(shape).extent().prod() / (spacing * spacing * spacing);
      const Real refine = std::clamp(std::cbrt(4e6 / std::max(cells, Real(1))), Real(1), Real(4));
      return volume_estimate(shape, spacing / refine);
    }
  };
  return std::visit(Visitor{spacing}, s);
}

SamplingFill sampling_fill(const Shape& s, const std::vector<Vec3>& points, Real spacing, Real volume) {
  SamplingFill fill;
  fill.volume = volume > 0 ? volume : shape_volume(s, spacing);
  fill.shape_extent = bounds(s).extent();
  if (points.empty()) {
    fill.fraction = 0;
    return fill;
  }
  Aabb box = Aabb::empty_box();
  for (const Vec3& p : points) box.expand(p);
  fill.sampled_extent = box.extent() + Vec3::Constant(spacing);
  fill.fraction = fill.volume > 0 ? Real(points.size()) * spacing * spacing * spacing / fill.volume : 1;
  return fill;
}

FittingSpacing fitting_spacing(const Shape& s, Real spacing, Real volume) {
  const Vec3 extent = bounds(s).extent();
  if (!(volume > 0)) volume = shape_volume(s, spacing);
  FittingSpacing best;
  if (!(volume > 0)) return best;
  for (int axis = 0; axis < 3; ++axis) {
    const Real layers = std::floor(extent[axis] / spacing + 1e-9);
    for (const Real n : {layers, layers + 1}) {
      if (!(n >= 1)) continue;
      // E/n to six significant digits, rounded down, so that the value as printed still lays n layers.
      const Real exact = extent[axis] / n;
      const Real scale = std::pow(Real(10), Real(5) - std::floor(std::log10(exact)));
      const Real fitted = std::floor(exact * scale * (1 + 1e-12)) / scale;
      const Real fill = volume_estimate(s, fitted) / volume;
      if (!(std::abs(fill - 1) <= kSamplingFillTolerance)) continue;
      const Real change = std::abs(fitted - spacing), best_change = std::abs(best.spacing - spacing);
      if (best.spacing == 0 || change < best_change - 1e-12 * spacing ||
          (change <= best_change + 1e-12 * spacing && std::abs(fill - 1) < std::abs(best.fraction - 1)))
        best = {fitted, fill};
    }
  }
  return best;
}

std::string sampling_warning(const std::string& where, const std::string& name, const char* points, std::size_t count,
                             Real spacing, const SamplingFill& fill, const Shape& shape, const SpacingKey& key) {
  if (!(std::abs(fill.fraction - 1) > kSamplingFillTolerance)) return "";
  const Vec3 mm = 1e3 * fill.sampled_extent, shape_mm = 1e3 * fill.shape_extent;
  std::string out = fmt::format(
      "{}: body '{}' is sampled as {:.1f}% of its volume ({} {} of {:g} mm, each standing for a spacing cubed, so "
      "its mass too): the lattice spans {:.1f} x {:.1f} x {:.1f} mm of its {:.1f} x {:.1f} x {:.1f} mm",
      where, name, 100 * fill.fraction, count, points, 1e3 * spacing, mm.x(), mm.y(), mm.z(), shape_mm.x(),
      shape_mm.y(), shape_mm.z());
  if (const FittingSpacing fitted = fitting_spacing(shape, spacing, fill.volume); fitted.spacing > 0) {
    out += fmt::format("; {} {:.6g} would fill {:.1f}%", key.path, fitted.spacing * key.per_spacing,
                       100 * fitted.fraction);
  } else {
    out +=
        "; no spacing a layer from it fills it within 5% (a shell or part a few spacings thin?): a finer one "
        "comes closer";
  }
  return out;
}

}  // namespace bakesim
