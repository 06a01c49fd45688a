#pragma once
// `bakesim render RUN_DIR`: pictures of a run's frames into RUN_DIR/render/,
//   mesh-COLOUR-NNNNN.png       the surface (meshed now from the particle frame)
//   particles-COLOUR-NNNNN.png  the particles as spheres with a colour bar
//   MODE-COLOUR.mp4             with --movie, when ffmpeg is installed
//   MODE-COLOUR-strip.png       with --strip: up to six frames side by side and the colour bar
//   MODE-COLOUR-NNNNN-turn-KKK.png  with --turntable N: N views around each frame
//   MODE-COLOUR-cut-AXIS-NNNNN.png  with --cut: the part beyond a plane cut away,
//                               the mesh's cut face coloured by the same quantity
// The scene's `render` section gives the size, a fixed camera, the default
// colour quantity and range, and the look of the domain walls (drawn as an
// open tank: geometry/collider_mesh.hpp, domain_tank_mesh).
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/run_meshes.hpp"
#include "render/render.hpp"

namespace bakesim::render {

struct RenderRunOptions {
  std::vector<int> frames;  // empty: the last frame
  bool all_frames = false;
  std::string mode = "mesh";  // mesh or particles
  // Empty: the scene's render.colour (and render.range), else browning.
  std::string colour;
  std::optional<std::pair<Real, Real>> range;
  surface::SurfaceMethod method = surface::SurfaceMethod::levelset;
  std::optional<int> width, height;  // override the scene's render size
  bool movie = false, strip = false;
  std::string cut;  // "" none; else a cut view (render.hpp, parse_cut_plane): "z", "x=0.01", ...
  // The camera: replaces the scene's render.camera (and the automatic one) in
  // the parts given; a position without look_at looks at the framed bodies' middle.
  std::optional<Vec3> camera_position, look_at;
  std::optional<Real> field_of_view;
  // > 0: this many views of each frame, the camera circling the vertical axis
  // through what it looks at (its height and distance kept), named
  // ...-NNNNN-turn-KKK.png; a movie then turns.
  int turntable = 0;
};

struct RenderRunResult {
  std::vector<std::filesystem::path> images;
  std::optional<std::filesystem::path> movie, strip;
  std::string note;  // e.g. why no movie was made
};

RenderRunResult render_run(const std::filesystem::path& run_dir, const RenderRunOptions& options);

}  // namespace bakesim::render
