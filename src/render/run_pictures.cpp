#include "render/run_pictures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <Eigen/Geometry>

#include "core/errors.hpp"
#include "geometry/collider_mesh.hpp"
#include "io/files.hpp"

namespace bakesim::render {

namespace fs = std::filesystem;

namespace {

bool has_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string p = path;
  std::size_t start = 0;
  while (start <= p.size()) {
    const std::size_t end = p.find(':', start);
    const fs::path candidate = fs::path(p.substr(start, end - start)) / name;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) return true;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return false;
}

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

RenderRunResult render_run(const fs::path& run_dir, const RenderRunOptions& o) {
  if (o.mode != "mesh" && o.mode != "particles")
    throw InputError("render --mode", "must be mesh or particles, got '" + o.mode + "'");
  const RunDirectory run = open_run(run_dir);
  if (run.frames.empty()) throw InputError(run_dir.string(), "has no particle frames (frames/NNNNN.ply) to render");
  const RunGeometry geometry = run_geometry(run.scene);
  std::vector<int> frames;
  if (o.all_frames) {
    for (const auto& [f, path] : run.frames) frames.push_back(f);
  } else if (o.frames.empty()) {
    frames.push_back(run.frames.rbegin()->first);
  } else {
    for (int f : o.frames) {
      if (!run.frames.count(f))
        throw InputError("render --frame", fmt::format("{} has no frame {} (it has {} to {})", run_dir.string(), f,
                                                       run.frames.begin()->first, run.frames.rbegin()->first));
      frames.push_back(f);
    }
  }
  RenderSettings settings;
  const auto& r = run.scene.contains("render") ? run.scene["render"] : nlohmann::json::object();
  settings.width = o.width.value_or(r.value("width", 1280));
  settings.height = o.height.value_or(r.value("height", 720));
  // The command line's limits, for every caller (the schema checks the scene's render size).
  for (const auto& [option, pixels] : {std::pair{"render --width", o.width}, std::pair{"render --height", o.height}})
    if (pixels && (*pixels < 16 || *pixels > 8192))
      throw InputError(option, fmt::format("{} is outside [16, 8192] pixels", *pixels));
  if (o.range && !(o.range->first < o.range->second))
    throw InputError("render --range", fmt::format("expects LOW < HIGH, got {}, {}", o.range->first, o.range->second));
  settings.crumb_cell = r.value("crumb_cell", settings.crumb_cell);
  // The colour: the command's, else the scene's render.colour with its range, else browning.
  const std::string colour = !o.colour.empty() ? o.colour : r.value("colour", std::string("browning"));
  std::optional<std::pair<Real, Real>> colour_range_given = o.range;
  if (!colour_range_given && o.colour.empty() && r.contains("range")) {
    colour_range_given = std::pair<Real, Real>(r["range"][0].get<double>(), r["range"][1].get<double>());
    if (!(colour_range_given->first < colour_range_given->second))
      throw InputError(run_dir.string() + ": scene.json: render.range", "LOW must be below HIGH");
  }
  if (r.contains("camera")) {
    const auto& c = r["camera"];
    Camera cam;
    cam.position = Vec3(c["position"][0].get<double>(), c["position"][1].get<double>(), c["position"][2].get<double>());
    cam.look_at = Vec3(c["look_at"][0].get<double>(), c["look_at"][1].get<double>(), c["look_at"][2].get<double>());
    cam.field_of_view = c.value("field_of_view", 35.0);
    settings.camera = cam;
  }
  // The colliders, drawn at each frame's pose; planes as a slab sized to every rendered frame's bodies.
  std::vector<std::string> missing;
  const std::vector<Collider> colliders = run_colliders(run, missing);
  Aabb bodies = Aabb::empty_box();
  for (int f : frames) {
    const ParticleSet ps = read_particle_frame(run.frames.at(f));
    for (const Vec3& x : ps.vector("position")) bodies.expand(x);
  }
  bodies.min.array() -= geometry.spacing;
  bodies.max.array() += geometry.spacing;
  // The domain walls as an open tank (render.domain_walls), the walls chosen for the camera of each picture.
  // (The domain walls' own default look is hidden.)
  const ColliderLook tank_look =
      parse_collider_look(r.value("domain_walls", std::string("hidden")), InsideBoxCollider{},
                          (run_dir / "scene.json").string() + ": render.domain_walls");
  const auto tank_at = [&](const Vec3& viewer) {
    return Prop{domain_tank_mesh(geometry.domain, geometry.periodic, viewer, 2 * geometry.spacing), tank_look, true};
  };
  const auto props_at = [&](int f) {
    std::vector<Prop> props;
    for (PosedCollider& c : posed_colliders(colliders, frame_time(run, f), bodies))
      props.push_back({std::move(c.mesh), c.look, c.bounded});
    if (tank_look != ColliderLook::hidden && settings.camera) props.push_back(tank_at(settings.camera->position));
    return props;
  };
  // One camera for the whole sequence: it frames every rendered frame's particles and the colliders near them
  // (and the tank's walls as a first camera, framing without them, sees them).
  if (!settings.camera) {
    Aabb box = bodies;
    for (int f : frames) {
      const Aabb framed = framing_box(bodies, props_at(f));
      box.expand(framed.min), box.expand(framed.max);
      if (colliders.empty() ||
          std::none_of(colliders.begin(), colliders.end(), [](const Collider& c) { return c.motion.moves(); }))
        break;  // every frame frames the same
    }
    const Real aspect = Real(settings.width) / Real(settings.height);
    if (tank_look != ColliderLook::hidden) {
      const Aabb framed = framing_box(bodies, {tank_at(frame_camera(box, aspect).position)});
      box.expand(framed.min), box.expand(framed.max);
    }
    settings.camera = frame_camera(box, aspect);
    if (o.camera_position && !o.look_at) settings.camera->look_at = 0.5 * (box.min + box.max);
  }
  if (o.camera_position) settings.camera->position = *o.camera_position;
  if (o.look_at) settings.camera->look_at = *o.look_at;
  if (o.field_of_view) settings.camera->field_of_view = *o.field_of_view;
  if (!((settings.camera->position - settings.camera->look_at).norm() > 0))
    throw InputError("render --camera", "the camera is where it looks: give a position away from --look-at");
  if (!o.cut.empty()) settings.cut = parse_cut_plane(o.cut, bodies);
  const TextRenderer text;
  MeshSettings mesh_opts;
  mesh_opts.colour = colour;
  mesh_opts.range = colour_range_given;
  mesh_opts.surface.method = o.method;
  const fs::path out_dir = run_dir / "render";
  ensure_directory(out_dir);
  const std::string scene_name = run.scene.value("name", std::string("bake"));
  const double fps = frame_rate(run);
  const double bake_scale =
      run.scene.contains("environment") ? run.scene["environment"].value("bake_time_scale", 1.0) : 1.0;
  // The cut's axis names the pictures (parse_cut_plane accepted AXIS or AXIS=VALUE).
  const std::string stem = o.mode + "-" + colour + (settings.cut ? "-cut-" + o.cut.substr(0, 1) : "");
  // Each food's browning ramp from its own raw colour (the lava cake's chocolate; the s'more's marshmallow
  // and crackers side by side), once per distinct colour; a scene of dough alone keeps the dough's bar.
  std::vector<surface::Lab> food_raws;
  for (const surface::Lab& c : geometry.raw_colour)
    if (std::none_of(food_raws.begin(), food_raws.end(),
                     [&](const surface::Lab& seen) { return surface::lab_distance(c, seen) == 0; }))
      food_raws.push_back(c);
  if (food_raws.size() == 1 && surface::lab_distance(food_raws.front(), surface::dough_lab()) == 0) food_raws.clear();
  // The colour bar of a frame's picture (a mesh shows the value in the colour the particles show it).
  const auto colour_bar = [&](const ParticleSet& ps) {
    const auto range = colour_range(ps, colour, colour_range_given);
    ColourBar bar;
    bar.label = colour;
    bar.low = range.first, bar.high = range.second;
    bar.palette = colour_palette(colour);
    bar.raws = food_raws;
    return bar;
  };
  // One frame's picture: with its colour bar and full caption, or (a strip's tile) with the bake time only.
  const auto draw = [&](int f, bool tile) {
    const ParticleSet ps = read_particle_frame(run.frames.at(f));
    const ColourBar bar = colour_bar(ps);
    const std::pair<Real, Real> range{bar.low, bar.high};
    const double bake = frame_time(run, f) * bake_scale;
    const std::string when = bake >= 120  ? fmt::format("{:.1f} min", bake / 60)
                             : bake >= 10 ? fmt::format("{:.0f} s", bake)
                                          : fmt::format("{:.2f} s", bake);
    const std::string caption = tile ? when : fmt::format("{}   frame {}   bake {}", scene_name, f, when);
    if (o.mode == "mesh") {
      const surface::SurfaceMesh mesh = frame_mesh(ps, geometry, mesh_opts);
      RenderSettings frame_settings = settings;
      std::optional<surface::ColourField> field, pores;
      if (settings.cut) {
        // The cut face: the same colouring as the surface, at every point of the plane inside the body.
        field.emplace(colour_samples(ps, geometry, mesh_opts), kColourSupport * geometry.spacing);
        frame_settings.cut_colour = [&, palette = bar.palette](const Vec3& x) {
          const Real value = surface::value_of_colour_coordinate(field->uv_at(x));
          const std::optional<surface::Lab> raw = palette == surface::Palette::baking ? field->raw_at(x) : std::nullopt;
          return raw ? surface::baking_colour(*raw, value) : surface::palette_colour(palette, value);
        };
        // And its crumb: pores where the dough rose (the same interpolation of the pore share, over twice the
        // support: a bubble particle is a pore of its own size, and the crumb's cells are drawn finer).
        if (settings.crumb_cell > 0) {
          pores.emplace(pore_samples(ps, geometry), 2 * kColourSupport * geometry.spacing);
          frame_settings.cut_pore_fraction = [&](const Vec3& x) { return pores->value_at(x); };
        }
      }
      return render_mesh(mesh, frame_settings, text, tile ? nullptr : &bar, caption, props_at(f));
    }
    ParticleView pv;
    const std::vector<Real> values = particle_values(ps, colour);
    // Browning starts from each particle's food colour (its material's raw_colour).
    const std::vector<surface::Lab> raw =
        colour == "browning" ? particle_raw_colours(ps, geometry) : std::vector<surface::Lab>{};
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const Vec3& x = ps.vector("position")[i];
      if (settings.cut && settings.cut->removes(x)) continue;  // the cut view shows the particles behind the plane
      pv.position.push_back(x);
      const Real value = (values[i] - range.first) / (range.second - range.first);
      pv.colour.push_back(i < raw.size() ? surface::baking_colour(raw[i], value)
                                         : surface::palette_colour(bar.palette, value));
    }
    pv.radius = 0.5 * geometry.spacing;
    return render_particles(pv, settings, text, tile ? nullptr : &bar, caption, props_at(f));
  };
  RenderRunResult result;
  const Camera camera = *settings.camera;
  for (int f : frames) {
    if (o.turntable <= 0) {
      const fs::path file = out_dir / (stem + "-" + frame_stem(f) + ".png");
      write_file_atomic(file, encode_png(draw(f, false)));
      result.images.push_back(file);
      continue;
    }
    for (int k = 0; k < o.turntable; ++k) {
      // About the vertical axis through the look-at point, counter-clockwise seen from above.
      const Real angle = 2 * kPi * k / o.turntable;
      const Eigen::AngleAxis<Real> turn(angle, Vec3::UnitY());
      settings.camera->position = camera.look_at + turn * (camera.position - camera.look_at);
      const fs::path file = out_dir / fmt::format("{}-{}-turn-{:03d}.png", stem, frame_stem(f), k);
      write_file_atomic(file, encode_png(draw(f, false)));
      result.images.push_back(file);
    }
  }
  settings.camera = camera;
  if (o.strip && !result.images.empty()) {
    // Up to six frames, evenly spread, in a row of full-size pictures (drawn again as tiles).
    const std::size_t n = std::min<std::size_t>(6, frames.size());
    std::vector<Image> tiles;
    for (std::size_t k = 0; k < n; ++k)
      tiles.push_back(draw(frames[n == 1 ? 0 : k * (frames.size() - 1) / (n - 1)], true));
    // The tiles, then a panel with the colour bar (the last tile's range) at the right.
    constexpr int kLegendWidth = 130;
    Image strip(int(n) * tiles[0].width + kLegendWidth, tiles[0].height, {236, 236, 234});
    for (std::size_t k = 0; k < n; ++k) strip.paste(tiles[k], int(k) * tiles[0].width, 0);
    draw_colour_bar(strip, colour_bar(read_particle_frame(run.frames.at(frames[frames.size() - 1]))), text);
    result.strip = out_dir / (stem + "-strip.png");
    write_file_atomic(*result.strip, encode_png(strip));
  }
  const auto add_note = [&](const std::string& note) { result.note += (result.note.empty() ? "" : "; ") + note; };
  for (const std::string& m : missing) add_note(m);
  if (o.movie) {
    if (!has_program("ffmpeg")) {
      add_note("no movie: ffmpeg is not installed (apt-get install ffmpeg)");
    } else if (result.images.size() < 2) {
      add_note("no movie: only one frame was rendered (use --all)");
    } else {
      const fs::path movie = out_dir / (stem + ".mp4");
      const double movie_fps = std::clamp(fps, 1.0, 60.0);
      // The concat demuxer takes the pictures in order whatever their numbers.
      std::string list;
      for (const auto& image : result.images)
        list += fmt::format("file {}\nduration {}\n", shell_quote(fs::absolute(image).string()), 1.0 / movie_fps);
      list += fmt::format("file {}\n", shell_quote(fs::absolute(result.images.back()).string()));
      const fs::path list_file = out_dir / (stem + ".ffconcat.txt");
      write_file_atomic(list_file, list);
      const std::string cmd = fmt::format(
          "ffmpeg -y -loglevel error -f concat -safe 0 -i {} -r {} -c:v libx264 -pix_fmt yuv420p "
          "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' {}",
          shell_quote(list_file.string()), movie_fps, shell_quote(movie.string() + ".tmp.mp4"));
      const int status = std::system(cmd.c_str());
      fs::remove(list_file);
      if (status != 0) throw IoError("ffmpeg failed to make " + movie.string());
      fs::rename(movie.string() + ".tmp.mp4", movie);
      result.movie = movie;
    }
  }
  return result;
}

}  // namespace bakesim::render
