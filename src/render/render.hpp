#pragma once
// Pictures (Embree ray casting): a surface mesh shaded with its vertex
// colours, or the particles as spheres coloured by a quantity with a colour
// bar; both over a ground plane with soft shadows from a key light, a fill
// light and sky light with ambient occlusion. The camera frames the bodies
// automatically unless one is given. Pixels are computed independently with a
// per-pixel random sequence, so a picture does not depend on the thread count.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "geometry/colliders.hpp"
#include "geometry/mesh.hpp"
#include "io/image.hpp"
#include "render/text.hpp"
#include "surface/surface.hpp"

namespace bakesim::render {

struct Camera {
  Vec3 position = Vec3(0, 0, 1);
  Vec3 look_at = Vec3::Zero();
  Real field_of_view = 35;  // vertical, degrees
};

// A camera looking at the box from the front-right and above (y up), far
// enough that the whole box fits the picture.
Camera frame_camera(const Aabb& box, Real aspect, Real field_of_view = 35);

// A cut view: everything with normal·x > offset is left out (bodies and
// colliders, not the ground), and where the plane passes through a closed body
// or collider its cut face is drawn, the body's in `cut_colour` at each point.
struct CutPlane {
  Vec3 normal = Vec3::UnitZ();  // unit
  Real offset = 0;
  bool removes(const Vec3& x) const { return normal.dot(x) > offset; }
};
// "x", "y" or "z" (through the middle of `bodies`) or "x=VALUE" (m): the side
// of larger coordinates is cut away. InputError("render --cut", ...) otherwise.
CutPlane parse_cut_plane(const std::string& text, const Aabb& bodies);

struct RenderSettings {
  int width = 1280, height = 720;
  std::optional<Camera> camera;
  std::optional<CutPlane> cut;
  std::function<std::array<std::uint8_t, 3>(const Vec3&)> cut_colour;  // sRGB of the body's cut face at a point
  // The share of the body's volume that is pore gas at a point of its cut face
  // (0–1); empty: a solid face. The cut face then shows pores (crumb_cell).
  std::function<Real(const Vec3&)> cut_pore_fraction;
  // Crumb cells on the cut face: spherical pores, on average one per cube of
  // side `crumb_cell` (m), placed at random (a Boolean model), their radius
  // set so that the face's pore area share equals the pore fraction there
  // (Delesse: area share = volume share on a section). 0: no pores drawn.
  Real crumb_cell = 0.002;
  int samples = 4;            // per pixel (a jittered 2×2 pattern for 4)
  int shadow_samples = 2;     // key-light rays per sample
  int occlusion_samples = 4;  // 2 left visible grain in the shade inside tins and cups
};

struct ColourBar {
  std::string label;
  Real low = 0, high = 1;
  surface::Palette palette = surface::Palette::heat;
  // The baking palette browned from each food's raw colour, a column per food side by side (none: the dough's).
  std::vector<surface::Lab> raws;
};

struct ParticleView {
  std::vector<Vec3> position;
  std::vector<std::array<std::uint8_t, 3>> colour;
  Real radius = 0.005;
};

// The colour bar with its ticks and label, drawn 110 pixels in from the
// picture's right edge, over its middle three fifths; a browning bar of
// several foods is a column per food (22 pixels wide in all, 8 a column from
// three foods on, at most 48), each browning from its raw colour, so a
// column's foot is that food's colour in the picture.
void draw_colour_bar(Image& img, const ColourBar& bar, const TextRenderer& text);

// A collider in the picture (geometry/collider_mesh.hpp): its triangles at the
// frame's pose and what it is made of. Metal, ceramic and wood are opaque
// (wood with a grain along the longest side of its box); each glass face
// reflects the sky by Schlick's Fresnel factor (4% head-on) and lets the rest
// through, slightly tinted; glass casts no shadow. `frame`: the
// automatic camera keeps it in view (as far as it lies near the bodies); planes'
// slabs are not framed.
struct Prop {
  TriangleMesh mesh;
  ColliderLook look = ColliderLook::metal;
  bool frame = true;
};

// What the automatic camera frames: the bodies and the parts of framed props
// within one body size of them.
Aabb framing_box(const Aabb& bodies, const std::vector<Prop>& props);

// The ground plane lies under the lowest body or prop; the automatic camera
// frames the bodies and the parts of props within one body size of them.
Image render_mesh(const surface::SurfaceMesh& mesh, const RenderSettings& settings, const TextRenderer& text,
                  const ColourBar* bar = nullptr, const std::string& caption = "", const std::vector<Prop>& props = {});
Image render_particles(const ParticleView& particles, const RenderSettings& settings, const TextRenderer& text,
                       const ColourBar* bar = nullptr, const std::string& caption = "",
                       const std::vector<Prop>& props = {});

}  // namespace bakesim::render
