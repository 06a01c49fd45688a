#include "render/render.hpp"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "render/plot.hpp"

namespace bakesim::render {

using Vec3f = Eigen::Vector3f;

Camera frame_camera(const Aabb& box, Real aspect, Real fov) {
  Camera c;
  c.field_of_view = fov;
  const Vec3 centre = 0.5 * (box.min + box.max);
  const Real radius = std::max(0.5 * box.extent().norm(), 1e-4);
  const Vec3 view = Vec3(0.55, 0.55, 1.0).normalized();  // front-right, above
  // The bounding sphere fits the narrower of the two fields of view.
  const Real half = 0.5 * fov * kPi / 180.0;
  const Real half_narrow = std::min(half, std::atan(std::tan(half) * aspect));
  c.look_at = centre;
  c.position = centre + view * (radius / std::sin(half_narrow) * 1.02);
  return c;
}

namespace {

// Embree device and scenes, released together: `scene` holds everything a
// camera ray can hit; `opaque` (only made when glass is drawn) everything that
// casts a shadow.
struct RayScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr, opaque = nullptr;
  unsigned ground = RTC_INVALID_GEOMETRY_ID, object = RTC_INVALID_GEOMETRY_ID;
  // A geometry's ID in `opaque` differs from its ID in `scene` once glass is
  // left out: this maps the first to the second.
  std::vector<unsigned> scene_id_of_opaque;
  explicit RayScene(bool with_glass = false) {
    device = rtcNewDevice("threads=1");  // rays are cast from our own parallel loop
    if (!device) throw Error("render: Embree could not create a device");
    scene = rtcNewScene(device);
    if (with_glass) opaque = rtcNewScene(device);
  }
  ~RayScene() {
    if (opaque) rtcReleaseScene(opaque);
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  RTCScene shadow_scene() const { return opaque ? opaque : scene; }
  // The ground's ID in the shadow scene (a cut view never cuts it away).
  unsigned shadow_ground() const {
    if (!opaque) return ground;
    const auto it = std::find(scene_id_of_opaque.begin(), scene_id_of_opaque.end(), ground);
    return it == scene_id_of_opaque.end() ? RTC_INVALID_GEOMETRY_ID : unsigned(it - scene_id_of_opaque.begin());
  }
  unsigned attach(RTCGeometry g, bool casts_shadow) {
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene, g);
    if (opaque && casts_shadow) {
      const unsigned opaque_id = rtcAttachGeometry(opaque, g);
      if (scene_id_of_opaque.size() <= opaque_id) scene_id_of_opaque.resize(opaque_id + 1, RTC_INVALID_GEOMETRY_ID);
      scene_id_of_opaque[opaque_id] = id;
    }
    rtcReleaseGeometry(g);
    return id;
  }
  template <class Index>
  unsigned add_triangles(const std::vector<Vec3f>& v, const std::vector<std::array<Index, 3>>& t,
                         bool casts_shadow = true) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), v.size()));
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), t.size()));
    for (std::size_t i = 0; i < v.size(); ++i) vb[3 * i] = v[i].x(), vb[3 * i + 1] = v[i].y(), vb[3 * i + 2] = v[i].z();
    for (std::size_t i = 0; i < t.size(); ++i)
      ib[3 * i] = unsigned(t[i][0]), ib[3 * i + 1] = unsigned(t[i][1]), ib[3 * i + 2] = unsigned(t[i][2]);
    return attach(g, casts_shadow);
  }
  unsigned add_spheres(const std::vector<Vec3>& p, float radius) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), p.size()));
    for (std::size_t i = 0; i < p.size(); ++i)
      vb[4 * i] = float(p[i].x()), vb[4 * i + 1] = float(p[i].y()), vb[4 * i + 2] = float(p[i].z()),
             vb[4 * i + 3] = radius;
    return attach(g, true);
  }
};

bool any_glass(const std::vector<Prop>& props) {
  return std::any_of(props.begin(), props.end(), [](const Prop& p) { return p.look == ColliderLook::glass; });
}

// How a look reflects light: its highlight's strength and sharpness, and how
// much of the sky it mirrors (metal).
struct LookShading {
  float specular, exponent, mirror;
};
LookShading look_shading(ColliderLook look) {
  switch (look) {
    case ColliderLook::metal: return {0.35f, 40.0f, 0.35f};
    case ColliderLook::ceramic: return {0.3f, 90.0f, 0.06f};
    case ColliderLook::glass: return {0.6f, 150.0f, 0.0f};  // reflects by Fresnel's law instead
    default: return {0.04f, 12.0f, 0.0f};                   // wood, stone: rough
  }
}

// Per-pixel random numbers (a hash, so pixels are independent of scheduling).
struct Random {
  std::uint32_t state;
  Random(std::uint32_t x, std::uint32_t y) : state(x * 1973u + y * 9277u + 26699u) { next(); }
  std::uint32_t next() {
    state ^= state << 13, state ^= state >> 17, state ^= state << 5;
    std::uint32_t z = state * 0x9E3779B9u;
    z ^= z >> 16;
    return z;
  }
  float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }
};

// MurmurHash3's 32-bit finaliser: every input bit reaches every output bit,
// so neighbouring cells get unrelated numbers.
std::uint32_t mix32(std::uint32_t h) {
  h ^= h >> 16, h *= 0x85EBCA6Bu, h ^= h >> 13, h *= 0xC2B2AE35u, h ^= h >> 16;
  return h;
}
// A cell's own random numbers: the finaliser over a Weyl sequence from its hash.
struct CellRandom {
  std::uint32_t state;
  float uniform() { return float(mix32(state += 0x9E3779B9u) >> 8) * (1.0f / 16777216.0f); }
};

// Crumb pores on a cut face (RenderSettings::crumb_cell): a Boolean model
// of spheres of radius R around the points of a Poisson process of one point
// per cell³, drawn from a hash of the cell so that every picture of a body
// shows the same crumb. Its section by any plane covers 1 − exp(−λ 4πR³/3) of
// the plane (λ = 1/cell³), so R = cell (−3 ln(1 − φ)/4π)^⅓ makes the pore
// area share φ. Returns how deep in a pore x lies: 0 on the crumb wall,
// (0, 1] inside a pore (1 at its centre).
float pore_depth(const Vec3f& x, float phi, float cell) {
  if (!(phi > 0) || !(cell > 0)) return 0;
  phi = std::min(phi, 0.85f);
  const float radius = cell * std::cbrt(-3.0f * std::log(1.0f - phi) / (4.0f * float(kPi)));
  const Vec3f q = x / cell;
  const int cx = int(std::floor(q.x())), cy = int(std::floor(q.y())), cz = int(std::floor(q.z()));
  const int reach = int(std::ceil(radius / cell));
  const float no_point = std::exp(-1.0f);  // Poisson(1): P(0)
  float nearest2 = std::numeric_limits<float>::infinity();
  for (int i = cx - reach; i <= cx + reach; ++i)
    for (int j = cy - reach; j <= cy + reach; ++j)
      for (int k = cz - reach; k <= cz + reach; ++k) {
        CellRandom rng{
            mix32(mix32(mix32(std::uint32_t(i)) ^ std::uint32_t(j) * 0x27D4EB2Du) + std::uint32_t(k) * 0x165667B1u)};
        // Poisson(1) points in this cell, by inversion (more than 6: p < 1e-4, left out).
        const float u = rng.uniform();
        float cdf = no_point, term = no_point;
        int count = 0;
        while (u > cdf && count < 6) term /= float(++count), cdf += term;
        for (int n = 0; n < count; ++n) {
          const Vec3f centre(float(i) + rng.uniform(), float(j) + rng.uniform(), float(k) + rng.uniform());
          nearest2 = std::min(nearest2, (centre * cell - x).squaredNorm());
        }
      }
  const float d = std::sqrt(nearest2);
  return d < radius ? 1.0f - d / radius : 0.0f;
}

Vec3f srgb_to_linear(const std::array<std::uint8_t, 3>& c) {
  auto f = [](std::uint8_t v) { return std::pow(v / 255.0f, 2.2f); };
  return {f(c[0]), f(c[1]), f(c[2])};
}
std::uint8_t linear_to_srgb(float v) {
  v = v * (1.0f + v / 4.0f) / (1.0f + v);  // gentle highlight roll-off (white at 2)
  return std::uint8_t(std::lround(255.0f * std::pow(std::clamp(v, 0.0f, 1.0f), 1.0f / 2.2f)));
}

void orthonormal_basis(const Vec3f& n, Vec3f& t, Vec3f& b) {
  t = (std::abs(n.x()) > 0.5f ? Vec3f(0, 1, 0) : Vec3f(1, 0, 0)).cross(n).normalized();
  b = n.cross(t);
}

bool occluded(RTCScene scene, const Vec3f& o, const Vec3f& d, float far) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay ray{};
  ray.org_x = o.x(), ray.org_y = o.y(), ray.org_z = o.z();
  ray.dir_x = d.x(), ray.dir_y = d.y(), ray.dir_z = d.z();
  ray.tnear = 0, ray.tfar = far, ray.mask = 0xffffffffu, ray.flags = 0, ray.time = 0;
  rtcOccluded1(scene, &ctx, &ray);
  return ray.tfar < 0;
}

// The first hit along o + t d (t < far) that `keep(hit, point)` accepts, passing
// through the others; false when there is none.
template <class Keep>
bool first_hit(RTCScene scene, const Vec3f& o, const Vec3f& d, float far, Keep&& keep, RTCRayHit& rh) {
  float from = 0;
  for (int skipped = 0; skipped < 256; ++skipped) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rh = RTCRayHit{};
    rh.ray.org_x = o.x(), rh.ray.org_y = o.y(), rh.ray.org_z = o.z();
    rh.ray.dir_x = d.x(), rh.ray.dir_y = d.y(), rh.ray.dir_z = d.z();
    rh.ray.tnear = from, rh.ray.tfar = far, rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    if (keep(rh.hit, o + rh.ray.tfar * d)) return true;
    from = std::nextafter(rh.ray.tfar, std::numeric_limits<float>::infinity()) * (1 + 1e-6f);
  }
  return false;
}

// The first hit along o + t d (t < far) that a cut view keeps (the ground is
// never cut away); false when there is none.
bool intersect_kept(RTCScene scene, const Vec3f& o, const Vec3f& d, float far, const CutPlane* cut, unsigned ground,
                    RTCRayHit& rh) {
  return first_hit(
      scene, o, d, far,
      [&](const RTCHit& hit, const Vec3f& point) {
        return !cut || hit.geomID == ground || !cut->removes(point.cast<Real>());
      },
      rh);
}

// Is anything kept between o and o + far d?
bool blocked(RTCScene scene, const Vec3f& o, const Vec3f& d, float far, const CutPlane* cut, unsigned ground) {
  if (!cut) return occluded(scene, o, d, far);
  RTCRayHit rh;
  return intersect_kept(scene, o, d, far, cut, ground, rh);
}

// A prop's triangles in single precision, its bounds, and its Embree geometry id.
struct PlacedProp {
  const Prop* prop;
  Aabb box;
  unsigned id;
};

// Wood: darker bands across the longest side of the prop's box (the grain of
// a board or a rolling pin), gently wavy.
float wood_grain(const Aabb& box, const Vec3f& p) {
  const Vec3 e = box.extent();
  int a = 0;
  for (int k = 1; k < 3; ++k)
    if (e[k] > e[a]) a = k;
  const float length = float(std::max(e[a], 1e-6));
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  const float u = (p[a] - float(box.min[a])) / length;
  const float v = (p[b] - float(box.min[b])) / length + 0.6f * (p[c] - float(box.min[c])) / length;
  const float ring = 0.5f + 0.5f * std::sin(2 * 3.14159265f * (18 * v + 0.4f * std::sin(2 * 3.14159265f * 2.5f * u)));
  return 0.8f + 0.2f * ring;
}

// surface_at(hit, albedo, normal): the object's albedo and shading normal at
// a hit (a template parameter, so the per-sample call is inlined).
template <class SurfaceAt>
Image trace(RayScene& rs, const Aabb& bodies, const RenderSettings& s, const SurfaceAt& surface_at,
            const TextRenderer& text, const ColourBar* bar, const std::string& caption,
            const std::vector<Prop>& props) {
  const Real radius = std::max(0.5 * bodies.extent().norm(), 1e-4);
  // Props, and what the automatic camera frames: the bodies and the parts of
  // props within one body size of them.
  std::vector<PlacedProp> placed;
  std::vector<int> prop_of_geometry;
  const Aabb frame = framing_box(bodies, props);
  Real lowest = bodies.min.y();
  for (const Prop& prop : props) {
    if (prop.look == ColliderLook::hidden || prop.mesh.triangles.empty()) continue;
    std::vector<Vec3f> v;
    v.reserve(prop.mesh.vertices.size());
    Aabb box = Aabb::empty_box();
    for (const Vec3& x : prop.mesh.vertices) v.push_back(x.cast<float>()), box.expand(x);
    const unsigned id = rs.add_triangles(v, prop.mesh.triangles, prop.look != ColliderLook::glass);
    if (prop_of_geometry.size() <= id) prop_of_geometry.resize(id + 1, -1);
    prop_of_geometry[id] = int(placed.size());
    placed.push_back({&prop, box, id});
    lowest = std::min(lowest, box.min.y());
  }
  const float ground_y = float(lowest);
  {
    // A ground plane under everything, large enough to reach the horizon haze.
    const float g = float(60 * radius);
    const Vec3 c = 0.5 * (bodies.min + bodies.max);
    const float cx = float(c.x()), cz = float(c.z()), y = ground_y - float(1e-4 * radius);
    rs.ground = rs.add_triangles(std::vector<Vec3f>{Vec3f(cx - g, y, cz - g), Vec3f(cx + g, y, cz - g),
                                                    Vec3f(cx + g, y, cz + g), Vec3f(cx - g, y, cz + g)},
                                 std::vector<std::array<unsigned, 3>>{{0, 2, 1}, {0, 3, 2}});
  }
  rtcCommitScene(rs.scene);
  if (rs.opaque) rtcCommitScene(rs.opaque);
  const RTCScene shadows = rs.shadow_scene();
  const unsigned shadow_ground = rs.shadow_ground();
  const Real aspect = Real(s.width) / Real(s.height);
  const Camera cam = s.camera ? *s.camera : frame_camera(frame, aspect);
  const Vec3f eye = cam.position.cast<float>();
  const Vec3f forward = (cam.look_at - cam.position).normalized().cast<float>();
  Vec3f right = forward.cross(Vec3f(0, 1, 0));
  if (right.norm() < 1e-6f) right = Vec3f(1, 0, 0);
  right.normalize();
  const Vec3f up = right.cross(forward);
  const float tan_half = float(std::tan(0.5 * cam.field_of_view * kPi / 180.0));
  // Lights placed relative to the camera: key from the upper left, fill from the right. A cut
  // view is lit for its cut face, as a cut loaf is photographed: the key comes from further
  // in front, so the cut (facing the camera) and the top take about the same light, and a
  // pale crumb does not read darker than the brown crust over it.
  const Vec3f key = s.cut ? (-0.45f * right + 0.9f * Vec3f(0, 1, 0) - 0.9f * forward).normalized()
                          : (-0.55f * right + 1.1f * Vec3f(0, 1, 0) - 0.45f * forward).normalized();
  const Vec3f fill = (0.9f * right + 0.35f * Vec3f(0, 1, 0) - 0.6f * forward).normalized();
  const Vec3f key_colour(1.05f, 1.0f, 0.93f), fill_colour(0.22f, 0.24f, 0.28f), sky_colour(0.42f, 0.45f, 0.5f);
  const float eps = float(1e-4 * radius), ao_reach = float(0.6 * radius);
  auto background = [&](const Vec3f& d) -> Vec3f {
    const float t = std::clamp(d.y() * 1.5f, 0.0f, 1.0f);
    return Vec3f(0.93f, 0.93f, 0.92f) * (1 - t) + Vec3f(0.62f, 0.70f, 0.80f) * t;
  };
  constexpr int kMaxGlassLayers = 8;  // a glass funnel over a glass cup: eight faces
  const CutPlane* cut = s.cut ? &*s.cut : nullptr;
  // A back face seen through the cut: the ray crossed the plane inside the
  // solid, so what shows is the cut face there; p and n move onto it.
  const auto cut_face = [&](const Vec3f& origin, const Vec3f& dir, Vec3f& p, Vec3f& n) {
    const Vec3f plane = cut->normal.cast<float>();
    const float along = plane.dot(dir);
    if (std::abs(along) < 1e-8f) return false;
    const float t = (float(cut->offset) - plane.dot(origin)) / along;
    if (!(t >= 0) || !(t <= (p - origin).norm())) return false;
    p = origin + t * dir;
    n = along < 0 ? plane : Vec3f(-plane);
    return true;
  };
  // Is the cut plane's point q inside a body? Then the first body surface along
  // d from q is one of its back faces; props and the ground, which may overlap
  // a body (a cake pressed against its pan), are passed through.
  const auto inside_body = [&](const Vec3f& q, const Vec3f& d) {
    const auto is_body = [&](const RTCHit& hit, const Vec3f&) {
      return hit.geomID != rs.ground && !(hit.geomID < prop_of_geometry.size() && prop_of_geometry[hit.geomID] >= 0);
    };
    RTCRayHit h;
    if (!first_hit(rs.scene, q, d, std::numeric_limits<float>::infinity(), is_body, h)) return false;
    Vec3f albedo, n;
    surface_at(h.hit, albedo, n);
    return n.dot(d) > 0;
  };
  // The cut face's colour at p, darkened inside crumb pores: a pore's far
  // wall is crumb too, in the pore's shade, deepest at its centre.
  const auto crumb_albedo = [&](const Vec3f& p) -> Vec3f {
    const Vec3f albedo = srgb_to_linear(s.cut_colour(p.cast<Real>()));
    if (!s.cut_pore_fraction || !(s.crumb_cell > 0)) return albedo;
    const float depth = pore_depth(p, float(s.cut_pore_fraction(p.cast<Real>())), float(s.crumb_cell));
    return depth > 0 ? albedo * (0.88f - 0.4f * depth * depth) : albedo;
  };
  // A prop or the ground seen through the cut where the ray crossed the plane
  // inside a body first: the body's cut face shows there (the plane is nearer
  // than anything kept); p, n and albedo move onto it.
  const auto body_cut_face = [&](const Vec3f& origin, const Vec3f& dir, float far, Vec3f& p, Vec3f& n, Vec3f& albedo) {
    if (!cut || !s.cut_colour) return false;
    const Vec3f plane = cut->normal.cast<float>();
    const float along = plane.dot(dir);
    if (std::abs(along) < 1e-8f) return false;
    const float t = (float(cut->offset) - plane.dot(origin)) / along;
    if (!(t >= 0 && t < far) || !inside_body(origin + t * dir, dir)) return false;
    p = origin + t * dir;
    n = along < 0 ? plane : Vec3f(-plane);
    albedo = crumb_albedo(p);
    return true;
  };
  Image img(s.width, s.height);
  const int n_side = std::max(1, int(std::lround(std::sqrt(double(s.samples)))));
  constexpr float kSamplesAgree = 0.002f;
  parallel_for(
      std::size_t(s.height),
      [&](std::size_t row) {
        const int y = int(row);
        for (int x = 0; x < s.width; ++x) {
          Random rng{static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y)};
          Vec3f sum = Vec3f::Zero(), first = Vec3f::Zero();
          const int cells = n_side * n_side;
          int taken = 0;
          for (int k = 0; k < cells; ++k) {
            // Opposite corners first: where they agree (open ground, sky, a face in full light), the
            // pixel is done with two samples; the others go on to all of them.
            const int cell = k == 0 ? 0 : k == 1 ? cells - 1 : k - 1;
            const float jx = (float(cell % n_side) + rng.uniform()) / float(n_side),
                        jy = (float(cell / n_side) + rng.uniform()) / float(n_side);
            const float px = (2.0f * (float(x) + jx) / float(s.width) - 1.0f) * tan_half * float(aspect);
            const float py = (1.0f - 2.0f * (float(y) + jy) / float(s.height)) * tan_half;
            const Vec3f dir = (forward + px * right + py * up).normalized();
            Vec3f origin = eye, throughput = Vec3f::Ones(), here = Vec3f::Zero();
            for (int layer = 0;; ++layer) {
              RTCRayHit rh;
              if (!intersect_kept(rs.scene, origin, dir, std::numeric_limits<float>::infinity(), cut, rs.ground, rh)) {
                here += throughput.cwiseProduct(background(dir));
                break;
              }
              // Glass lying on an opaque face (a glass lid on a metal pan's rim, faces
              // coinciding): the opaque face shows, rather than whichever the ray met first.
              if (rs.opaque && rh.hit.geomID < prop_of_geometry.size() && prop_of_geometry[rh.hit.geomID] >= 0 &&
                  placed[std::size_t(prop_of_geometry[rh.hit.geomID])].prop->look == ColliderLook::glass) {
                RTCRayHit under;
                if (intersect_kept(rs.opaque, origin, dir, rh.ray.tfar + 8 * eps, cut, shadow_ground, under)) {
                  under.hit.geomID = rs.scene_id_of_opaque[under.hit.geomID];
                  rh = under;
                }
              }
              Vec3f p = origin + rh.ray.tfar * dir;
              bool ground = rh.hit.geomID == rs.ground;
              const int prop_index = rh.hit.geomID < prop_of_geometry.size() ? prop_of_geometry[rh.hit.geomID] : -1;
              const PlacedProp* prop = prop_index >= 0 ? &placed[std::size_t(prop_index)] : nullptr;
              Vec3f albedo, n;
              bool on_cut_face = false;  // crumb: matte, no highlight
              if ((ground || prop) && body_cut_face(origin, dir, rh.ray.tfar, p, n, albedo)) {
                ground = false, prop = nullptr;  // p, n and albedo: the body's cut face
                on_cut_face = true;
              } else if (ground) {
                albedo = Vec3f(0.78f, 0.76f, 0.73f);
                n = Vec3f(0, 1, 0);
              } else if (prop) {
                albedo = look_albedo(prop->prop->look).cast<float>();
                if (prop->prop->look == ColliderLook::wood) albedo *= wood_grain(prop->box, p);
                n = prop->prop->mesh.normal(rh.hit.primID).cast<float>();  // outward
                if (cut && prop->prop->look != ColliderLook::glass && n.dot(dir) > 0) cut_face(origin, dir, p, n);
                if (n.dot(dir) > 0) n = -n;
              } else {
                surface_at(rh.hit, albedo, n);
                // Seeing the inside of the body from the cut side: its cut face, coloured by the quantity.
                if (cut && n.dot(dir) > 0 && cut_face(origin, dir, p, n) && s.cut_colour) {
                  albedo = crumb_albedo(p);
                  on_cut_face = true;
                }
                if (n.dot(dir) > 0) n = -n;
              }
              const Vec3f h = (key - dir).normalized();
              if (prop && prop->prop->look == ColliderLook::glass) {
                // Glass: the sky reflected by Schlick's Fresnel factor (4% head-on, more at
                // grazing angles, so rims show) and a highlight; the rest goes on through, tinted.
                const LookShading g = look_shading(ColliderLook::glass);
                const Vec3f mirrored = dir - 2 * dir.dot(n) * n;
                const float reflected = 0.04f + 0.96f * std::pow(1.0f - std::min(1.0f, -dir.dot(n)), 5.0f);
                here += throughput.cwiseProduct(
                    reflected * background(mirrored) +
                    Vec3f::Constant(g.specular * std::pow(std::max(0.0f, n.dot(h)), g.exponent)));
                throughput = throughput.cwiseProduct((1 - reflected) * albedo);
                origin = p + 4 * eps * dir;
                if (layer + 1 < kMaxGlassLayers) continue;
                here += throughput.cwiseProduct(background(dir));
                break;
              }
              const Vec3f o = p + eps * n;
              Vec3f t, b;
              orthonormal_basis(key, t, b);
              float visible = 0;
              for (int j = 0; j < s.shadow_samples; ++j) {
                const float a = 6.2831853f * rng.uniform(),
                            r = 0.06f * std::sqrt(rng.uniform());  // soft: a light of ~7°
                const Vec3f l = (key + r * (std::cos(a) * t + std::sin(a) * b)).normalized();
                if (!blocked(shadows, o, l, std::numeric_limits<float>::infinity(), cut, shadow_ground)) visible += 1;
              }
              visible /= float(std::max(1, s.shadow_samples));
              Vec3f nt, nb;
              orthonormal_basis(n, nt, nb);
              float open = 0;
              for (int j = 0; j < s.occlusion_samples; ++j) {
                const float a = 6.2831853f * rng.uniform(), r2 = rng.uniform(), r = std::sqrt(r2);
                const Vec3f d = (r * std::cos(a) * nt + r * std::sin(a) * nb + std::sqrt(1 - r2) * n).normalized();
                if (!blocked(shadows, o, d, ao_reach, cut, shadow_ground)) open += 1;
              }
              open = s.occlusion_samples > 0 ? open / float(s.occlusion_samples) : 1.0f;
              Vec3f light = key_colour * (std::max(0.0f, n.dot(key)) * visible) +
                            fill_colour * std::max(0.0f, n.dot(fill)) + sky_colour * ((0.6f + 0.4f * n.y()) * open);
              Vec3f c = albedo.cwiseProduct(light);
              if (ground) {
                const float haze =
                    1.0f -
                    std::exp(-float((p - 0.5f * (bodies.min + bodies.max).cast<float>()).norm() / (12.0 * radius)));
                c = c * (1 - haze) + background(dir) * haze;
              } else if (prop) {
                const LookShading l = look_shading(prop->prop->look);
                const Vec3f mirrored = dir - 2 * dir.dot(n) * n;
                c += l.mirror * open * albedo.cwiseProduct(background(mirrored));
                c += Vec3f::Constant(l.specular * visible * std::pow(std::max(0.0f, n.dot(h)), l.exponent));
              } else if (!on_cut_face) {
                c += Vec3f::Constant(0.12f * visible * std::pow(std::max(0.0f, n.dot(h)), 30.0f));
              }
              here += throughput.cwiseProduct(c);
              break;
            }
            sum += here;
            ++taken;
            if (k == 0) first = here;
            // Within 0.002 of linear radiance (about half a level of the 8-bit output at mid grey).
            if (k == 1 && (here - first).cwiseAbs().maxCoeff() < kSamplesAgree) break;
          }
          sum /= float(taken);
          img.set(x, y, {linear_to_srgb(sum.x()), linear_to_srgb(sum.y()), linear_to_srgb(sum.z())});
        }
      },
      1);
  if (bar) draw_colour_bar(img, *bar, text);
  if (!caption.empty()) text.draw(img, 16, 30, caption, 18, {30, 30, 30});
  return img;
}

}  // namespace

void draw_colour_bar(Image& img, const ColourBar& bar, const TextRenderer& text) {
  const bool per_food = bar.palette == surface::Palette::baking && !bar.raws.empty();
  const int columns = per_food ? int(bar.raws.size()) : 1;
  const int width = std::clamp(8 * columns, 22, 48);
  const int x0 = img.width - 110, x1 = x0 + width, y0 = img.height / 5, y1 = img.height * 4 / 5;
  for (int y = y0; y <= y1; ++y) {
    const double t = double(y1 - y) / double(y1 - y0);
    for (int food = 0; food < columns; ++food) {
      const auto c = per_food ? surface::baking_colour(bar.raws[food], t) : surface::palette_colour(bar.palette, t);
      // Column `food` spans the pixels x with (x − x0) columns / (width + 1) == food.
      const int from = x0 + (food * (width + 1) + columns - 1) / columns,
                to = x0 + ((food + 1) * (width + 1) - 1) / columns;
      for (int x = from; x <= to; ++x) img.set(x, y, c);
    }
  }
  for (int y = y0 - 1; y <= y1 + 1; ++y) img.set(x0 - 1, y, {40, 40, 40}), img.set(x1 + 1, y, {40, 40, 40});
  for (int x = x0 - 1; x <= x1 + 1; ++x) img.set(x, y0 - 1, {40, 40, 40}), img.set(x, y1 + 1, {40, 40, 40});
  const auto ticks = nice_ticks(bar.low, bar.high, 5);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1;
  const int decimals = std::max(0, int(-std::floor(std::log10(step) + 1e-9)));
  for (double t : ticks) {
    if (t < bar.low - 1e-9 * step || t > bar.high + 1e-9 * step) continue;
    const int y = y1 - int(std::lround((t - bar.low) / (bar.high - bar.low) * (y1 - y0)));
    for (int x = x1 + 1; x <= x1 + 6; ++x) img.set(x, y, {40, 40, 40});
    text.draw(img, x1 + 9, y + 5, fmt::format("{:.{}f}", t, std::min(decimals, 6)), 14, {30, 30, 30});
  }
  text.draw(img, (x0 + x1) / 2, y0 - 14, bar.label, 15, {30, 30, 30}, Align::centre);
}

CutPlane parse_cut_plane(const std::string& text, const Aabb& bodies) {
  const auto eq = text.find('=');
  const std::string axis = text.substr(0, eq);
  const int k = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
  if (k < 0) throw InputError("render --cut", "'" + text + "': give x, y or z, or AXIS=VALUE in metres (e.g. z=0.01)");
  CutPlane cut;
  cut.normal = Vec3::Unit(k);
  cut.offset = 0.5 * (bodies.min[k] + bodies.max[k]);
  if (eq != std::string::npos) {
    const std::string value = text.substr(eq + 1);
    std::size_t used = 0;
    try {
      cut.offset = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != value.size() || !std::isfinite(cut.offset))
      throw InputError("render --cut", "'" + text + "': the value after = must be a number of metres");
  }
  return cut;
}

Aabb framing_box(const Aabb& bodies, const std::vector<Prop>& props) {
  Aabb frame = bodies, near = bodies;
  near.min.array() -= bodies.extent().maxCoeff();
  near.max.array() += bodies.extent().maxCoeff();
  for (const Prop& prop : props) {
    if (!prop.frame || prop.look == ColliderLook::hidden) continue;
    Aabb box = Aabb::empty_box();
    for (const Vec3& x : prop.mesh.vertices) box.expand(x);
    const Aabb clipped{box.min.cwiseMax(near.min), box.max.cwiseMin(near.max)};
    if ((clipped.min.array() <= clipped.max.array()).all()) frame.expand(clipped.min), frame.expand(clipped.max);
  }
  return frame;
}

Image render_mesh(const surface::SurfaceMesh& mesh, const RenderSettings& s, const TextRenderer& text,
                  const ColourBar* bar, const std::string& caption, const std::vector<Prop>& props) {
  if (mesh.triangles.empty()) throw InputError("render", "the mesh is empty: nothing to draw");
  RayScene rs(any_glass(props));
  rs.object = rs.add_triangles(mesh.vertices, mesh.triangles);
  Aabb box = Aabb::empty_box();
  for (const auto& v : mesh.vertices) box.expand(v.cast<Real>());
  const bool colours = mesh.colours.size() == mesh.vertices.size();
  const bool normals = mesh.normals.size() == mesh.vertices.size();
  const auto surface_at = [&](const RTCHit& hit, Vec3f& albedo, Vec3f& n) {
    const auto& t = mesh.triangles[hit.primID];
    const float w0 = 1 - hit.u - hit.v;
    if (colours)
      albedo = w0 * srgb_to_linear(mesh.colours[t[0]]) + hit.u * srgb_to_linear(mesh.colours[t[1]]) +
               hit.v * srgb_to_linear(mesh.colours[t[2]]);
    else
      albedo = Vec3f(0.7f, 0.7f, 0.7f);
    if (normals)
      n = (w0 * mesh.normals[t[0]] + hit.u * mesh.normals[t[1]] + hit.v * mesh.normals[t[2]]).normalized();
    else
      n = Vec3f(hit.Ng_x, hit.Ng_y, hit.Ng_z).normalized();
  };
  return trace(rs, box, s, surface_at, text, bar, caption, props);
}

Image render_particles(const ParticleView& pv, const RenderSettings& s, const TextRenderer& text, const ColourBar* bar,
                       const std::string& caption, const std::vector<Prop>& props) {
  if (pv.position.empty()) throw InputError("render", "the frame has no particles: nothing to draw");
  RayScene rs(any_glass(props));
  rs.object = rs.add_spheres(pv.position, float(pv.radius));
  Aabb box = Aabb::empty_box();
  for (const auto& p : pv.position) box.expand(p);
  box.min.array() -= pv.radius;
  box.max.array() += pv.radius;
  const auto surface_at = [&](const RTCHit& hit, Vec3f& albedo, Vec3f& n) {
    albedo = hit.primID < pv.colour.size() ? srgb_to_linear(pv.colour[hit.primID]) : Vec3f(0.7f, 0.7f, 0.7f);
    n = Vec3f(hit.Ng_x, hit.Ng_y, hit.Ng_z).normalized();
  };
  return trace(rs, box, s, surface_at, text, bar, caption, props);
}

}  // namespace bakesim::render
