#include "surface/surface.hpp"

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

#include <Eigen/Geometry>
#include <nanoflann.hpp>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "surface/crust_colour.hpp"

namespace bakesim::surface {

using Vec1 = Eigen::Matrix<Real, 1, 1>;  // a scalar for the Shepard sums, which also sum colours

SurfaceMethod parse_surface_method(const std::string& name) {
  if (name == "levelset") return SurfaceMethod::levelset;
  if (name == "wyvill") return SurfaceMethod::wyvill;
  throw InputError("surface method", "unknown method '" + name + "' (levelset or wyvill)");
}

std::string to_string(SurfaceMethod m) { return m == SurfaceMethod::levelset ? "levelset" : "wyvill"; }

Real wyvill_interior_value(Real radius_over_spacing) {
  // ∫₀¹ (1 − 4/9 t⁶ + 17/9 t⁴ − 22/9 t²) t² dt = 1/3 − 4/81 + 17/63 − 22/45
  const Real moment = 1.0 / 3.0 - 4.0 / 81.0 + 17.0 / 63.0 - 22.0 / 45.0;
  return 4.0 * kPi * moment * radius_over_spacing * radius_over_spacing * radius_over_spacing;
}

namespace {

// Linear expansion c_i = (ρ0/ρ_i)^{1/3}, kept within a sane range so a stray
// particle cannot blow a sphere up across the scene.
Real linear_expansion(Real density_ratio) { return std::cbrt(std::clamp(density_ratio, 0.5, 8.0)); }

// The particle list OpenVDB's rasteriser reads.
struct SphereList {
  using PosType = openvdb::Vec3R;
  const SurfaceParticles* p;
  Real radius_factor;  // × s
  std::size_t size() const { return p->position.size(); }
  void getPos(std::size_t n, openvdb::Vec3R& xyz) const {
    const Vec3& x = p->position[n];
    xyz = openvdb::Vec3R(x.x(), x.y(), x.z());
  }
  void getPosRad(std::size_t n, openvdb::Vec3R& xyz, openvdb::Real& radius) const {
    getPos(n, xyz);
    radius = radius_factor * p->spacing * linear_expansion(p->density_ratio[n]);
  }
};

openvdb::FloatGrid::Ptr level_set(const SurfaceParticles& particles, const SurfaceOptions& o, Real voxel) {
  // The union of spheres is only a distance near each sphere's surface; the
  // erosion (LevelSetFilter::offset) re-normalises it as it goes.
  auto grid = openvdb::createLevelSet<openvdb::FloatGrid>(voxel, 3.0);
  openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
  raster.setRmin(0.5);  // voxels: keep every particle, even in a coarse grid
  raster.rasterizeSpheres(SphereList{&particles, o.sphere_radius});
  raster.finalize(true);
  Real mean_expansion = 0;
  for (Real r : particles.density_ratio) mean_expansion += linear_expansion(r);
  mean_expansion /= Real(particles.density_ratio.size());
  openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
  filter.offset(float((o.sphere_radius - 0.5) * particles.spacing * mean_expansion));
  for (int i = 0; i < o.smoothing_iterations; ++i) filter.meanCurvature();
  return grid;
}

// Rasterises particles onto Grids float grids: add(accessors, i, ijk, r, b) for
// every voxel centre within b = radius(i) of particle i (r its distance).
// Particles go in fixed chunks, each into grids of its own, summed in chunk
// order: the result does not depend on the thread count.
template <std::size_t Grids, class Radius, class Add>
std::array<openvdb::FloatGrid::Ptr, Grids> rasterise_in_chunks(const SurfaceParticles& particles,
                                                               const openvdb::math::Transform& transform,
                                                               const Radius& radius, const Add& add) {
  const std::size_t n = particles.position.size();
  constexpr std::size_t kChunk = 8192;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  const Real voxel = transform.voxelSize()[0];
  std::vector<std::array<openvdb::FloatGrid::Ptr, Grids>> grids(chunks);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::array<openvdb::FloatGrid::Ptr, Grids>& mine = grids[c];
    std::vector<openvdb::FloatGrid::Accessor> acc;
    for (auto& g : mine) {
      g = openvdb::FloatGrid::create(0.0f);
      g->setTransform(transform.copy());
      acc.push_back(g->getAccessor());
    }
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    for (std::size_t i = c * kChunk; i < end; ++i) {
      const Vec3& x = particles.position[i];
      const Real b = radius(i);
      const Vec3 lo = (x.array() - b) / voxel, hi = (x.array() + b) / voxel;
      for (int k = int(std::ceil(lo.z())); k <= int(std::floor(hi.z())); ++k)
        for (int j = int(std::ceil(lo.y())); j <= int(std::floor(hi.y())); ++j)
          for (int l = int(std::ceil(lo.x())); l <= int(std::floor(hi.x())); ++l) {
            const Real r = (Vec3(l, j, k) * voxel - x).norm();
            if (r < b) add(acc, i, openvdb::Coord(l, j, k), r, b);
          }
    }
  });
  for (std::size_t c = 1; c < chunks; ++c)
    for (std::size_t g = 0; g < Grids; ++g) openvdb::tools::compSum(*grids[0][g], *grids[c][g]);
  return grids[0];
}

// Σ_i φ_W(|x − x_i|, b_i), stored negated so that inside is below the isovalue
// as volume-to-mesh expects.
openvdb::FloatGrid::Ptr wyvill_grid(const SurfaceParticles& particles, const SurfaceOptions& o, Real voxel) {
  const auto transform = openvdb::math::Transform::createLinearTransform(voxel);
  const auto radius = [&](std::size_t i) {
    return (o.wyvill_alpha + o.wyvill_beta * std::clamp(particles.density_ratio[i], 0.5, 8.0)) * particles.spacing;
  };
  return rasterise_in_chunks<1>(particles, *transform, radius,
                                [](auto& acc, std::size_t, const openvdb::Coord& ijk, Real r, Real b) {
                                  acc[0].setValue(ijk, acc[0].getValue(ijk) - float(wyvill_field(r, b)));
                                })[0];
}

Real spline(Real r, Real support);  // below, with the colouring

// The voxel size of a method's grid.
Real voxel_size(const SurfaceParticles& particles, const SurfaceOptions& o) {
  const Real ratio = o.voxel_ratio > 0 ? o.voxel_ratio : (o.method == SurfaceMethod::levelset ? 0.75 : 0.5);
  return ratio * particles.spacing;
}

// Σ_i w_i v_i and Σ_i w_i over the voxels within `support` of each particle,
// w_i = volume_i W(r, support).
std::array<openvdb::FloatGrid::Ptr, 2> weighted_sums(const SurfaceParticles& particles, const std::vector<Real>& value,
                                                     const openvdb::math::Transform& transform, Real support) {
  const Real cell = particles.spacing * particles.spacing * particles.spacing;
  return rasterise_in_chunks<2>(
      particles, transform, [&](std::size_t) { return support; },
      [&](auto& acc, std::size_t i, const openvdb::Coord& ijk, Real r, Real) {
        const Real w = cell * particles.density_ratio[i] * spline(r, support);
        if (!(w > 0)) return;
        acc[0].setValue(ijk, acc[0].getValue(ijk) + float(w * value[i]));
        acc[1].setValue(ijk, acc[1].getValue(ijk) + float(w));
      });
}

}  // namespace

std::string encode_vdb(const SurfaceParticles& particles, const SurfaceOptions& options,
                       const std::vector<VolumeQuantity>& quantities, Real support) {
  if (particles.position.empty()) throw InputError("vdb", "no particles: nothing to write");
  if (particles.density_ratio.size() != particles.position.size())
    throw InputError("vdb", "one density ratio per particle is needed");
  openvdb::initialize();
  SurfaceOptions level = options;
  level.method = SurfaceMethod::levelset;
  openvdb::GridPtrVec grids;
  openvdb::FloatGrid::Ptr surface = level_set(particles, level, voxel_size(particles, level));
  surface->setName("surface");
  surface->setGridClass(openvdb::GRID_LEVEL_SET);
  grids.push_back(surface);
  for (const VolumeQuantity& q : quantities) {
    if (q.value.size() != particles.position.size())
      throw InputError("vdb", "quantity " + q.name + " needs one value per particle");
    auto [num, den] = weighted_sums(particles, q.value, surface->transform(), support);
    // num / den on den's active voxels; num becomes the grid.
    auto a_num = num->getAccessor();
    for (auto it = den->cbeginValueOn(); it; ++it) a_num.setValue(it.getCoord(), a_num.getValue(it.getCoord()) / *it);
    num->setName(q.name);
    num->setGridClass(openvdb::GRID_UNKNOWN);
    if (!q.unit.empty()) num->insertMeta("unit", openvdb::StringMetadata(q.unit));
    grids.push_back(num);
  }
  std::ostringstream out(std::ios_base::binary);
  openvdb::io::Stream(out).write(grids);
  return out.str();
}

SurfaceMesh reconstruct_surface(const SurfaceParticles& particles, const SurfaceOptions& o) {
  SurfaceMesh mesh;
  if (particles.position.empty()) return mesh;
  if (particles.density_ratio.size() != particles.position.size())
    throw InputError("surface", "one density ratio per particle is needed");
  if (!(particles.spacing > 0)) throw InputError("surface", "the particle spacing must be positive");
  openvdb::initialize();
  const Real voxel = voxel_size(particles, o);
  openvdb::FloatGrid::Ptr grid;
  double isovalue = 0;
  if (o.method == SurfaceMethod::levelset) {
    grid = level_set(particles, o, voxel);
  } else {
    grid = wyvill_grid(particles, o, voxel);
    isovalue = -0.5 * wyvill_interior_value(o.wyvill_alpha + o.wyvill_beta);
  }
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*grid, points, triangles, quads, isovalue, 0.0, true);
  mesh.vertices.reserve(points.size());
  for (const auto& p : points) mesh.vertices.emplace_back(p.x(), p.y(), p.z());
  mesh.triangles.reserve(triangles.size() + 2 * quads.size());
  // OpenVDB's polygons wind clockwise seen from outside; ours wind counter-clockwise.
  for (const auto& t : triangles) mesh.triangles.push_back({t[0], t[2], t[1]});
  for (const auto& q : quads) {
    // Split along the shorter diagonal.
    const float d02 = (mesh.vertices[q[0]] - mesh.vertices[q[2]]).squaredNorm();
    const float d13 = (mesh.vertices[q[1]] - mesh.vertices[q[3]]).squaredNorm();
    if (d02 <= d13) {
      mesh.triangles.push_back({q[0], q[2], q[1]});
      mesh.triangles.push_back({q[0], q[3], q[2]});
    } else {
      mesh.triangles.push_back({q[0], q[3], q[1]});
      mesh.triangles.push_back({q[1], q[3], q[2]});
    }
  }
  // Volume-to-mesh winds level sets and plain scalar grids differently; the
  // enclosed volume of a closed mesh is positive exactly when it is wound
  // outward, so that settles it for either.
  Real signed_volume = 0;
  for (const auto& t : mesh.triangles)
    signed_volume +=
        mesh.vertices[t[0]].cast<Real>().dot(mesh.vertices[t[1]].cast<Real>().cross(mesh.vertices[t[2]].cast<Real>()));
  if (signed_volume < 0)
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  compute_normals(mesh);
  return mesh;
}

void compute_normals(SurfaceMesh& m) {
  m.normals.assign(m.vertices.size(), Eigen::Vector3f::Zero());
  for (const auto& t : m.triangles) {
    const Eigen::Vector3f n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    for (auto v : t) m.normals[v] += n;  // area-weighted
  }
  for (auto& n : m.normals) {
    const float len = n.norm();
    n = len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f(0, 1, 0);
  }
}

// ---- colouring --------------------------------------------------------------

// Named, not anonymous: ColourField::Index (a member type of a class with
// linkage) holds them, and in the unity build GCC warns about anonymous types there.
namespace detail {

struct PointCloud {
  const std::vector<Vec3>* pts;
  std::size_t kdtree_get_point_count() const { return pts->size(); }
  Real kdtree_get_pt(std::size_t i, std::size_t d) const { return (*pts)[i][Eigen::Index(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};
using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<Real, PointCloud>, PointCloud, 3, std::size_t>;

}  // namespace detail
using detail::KdTree;
using detail::PointCloud;

namespace {

// Cubic spline kernel with support radius `support` (unnormalised: the sum is
// Shepard-normalised, so the constant cancels).
Real spline(Real r, Real support) {
  const Real q = 2.0 * r / support;
  if (q >= 2) return 0;
  if (q >= 1) return 0.25 * (2 - q) * (2 - q) * (2 - q);
  return 1 - 1.5 * q * q + 0.75 * q * q * q;
}

}  // namespace

struct ColourField::Index {
  PointCloud cloud;
  KdTree tree;
  explicit Index(const std::vector<Vec3>* points)
      : cloud{points}, tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree.buildIndex();
  }
};

ColourField::ColourField(ColourSamples samples, Real support)
    : samples_(std::move(samples)),
      support_(support),
      index_(samples_.position.empty() ? nullptr : std::make_unique<Index>(&samples_.position)) {}

ColourField::~ColourField() = default;

namespace {
constexpr Real kDoughOffset = 0.1, kValueScale = 0.8, kBaseCoordinate = 0.05;  // Eq 4.7's O, the 0.8 and 0.05
Real sample_g(const ColourSamples& s, std::size_t j) {
  const Real offset = (!s.bubble.empty() && s.bubble[j]) ? 0.0 : kDoughOffset;
  return offset + kValueScale * std::clamp(s.value[j], 0.0, 1.0) + kBaseCoordinate;
}
}  // namespace

Real value_of_colour_coordinate(Real u) {
  return std::clamp((u - kDoughOffset - kBaseCoordinate) / kValueScale, Real(0), Real(1));
}

template <class R, class G>
std::optional<R> ColourField::shepard(const Vec3& x, const G& g) const {
  if (!index_) return std::nullopt;
  thread_local std::vector<std::pair<std::size_t, Real>> found;  // the search reuses its storage
  index_->tree.radiusSearch(x.data(), support_ * support_, found, nanoflann::SearchParams(32, 0, false));
  R num = R::Zero();
  Real den = 0;
  for (const auto& f : found) {
    const Real w = samples_.volume[f.first] * spline(std::sqrt(f.second), support_);  // Eq 4.5
    num += w * g(f.first);
    den += w;
  }
  if (den > 0) return R(num / den);
  return std::nullopt;
}

std::size_t ColourField::nearest(const Vec3& x) const {
  std::size_t j = 0;
  Real d2 = 0;
  index_->tree.knnSearch(x.data(), 1, &j, &d2);
  return j;
}

std::optional<Real> ColourField::uv_within(const Vec3& x) const {
  const auto u = shepard<Vec1>(x, [&](std::size_t j) { return Vec1(sample_g(samples_, j)); });
  return u ? std::optional<Real>((*u)(0)) : std::nullopt;
}

std::optional<Lab> ColourField::raw_at(const Vec3& x) const {
  if (!index_ || samples_.raw.size() != samples_.position.size()) return std::nullopt;
  const auto lab = [&](std::size_t j) { return Vec3(samples_.raw[j].L, samples_.raw[j].a, samples_.raw[j].b); };
  const Vec3 c = shepard<Vec3>(x, lab).value_or(lab(nearest(x)));
  return Lab{c.x(), c.y(), c.z()};
}

Real ColourField::uv_at(const Vec3& x) const {
  if (!index_) return 0.05;
  if (const std::optional<Real> u = uv_within(x)) return *u;
  return sample_g(samples_, nearest(x));
}

Real ColourField::value_at(const Vec3& x) const {
  if (!index_) return 0;
  const auto value = [&](std::size_t j) { return std::clamp(samples_.value[j], 0.0, 1.0); };
  if (const auto v = shepard<Vec1>(x, [&](std::size_t j) { return Vec1(value(j)); })) return (*v)(0);
  return value(nearest(x));
}

void assign_uv(SurfaceMesh& mesh, const ColourSamples& s, Real support) {
  mesh.uv.assign(mesh.vertices.size(), 0.05f);
  if (s.position.empty() || mesh.vertices.empty()) return;
  const ColourField field(s, support);
  // The surface's own particles, where the colour is theirs (browning).
  ColourSamples face;
  for (std::size_t j = 0; j < s.face.size() && j < s.position.size(); ++j) {
    if (!s.face[j]) continue;
    face.position.push_back(s.position[j]);
    face.volume.push_back(s.volume[j]);
    face.value.push_back(s.value[j]);
    if (!s.bubble.empty()) face.bubble.push_back(s.bubble[j]);
  }
  const ColourField face_field(std::move(face), support);
  mesh.raw_colour.clear();
  if (s.raw.size() == s.position.size()) mesh.raw_colour.resize(mesh.vertices.size());
  parallel_blocks(
      mesh.vertices.size(),
      [&](std::size_t vb, std::size_t ve) {
        for (std::size_t v = vb; v < ve; ++v) {
          const Vec3 x = mesh.vertices[v].cast<Real>();
          const std::optional<Real> u = face_field.uv_within(x);
          mesh.uv[v] = float(u ? *u : field.uv_at(x));
          if (!mesh.raw_colour.empty()) mesh.raw_colour[v] = *field.raw_at(x);
        }
      },
      1024);
}

std::array<std::uint8_t, 3> palette_colour(Palette p, Real u) {
  u = std::clamp(u, 0.0, 1.0);
  if (p == Palette::baking) return baking_colour(dough_lab(), u);  // the measured crust colour (crust_colour.hpp)
  struct Stop {
    Real at, r, g, b;
  };
  // heat: blue → red.
  static const Stop heat[] = {{0.0, 0.19, 0.25, 0.68},
                              {0.25, 0.27, 0.62, 0.85},
                              {0.5, 0.95, 0.93, 0.75},
                              {0.75, 0.97, 0.55, 0.25},
                              {1.0, 0.70, 0.05, 0.10}};
  int k = 0;
  while (k < 3 && u > heat[k + 1].at) ++k;
  const Real t = (u - heat[k].at) / (heat[k + 1].at - heat[k].at);
  auto mix = [&](Real a, Real b) { return std::uint8_t(std::lround(255.0 * (a + (b - a) * t))); };
  return {mix(heat[k].r, heat[k + 1].r), mix(heat[k].g, heat[k + 1].g), mix(heat[k].b, heat[k + 1].b)};
}

std::array<std::uint8_t, 3> baking_colour(const Lab& raw, Real u) {
  const auto rgb = lab_to_srgb(crust_lab_of_browning(std::clamp(u, 0.0, 1.0), raw));
  return {std::uint8_t(std::lround(255.0 * rgb[0])), std::uint8_t(std::lround(255.0 * rgb[1])),
          std::uint8_t(std::lround(255.0 * rgb[2]))};
}

void colour_vertices(SurfaceMesh& mesh, Palette p) {
  mesh.colours.resize(mesh.vertices.size());
  const bool raw = p == Palette::baking && mesh.raw_colour.size() == mesh.vertices.size();
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Real value = value_of_colour_coordinate(v < mesh.uv.size() ? mesh.uv[v] : 0.0);
    mesh.colours[v] = raw ? baking_colour(mesh.raw_colour[v], value) : palette_colour(p, value);
  }
}

// ---- checks -----------------------------------------------------------------

MeshQuality check_mesh(const SurfaceMesh& m) {
  MeshQuality q;
  // Directed edge counts: a closed oriented 2-manifold has every edge once in
  // each direction.
  std::unordered_map<std::uint64_t, int> directed;
  directed.reserve(m.triangles.size() * 3);
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e) ++directed[key(t[e], t[(e + 1) % 3])];
  for (const auto& [k, count] : directed) {
    const std::uint32_t a = std::uint32_t(k >> 32), b = std::uint32_t(k & 0xffffffffu);
    const auto rev = directed.find(key(b, a));
    const int back = rev == directed.end() ? 0 : rev->second;
    if (a < b || back == 0) {  // count each undirected edge once
      const int total = count + back;
      if (total == 1)
        ++q.boundary_edges;
      else if (total > 2)
        ++q.non_manifold_edges;
      else if (count != 1 || back != 1)
        ++q.misoriented_edges;
    }
  }
  for (const auto& t : m.triangles) {
    const Vec3 a = m.vertices[t[0]].cast<Real>(), b = m.vertices[t[1]].cast<Real>(), c = m.vertices[t[2]].cast<Real>();
    q.volume += a.dot(b.cross(c)) / 6.0;
    q.area += 0.5 * (b - a).cross(c - a).norm();
  }
  return q;
}

namespace {
Real one_sided(const SurfaceMesh& from, const SurfaceMesh& to) {
  std::vector<Vec3> pts(to.vertices.size());
  for (std::size_t i = 0; i < pts.size(); ++i) pts[i] = to.vertices[i].cast<Real>();
  PointCloud cloud{&pts};
  KdTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  Real worst = 0;
  for (const auto& v : from.vertices) {
    const Vec3 x = v.cast<Real>();
    std::size_t idx = 0;
    Real d2 = 0;
    tree.knnSearch(x.data(), 1, &idx, &d2);
    worst = std::max(worst, d2);
  }
  return std::sqrt(worst);
}
}  // namespace

Real hausdorff_distance(const SurfaceMesh& a, const SurfaceMesh& b) {
  if (a.vertices.empty() || b.vertices.empty()) return std::numeric_limits<Real>::infinity();
  return std::max(one_sided(a, b), one_sided(b, a));
}

}  // namespace bakesim::surface
