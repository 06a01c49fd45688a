// The crust colour ramp: CIE L*a*b* → sRGB against published conversions, the
// ramp's distance from the dough against the browning kinetics' definition of
// B = ΔE / 52, and the Blender add-on's copy of the palette against the library's.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "physics/browning.hpp"
#include "surface/crust_colour.hpp"
#include "surface/surface.hpp"

using namespace bakesim;
using namespace bakesim::surface;

TEST(CrustColour, LabToSrgbMatchesPublishedConversions) {
  // sRGB primaries and greys in L*a*b* (D65), as tabulated by B. Lindbloom's
  // colour calculator (brucelindbloom.com): red (255, 0, 0) is L* 53.24,
  // a* 80.09, b* 67.20; blue (0, 0, 255) is 32.30, 79.19, −107.86; L* 50 grey is
  // sRGB 119; L* 100 is white.
  const struct {
    Lab lab;
    int r, g, b;
  } cases[] = {{{53.24, 80.09, 67.20}, 255, 0, 0},
               {{32.30, 79.19, -107.86}, 0, 0, 255},
               {{50.0, 0.0, 0.0}, 119, 119, 119},
               {{100.0, 0.0, 0.0}, 255, 255, 255}};
  for (const auto& c : cases) {
    const auto rgb = lab_to_srgb(c.lab);
    EXPECT_NEAR(255 * rgb[0], c.r, 0.6) << c.lab.L;
    EXPECT_NEAR(255 * rgb[1], c.g, 0.6) << c.lab.L;
    EXPECT_NEAR(255 * rgb[2], c.b, 0.6) << c.lab.L;
  }
}

TEST(CrustColour, TheRampLiesAtTheKineticsColourDifferenceFromTheDough) {
  const Lab dough = crust_lab_of_browning(0);
  EXPECT_DOUBLE_EQ(dough.L, 80.0);
  EXPECT_DOUBLE_EQ(dough.a, -0.5);
  EXPECT_DOUBLE_EQ(dough.b, 18.0);
  const BrowningKinetics kinetics;
  Real previous_lightness = dough.L + 1;
  for (int i = 0; i <= 100; ++i) {
    const Real b = i / 100.0;
    const Lab c = crust_lab_of_browning(b);
    // B = ΔE / ΔE∞ (Zanoni et al. 1995): the colour drawn is ΔE from the dough.
    EXPECT_NEAR(lab_distance(c, dough), kinetics.colour_difference(b), 1e-9) << b;
    EXPECT_LT(c.L, previous_lightness) << b;  // darker with every step
    previous_lightness = c.L;
  }
  // The path passes through the lightest commercial top crust (Mohd Jusoh 2008).
  const Lab commercial{66.0, 2.4, 22.3};
  const Lab on_path = crust_lab(lab_distance(commercial, dough));
  EXPECT_NEAR(lab_distance(on_path, commercial), 0, 1e-9);
  // Burnt (B = 1) is still short of the darkest crust measured, which it never passes.
  EXPECT_GT(crust_lab_of_browning(1).L, 25.0);
  EXPECT_DOUBLE_EQ(crust_lab(1000).L, 25.0);
}

TEST(CrustColour, TheBakingPaletteIsTheRampAndAMeshShowsDoughAtItsBrowning) {
  for (const Real b : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const auto rgb = lab_to_srgb(crust_lab_of_browning(b));
    const auto p = palette_colour(Palette::baking, b);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], 255 * rgb[k], 0.5) << b;
    // A vertex over dough of browning B has U = 0.1 + 0.8 B + 0.05 (Eq 4.7).
    EXPECT_NEAR(value_of_colour_coordinate(0.15 + 0.8 * b), b, 1e-12);
  }
  EXPECT_EQ(value_of_colour_coordinate(0.05), 0.0);  // raw bubbles: the dough's colour
}

// A food with its own raw colour (chocolate, fruit) browns from it: its crust colour for B is the dough's
// path point offset by the raw colour's difference from the dough, the offset fading with the distance
// travelled along the path (none at its darkest crust, 58.5 from the dough).
TEST(CrustColour, AFoodWithItsOwnRawColourBrownsFromIt) {
  const Lab chocolate{17.4, 2.6, 1.4}, dough = dough_lab();
  const Lab darkest = crust_lab(1000);
  const Real path_length = lab_distance(darkest, dough);
  EXPECT_NEAR(path_length, std::sqrt(55.0 * 55.0 + 15.5 * 15.5 + 12.0 * 12.0), 1e-9);
  for (const Real b : {0.0, 0.1, 0.3, 0.6, 1.0}) {
    // The dough's own colour gives the measured path unchanged.
    const Lab d = crust_lab_of_browning(b, dough), on_path = crust_lab_of_browning(b);
    EXPECT_NEAR(lab_distance(d, on_path), 0, 1e-12) << b;
    // The chocolate's crust lies off the path by (1 − travelled / path length) of its raw offset.
    const Real travelled = BrowningKinetics{}.colour_difference(b);
    EXPECT_NEAR(lab_distance(crust_lab_of_browning(b, chocolate), on_path),
                (1 - travelled / path_length) * lab_distance(chocolate, dough), 1e-9)
        << b;
  }
  const Lab raw = crust_lab_of_browning(0, chocolate);
  EXPECT_NEAR(lab_distance(raw, chocolate), 0, 1e-12);  // unbaked: its raw colour
  // Out of range browning is clamped as for the dough.
  EXPECT_NEAR(lab_distance(crust_lab_of_browning(2, chocolate), crust_lab_of_browning(1, chocolate)), 0, 1e-12);
  // In the palette: raw chocolate is dark brown, far darker than raw dough.
  const auto c = baking_colour(chocolate, 0), p = palette_colour(Palette::baking, 0);
  EXPECT_LT(int(c[0]) + c[1] + c[2] + 300, int(p[0]) + p[1] + p[2]);
  EXPECT_GT(c[0], c[2]);  // warm, not grey-blue
}

TEST(CrustColour, TheBlenderAddOnRampIsTheLibrarysPalette) {
  std::ifstream in(std::string(BAKESIM_SOURCE_DIR) + "/tools/blender/bakesim_import/__init__.py");
  ASSERT_TRUE(in);
  std::stringstream text;
  text << in.rdbuf();
  const std::string source = text.str();
  const auto begin = source.find("BAKING_STOPS = [");
  ASSERT_NE(begin, std::string::npos);
  const std::string stops = source.substr(begin, source.find("]\n", begin) - begin);
  const std::regex stop(R"(\(([0-9.]+), \(([0-9.]+), ([0-9.]+), ([0-9.]+)\)\))");
  int count = 0;
  for (std::sregex_iterator it(stops.begin(), stops.end(), stop), end; it != end; ++it, ++count) {
    const Real at = std::stod((*it)[1]);  // the mesh's colouring coordinate U
    const auto p = palette_colour(Palette::baking, value_of_colour_coordinate(at));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(255 * std::stod((*it)[2 + k]), p[k], 0.6) << "stop at " << at;
  }
  EXPECT_EQ(count, 11);
}
