#pragma once
// The colour of a browning crust, from measured crust colours.
//
// The browning index B of both solvers is Zanoni, Peri & Bruno's (1995) colour
// difference over its burnt limit, B = ΔE / ΔE∞ with ΔE∞ = 52 (CIE76 distance in
// L*a*b* from the raw dough). The colour drawn for B is therefore the point of a
// measured crust-colour path whose distance from the dough is ΔE = 52 B. The path
// runs through three measured colours (docs/surfaces.md, "Crust colour"):
//   dough surface before baking   L* 80,   a* −0.5, b* 18
//   lightest commercial top crust L* 66.0, a*  2.4, b* 22.3   (Mohd Jusoh 2008)
//   darkest crust after 30 min    L* 25,   a* 15,   b* 30
// and is straight in L*a*b* between them. Its end lies 58 from the dough, beyond
// the burnt ΔE∞ = 52, so B ∈ [0, 1] stays on it.
#include <array>

#include "core/types.hpp"

namespace bakesim::surface {

struct Lab {
  Real L = 0, a = 0, b = 0;  // CIE 1976 L*a*b*, D65 white
};

// The measured path's colour at CIE76 distance `colour_difference` from the
// dough (clamped to the path: below 0 the dough, past its end the darkest crust).
Lab crust_lab(Real colour_difference);
// The crust colour for a browning index B = ΔE / 52 (clamped to [0, 1]).
Lab crust_lab_of_browning(Real browning);
// The raw dough's colour, where the measured path starts.
Lab dough_lab();
// The same for a food whose raw surface has its own colour (a material's
// `raw_colour`: chocolate, fruit): the measured path's point for B, offset by
// the raw colour's difference from the dough, the offset fading linearly to
// nothing at the path's darkest crust. B = 0 gives the raw colour, the burnt
// end is every food's darkest crust, and the dough's own colour gives the
// measured path unchanged.
Lab crust_lab_of_browning(Real browning, const Lab& raw);
// CIE L*a*b* (D65) → sRGB in [0, 1] (IEC 61966-2-1 transfer), out-of-gamut
// components clamped.
std::array<Real, 3> lab_to_srgb(const Lab& c);
Real lab_distance(const Lab& p, const Lab& q);  // CIE76 ΔE

}  // namespace bakesim::surface
