// Pictures and plots (src/render): a rendered sphere coloured hot on one side
// is not blank and its hot side is browner than its cold side; particle mode
// draws a colour bar; plots of a stats table put their lines where the data are.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "helpers.hpp"
#include "render/plot.hpp"
#include "render/render.hpp"
#include "geometry/collider_mesh.hpp"
#include "support/threads.hpp"

using namespace bakesim;
using namespace bakesim::render;

namespace {

surface::SurfaceParticles ball(Real radius, Real s) {
  return test_support::lattice_ball(radius, s, Vec3(0, radius, 0));
}

// Mean "brownness" (how far below cream white) of pixels in a column range.
double brownness(const Image& img, int x0, int x1) {
  double sum = 0;
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = x0; x < x1; ++x) {
      const std::uint8_t* p = img.at(x, y);
      // Object pixels: the background and ground are grey (r ≈ g ≈ b).
      if (std::abs(int(p[0]) - int(p[2])) < 25) continue;
      sum += 255.0 - (p[1] + p[2]) / 2.0;  // browns lose green and blue
      ++n;
    }
  return n > 0 ? sum / n : 0;
}

}  // namespace

TEST(Render, HotSideOfAColouredSphereIsBrowner) {
  const Real s = 0.004;
  const auto p = ball(0.04, s);
  surface::SurfaceMesh mesh = surface::reconstruct_surface(p, {});
  surface::ColourSamples samples;
  samples.position = p.position;
  samples.volume.assign(p.position.size(), s * s * s);
  // Browning rises from 0 on the left (−x) to 1 on the right (+x).
  for (const Vec3& x : p.position) samples.value.push_back(std::clamp(0.5 + x.x() / 0.08, 0.0, 1.0));
  surface::assign_uv(mesh, samples, 2 * s);
  surface::colour_vertices(mesh, surface::Palette::baking);
  RenderSettings settings;
  settings.width = 320, settings.height = 240;
  // Looking straight at the sphere along −z: +x is the picture's right half.
  settings.camera = Camera{Vec3(0, 0.04, 0.35), Vec3(0, 0.04, 0), 30};
  const TextRenderer text;
  const Image img = render_mesh(mesh, settings, text);
  ASSERT_EQ(img.width, 320);
  // Not blank: many distinct colours, and object pixels on both halves.
  int object = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) object += std::abs(int(img.at(x, y)[0]) - int(img.at(x, y)[2])) >= 25;
  EXPECT_GT(object, 320 * 240 / 20);
  const double left = brownness(img, 0, 160), right = brownness(img, 160, 320);
  EXPECT_GT(right, left + 30) << "hot (right) side " << right << ", cold (left) side " << left;
}

TEST(Render, ParticlesWithAColourBarAndTheSameImageOnAnyThreadCount) {
  const test_support::ThreadLimitLifted all_threads;  // compares thread counts
  ParticleView pv;
  for (int i = 0; i < 200; ++i) {
    pv.position.push_back(Vec3(0.001 * (i % 20), 0.001 * (i / 20), 0));
    pv.colour.push_back(surface::palette_colour(surface::Palette::heat, i / 199.0));
  }
  pv.radius = 0.0005;
  RenderSettings settings;
  settings.width = 200, settings.height = 120;
  const TextRenderer text;
  const ColourBar bar{"temperature", 20, 220, surface::Palette::heat, {}};
  const Image a = render_particles(pv, settings, text, &bar);
  // The colour bar's top is the palette's hot end (red dominant).
  const std::uint8_t* top = a.at(a.width - 110 + 11, a.height / 5 + 2);
  EXPECT_GT(int(top[0]), int(top[2]) + 80);
  Image b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    b = render_particles(pv, settings, text, &bar);
  }
  EXPECT_EQ(a.rgb, b.rgb);
  // A browning bar for a food with its own raw colour (chocolate) runs from that colour: its foot is the
  // raw chocolate, where the dough's bar is pale.
  ColourBar chocolate{"browning", 0, 1, surface::Palette::baking, {}};
  const surface::Lab cocoa{17.4, 2.6, 1.4};
  chocolate.raws = {cocoa};
  const Image c = render_particles(pv, settings, text, &chocolate);
  const int foot_y = c.height * 4 / 5 - 1;
  const double foot_t = 1.0 / (c.height * 4 / 5 - c.height / 5);
  const std::uint8_t* foot = c.at(c.width - 110 + 11, foot_y);
  const auto raw = surface::baking_colour(cocoa, foot_t);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(int(foot[k]), int(raw[k]), 2) << k;
  EXPECT_LT(int(foot[0]) + foot[1] + foot[2], 200);  // dark brown, not the dough's cream (about 570)
  // Two foods (chocolate and dough, as a scene mixing them): a column each, side by side, each from its own
  // raw colour: the left column's foot is chocolate, the right one's the dough's cream.
  ColourBar mixed = chocolate;
  mixed.raws.push_back(surface::dough_lab());
  const Image d = render_particles(pv, settings, text, &mixed);
  const std::uint8_t* left = d.at(d.width - 110 + 3, foot_y);
  const std::uint8_t* right = d.at(d.width - 110 + 19, foot_y);
  const auto cream = surface::baking_colour(surface::dough_lab(), foot_t);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(int(left[k]), int(raw[k]), 2) << k;
    EXPECT_NEAR(int(right[k]), int(cream[k]), 2) << k;
  }
  EXPECT_GT(int(right[0]) + right[1] + right[2], 500);
}

namespace {

// Pixels whose colour is the wood look's (r > g > b, clearly apart): no body,
// ground or background pixel is.
bool woody(const std::uint8_t* p) { return p[0] > p[1] + 20 && p[1] > p[2] + 15; }

// A grey (uncoloured) ball resting on y = 0, seen from the front and above.
surface::SurfaceMesh grey_ball() {
  surface::SurfaceMesh mesh = surface::reconstruct_surface(ball(0.03, 0.003), {});
  mesh.colours.clear();
  return mesh;
}

// The same ball in one colour (sRGB).
surface::SurfaceMesh coloured_ball(std::array<std::uint8_t, 3> rgb) {
  surface::SurfaceMesh mesh = grey_ball();
  mesh.colours.assign(mesh.vertices.size(), rgb);
  return mesh;
}

// A picture of that size from that camera.
RenderSettings view(int width, int height, const Camera& camera) {
  RenderSettings s;
  s.width = width, s.height = height;
  s.camera = camera;
  return s;
}

// Pixels clearly red (red above blue by 60) and clearly blue (the other way).
bool reddish(const std::uint8_t* p) { return int(p[0]) > int(p[2]) + 60; }
bool bluish(const std::uint8_t* p) { return int(p[2]) > int(p[0]) + 60; }
template <class Test>
int count_pixels(const Image& img, Test test) {
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) n += test(img.at(x, y));
  return n;
}

}  // namespace

// Issue 23: the tray under the loaf is drawn in its material.
TEST(Render, ATrayIsDrawnUnderTheBodyInItsMaterial) {
  const surface::SurfaceMesh mesh = grey_ball();
  RenderSettings settings = view(240, 180, Camera{Vec3(0, 0.12, 0.25), Vec3(0, 0.02, 0), 35});
  const TextRenderer text;
  Prop tray;
  tray.mesh = collider_rest_mesh(BoxCollider{{Vec3(-0.08, -0.008, -0.08), Vec3(0.08, 0, 0.08)}}, Vec3::Zero(), 1);
  tray.look = ColliderLook::wood;
  const Image bare = render_mesh(mesh, settings, text);
  const Image with_tray = render_mesh(mesh, settings, text, nullptr, "", {tray});
  // Below the ball's centre (the picture's middle column, lower half) the tray
  // shows as wood; without it nothing there is.
  int wood = 0, wood_bare = 0, below = 0;
  for (int y = settings.height / 2; y < settings.height; ++y)
    for (int x = settings.width / 2 - 20; x < settings.width / 2 + 20; ++x) {
      wood += woody(with_tray.at(x, y));
      wood_bare += woody(bare.at(x, y));
      ++below;
    }
  EXPECT_EQ(wood_bare, 0);
  EXPECT_GT(wood, below / 4) << wood << " of " << below;
  // Ceramic and metal draw other colours in the same place: no wood there.
  for (ColliderLook look : {ColliderLook::ceramic, ColliderLook::metal}) {
    tray.look = look;
    const Image other = render_mesh(mesh, settings, text, nullptr, "", {tray});
    int other_wood = 0;
    for (int y = settings.height / 2; y < settings.height; ++y)
      for (int x = settings.width / 2 - 20; x < settings.width / 2 + 20; ++x) other_wood += woody(other.at(x, y));
    EXPECT_EQ(other_wood, 0) << to_string(look);
  }
  // Hidden: the same picture as without it.
  tray.look = ColliderLook::hidden;
  EXPECT_EQ(render_mesh(mesh, settings, text, nullptr, "", {tray}).rgb, bare.rgb);
}

// A glass cover over the body still shows the body through it, a little dimmer.
TEST(Render, ABodyUnderGlassStaysVisible) {
  const surface::SurfaceMesh mesh = coloured_ball({200, 60, 40});  // a red ball
  RenderSettings settings = view(160, 120, Camera{Vec3(0, 0.1, 0.25), Vec3(0, 0.03, 0), 35});
  const TextRenderer text;
  Prop cover;
  cover.mesh = collider_rest_mesh(CupCollider{Vec3(0, 0.08, 0), Vec3(0, -1, 0), 0.05, 0.08, 0.002}, Vec3::Zero(), 1);
  cover.look = ColliderLook::glass;
  const Image bare = render_mesh(mesh, settings, text);
  const Image covered = render_mesh(mesh, settings, text, nullptr, "", {cover});
  // Where the bare picture shows the ball, the covered one still shows red.
  double red_bare = 0, red_covered = 0;
  int ball_pixels = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const std::uint8_t* a = bare.at(x, y);
      if (int(a[0]) < int(a[2]) + 60) continue;
      const std::uint8_t* b = covered.at(x, y);
      red_bare += int(a[0]) - int(a[2]), red_covered += int(b[0]) - int(b[2]), ++ball_pixels;
    }
  ASSERT_GT(ball_pixels, 500);
  EXPECT_GT(red_covered, 0.5 * red_bare) << "mean red excess " << red_covered / ball_pixels << " under glass, "
                                         << red_bare / ball_pixels << " bare";
  EXPECT_LT(red_covered, red_bare);  // the glass dims and tints it
  EXPECT_NE(bare.rgb, covered.rgb);
}

// Glass lying on an opaque face (the pancake scene's glass lid on the metal
// pan's rim: the two walls coincide) does not let the view through the
// opaque one: a blue ball behind a metal wall with a glass copy of the wall
// stays hidden.
TEST(Render, GlassCoincidingWithAnOpaqueFaceDoesNotSeeThroughIt) {
  const surface::SurfaceMesh mesh = coloured_ball({40, 70, 200});  // a blue ball
  RenderSettings settings = view(160, 120, Camera{Vec3(0, 0.05, 0.3), Vec3(0, 0.03, 0), 35});
  const TextRenderer text;
  Prop wall, glass;
  wall.mesh = collider_rest_mesh(BoxCollider{{Vec3(-0.1, 0, 0.04), Vec3(0.1, 0.1, 0.05)}}, Vec3::Zero(), 1);
  wall.look = ColliderLook::metal;
  glass.mesh = wall.mesh;
  glass.look = ColliderLook::glass;
  const auto blue_pixels = [](const Image& img) { return count_pixels(img, bluish); };
  ASSERT_GT(blue_pixels(render_mesh(mesh, settings, text)), 500);  // the ball alone
  EXPECT_EQ(blue_pixels(render_mesh(mesh, settings, text, nullptr, "", {wall})), 0);
  EXPECT_EQ(blue_pixels(render_mesh(mesh, settings, text, nullptr, "", {wall, glass})), 0);
  EXPECT_EQ(blue_pixels(render_mesh(mesh, settings, text, nullptr, "", {glass, wall})), 0);
}

// Issue 23: the domain drawn as an open tank (render.domain_walls) shows its far
// walls behind the body and never a wall in front of it.
TEST(Render, TheDomainTankShowsItsFarWallsAndNeverHidesTheBody) {
  const surface::SurfaceMesh mesh = coloured_ball({40, 70, 200});  // a blue ball
  RenderSettings settings = view(200, 150, Camera{Vec3(0.02, 0.12, 0.25), Vec3(0, 0.03, 0), 40});
  const TextRenderer text;
  const Aabb domain{Vec3(-0.1, 0, -0.1), Vec3(0.1, 0.1, 0.1)};
  Prop tank;
  tank.mesh = domain_tank_mesh(domain, {false, false, false}, settings.camera->position, 0.004);
  tank.look = ColliderLook::wood;
  const Image bare = render_mesh(mesh, settings, text);
  const Image in_tank = render_mesh(mesh, settings, text, nullptr, "", {tank});
  int ball = 0, ball_still_blue = 0, wood_above_ball = 0, wood_bare = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const std::uint8_t* a = bare.at(x, y);
      const std::uint8_t* b = in_tank.at(x, y);
      wood_bare += woody(a);
      if (y < settings.height / 3) wood_above_ball += woody(b);  // the back wall, above the ball
      if (!bluish(a)) continue;
      ++ball;
      ball_still_blue += int(b[2]) > int(b[0]) + 40;
    }
  ASSERT_GT(ball, 500);
  EXPECT_EQ(wood_bare, 0);
  EXPECT_GT(wood_above_ball, settings.width * settings.height / 3 / 4) << wood_above_ball;
  EXPECT_GE(ball_still_blue, int(0.98 * ball)) << ball_still_blue << " of " << ball;
}

// Issue 23: the cut view of a half-hot sphere shows the colour ramp on its cut face.
TEST(Render, TheCutFaceOfAHalfHotSphereShowsTheColourRamp) {
  const surface::SurfaceMesh mesh = grey_ball();  // radius 3 cm, centre (0, 0.03, 0), grey outside
  RenderSettings settings;
  settings.width = 200, settings.height = 200;
  // Looking along −z at the plane z = 0 through the centre; the near half is cut away.
  settings.camera = Camera{Vec3(0, 0.03, 0.3), Vec3(0, 0.03, 0), 20};
  Aabb box{Vec3(-0.03, 0, -0.03), Vec3(0.03, 0.06, 0.03)};
  settings.cut = parse_cut_plane("z", box);
  EXPECT_NEAR(settings.cut->offset, 0.0, 1e-15);
  // Cold (the heat palette's blue) where x < 0, hot (red) where x > 0.
  settings.cut_colour = [](const Vec3& x) {
    return surface::palette_colour(surface::Palette::heat, x.x() > 0 ? 1 : 0);
  };
  const TextRenderer text;
  const Image img = render_mesh(mesh, settings, text);
  int hot_right = 0, cold_left = 0, wrong = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const std::uint8_t* p = img.at(x, y);
      const bool red = p[0] > p[2] + 60, blue = p[2] > p[0] + 60;
      if (x >= settings.width / 2)
        hot_right += red, wrong += blue;
      else
        cold_left += blue, wrong += red;
    }
  // The disc of radius 3 cm seen from 0.3 m with a 20° field: π (r_px)² pixels.
  const double r_px = 0.03 / (0.3 * std::tan(10 * kPi / 180)) * settings.height / 2;
  const double disc = kPi * r_px * r_px;
  EXPECT_NEAR(hot_right, disc / 2, 0.15 * disc / 2) << "disc " << disc;
  EXPECT_NEAR(cold_left, disc / 2, 0.15 * disc / 2);
  EXPECT_LT(wrong, disc / 100);
  // Without the cut the ball shows its grey outside: no ramp colours at all.
  settings.cut.reset();
  const Image whole = render_mesh(mesh, settings, text);
  int coloured = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) coloured += std::abs(int(whole.at(x, y)[0]) - int(whole.at(x, y)[2])) > 60;
  EXPECT_EQ(coloured, 0);
  EXPECT_THROW(parse_cut_plane("w=1", box), InputError);
  EXPECT_THROW(parse_cut_plane("x=abc", box), InputError);
  EXPECT_NEAR(parse_cut_plane("y=0.01", box).offset, 0.01, 1e-15);
}

// Issue 23, crumb vs crust: pores on a cut face cover the share of it that the
// pore fraction gives (Delesse's principle for the Boolean model of spheres the
// renderer draws), the same crumb in every picture, none where there is no gas.
TEST(Render, CrumbPoresCoverTheirShareOfTheCutFace) {
  const surface::SurfaceMesh mesh = grey_ball();  // radius 3 cm, centre (0, 0.03, 0)
  RenderSettings settings = view(400, 400, Camera{Vec3(0, 0.03, 0.3), Vec3(0, 0.03, 0), 20});
  settings.cut = parse_cut_plane("z", Aabb{Vec3(-0.03, 0, -0.03), Vec3(0.03, 0.06, 0.03)});
  settings.cut_colour = [](const Vec3&) { return surface::palette_colour(surface::Palette::baking, 0); };
  settings.crumb_cell = 0.0015;  // about 900 cells² of face in the disc counted, 5.6 pixels a cell
  const TextRenderer text;
  const Image solid = render_mesh(mesh, settings, text);
  const auto luma = [](const std::uint8_t* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; };
  // The disc's pixels (well inside its 3 cm radius, seen from 0.3 m with a 20° field) that a pore darkens:
  // a pore's rim is drawn at 0.88 of the face's linear albedo, 0.955 of its sRGB value after the tone
  // curve; the pixels darker than halfway down that step are counted.
  const double r_px = 0.03 / (0.3 * std::tan(10 * kPi / 180)) * settings.height / 2;
  const auto pore_share = [&](const Image& img) {
    long disc = 0, dark = 0;
    for (int y = 0; y < settings.height; ++y)
      for (int x = 0; x < settings.width; ++x) {
        if (std::hypot(x + 0.5 - settings.width / 2.0, y + 0.5 - settings.height / 2.0) > 0.85 * r_px) continue;
        ++disc;
        dark += luma(img.at(x, y)) < 0.978 * luma(solid.at(x, y));
      }
    return double(dark) / double(disc);
  };
  for (const double phi : {0.2, 0.5, 0.7}) {
    settings.cut_pore_fraction = [phi](const Vec3&) { return phi; };
    const Image crumb = render_mesh(mesh, settings, text);
    const double share = pore_share(crumb);
    RecordProperty("pore_share_" + std::to_string(int(phi * 100)), std::to_string(share));
    EXPECT_NEAR(share, phi, 0.04) << "pore fraction " << phi;  // measured 0.197, 0.505, 0.716
    // The same crumb in a second picture (pores placed from a hash of space, not at random per picture).
    if (phi == 0.5) {
      const Image again = render_mesh(mesh, settings, text);
      EXPECT_EQ(crumb.rgb, again.rgb);
    }
  }
  // No gas, no pores: the picture of a solid face.
  settings.cut_pore_fraction = [](const Vec3&) { return 0.0; };
  EXPECT_EQ(pore_share(render_mesh(mesh, settings, text)), 0.0);
  settings.cut_pore_fraction = [](const Vec3&) { return 0.5; };
  settings.crumb_cell = 0;  // turned off
  EXPECT_EQ(pore_share(render_mesh(mesh, settings, text)), 0.0);
}

// A body pressed into a collider (a cake against its pan's wall: surfaces
// overlap by about a particle radius) still shows its whole cut face: the
// collider's face behind the plane, inside the body, does not cover it.
TEST(Render, TheCutFaceShowsWhereAColliderOverlapsTheBody) {
  const surface::SurfaceMesh mesh = grey_ball();  // radius 3 cm, centre (0, 0.03, 0)
  RenderSettings settings = view(200, 200, Camera{Vec3(0, 0.03, 0.3), Vec3(0, 0.03, 0), 20});
  settings.cut = parse_cut_plane("z", Aabb{Vec3(-0.03, 0, -0.03), Vec3(0.03, 0.06, 0.03)});
  settings.cut_colour = [](const Vec3&) { return surface::palette_colour(surface::Palette::heat, 1); };
  const TextRenderer text;
  // A metal block filling the right half of the ball from 5 mm behind the cut plane backwards.
  Prop block;
  block.mesh = collider_rest_mesh(BoxCollider{{Vec3(0, -0.01, -0.1), Vec3(0.1, 0.1, -0.005)}}, Vec3::Zero(), 1);
  block.look = ColliderLook::metal;
  const auto red_pixels = [](const Image& img) { return count_pixels(img, reddish); };
  const int alone = red_pixels(render_mesh(mesh, settings, text));
  const int with_block = red_pixels(render_mesh(mesh, settings, text, nullptr, "", {block}));
  ASSERT_GT(alone, 2000);
  EXPECT_NEAR(with_block, alone, 0.02 * alone)
      << with_block << " cut-face pixels with the block, " << alone << " without";
}

TEST(Plot, NiceTicksAndALineWhereTheDataAre) {
  const auto t = nice_ticks(0.0, 27.3);
  ASSERT_GE(t.size(), 4u);
  EXPECT_DOUBLE_EQ(t.front(), 0.0);
  EXPECT_NEAR(t[1] - t[0], 5.0, 1e-12);
  PlotSpec spec{"test", "x", "y", {{"flat", {0, 1, 2}, {5, 5, 5}}}, 400, 300};
  spec.series.push_back({"other", {0, 2}, {0, 10}});
  const TextRenderer text;
  const Image img = plot_lines(spec, text);
  // The flat line at y = 5 sits at the middle height of the axes: some pixel
  // of the first series' colour (31, 119, 180) lies near it.
  int found = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 200; x < 380; ++x) {
      const std::uint8_t* p = img.at(x, y);
      if (std::abs(p[0] - 31) < 20 && std::abs(p[1] - 119) < 20 && std::abs(p[2] - 180) < 20)
        found = std::max(found, y);
    }
  const int top = 50, bottom = 300 - 70;
  EXPECT_NEAR(found, (top + bottom) / 2, 12);
}

// Issue 22: steps of 2.5 were labelled "0, 2, 5, 8, 10".
TEST(Plot, TickLabelsShowTheDecimalsTheirStepNeeds) {
  const auto t = nice_ticks(0.0, 10.0, 4);
  ASSERT_GE(t.size(), 2u);
  const double step = t[1] - t[0];
  EXPECT_DOUBLE_EQ(step, 2.5);
  std::vector<std::string> labels;
  for (double v : t) labels.push_back(tick_label(v, step));
  EXPECT_EQ(labels, (std::vector<std::string>{"0.0", "2.5", "5.0", "7.5", "10.0"}));
  EXPECT_EQ(tick_label(20, 5), "20");
  EXPECT_EQ(tick_label(0.25, 0.25), "0.25");
  EXPECT_EQ(tick_label(0.3, 0.1), "0.3");
  EXPECT_EQ(tick_label(-1e-17, 0.5), "0.0");  // never "-0.0"
  EXPECT_EQ(tick_label(1.5e-6, 2.5e-7), "0.0000015");
}

TEST(Plot, ATinyOrDegenerateSpanStillGetsTicksAndAPicture) {
  // A run of a few nanoseconds: the tick step was not representable (issue 21: a crash).
  for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{
           {1.0, 1.0 + 1e-15}, {0.0, 1e-310}, {5.0, 5.0}, {1e6, 1e6 + 1e-9}, {0.0, std::nan("")}}) {
    const auto t = nice_ticks(lo, hi);
    ASSERT_FALSE(t.empty()) << lo << " " << hi;
    EXPECT_LT(t.size(), 100u);
    for (double v : t) EXPECT_TRUE(std::isfinite(v));
  }
  PlotSpec spec{"tiny", "time (s)", "T", {{"probe", {0.0, 1e-12, 2e-12}, {20, 20, 20}}}, 200, 150};
  const TextRenderer text;
  const Image img = plot_lines(spec, text);
  EXPECT_EQ(img.width, 200);
}

// A dashed series with few points (the doneness line: two) was drawn solid.
TEST(Plot, ADashedLineOfTwoPointsIsDrawnInDashes) {
  PlotSpec spec{"dashes", "x", "y", {}, 400, 300};
  spec.series.push_back({"done", {0, 10}, {5, 5}, true});
  spec.series.push_back({"ramp", {0, 10}, {0, 10}});  // gives the axes a span around y = 5
  const TextRenderer text;
  const Image img = plot_lines(spec, text);
  // Along the line's row, right of the legend: runs of its colour (31, 119, 180) and gaps between them.
  const int top = 50, bottom = 300 - 70, row = (top + bottom) / 2;
  int runs = 0, gaps = 0;
  bool on = false;
  for (int x = 200; x < 360; ++x) {
    bool hit = false;
    for (int y = row - 3; y <= row + 3; ++y) {
      const std::uint8_t* p = img.at(x, y);
      hit = hit || (std::abs(p[0] - 31) < 40 && std::abs(p[1] - 119) < 40 && std::abs(p[2] - 180) < 40);
    }
    if (hit && !on) ++runs;
    if (!hit && on) ++gaps;
    on = hit;
  }
  EXPECT_GE(runs, 8) << "160 px of a 16-px dash pattern";
  EXPECT_GE(gaps, 8);
}
