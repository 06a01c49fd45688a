#pragma once
// Text for plots and colour bars: TrueType glyphs (stb_truetype) from the
// DejaVu Sans font Debian ships in fonts-dejavu-core; without it, the built-in
// stroke font of stb_easy_font, so labels never go missing.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "io/image.hpp"

namespace bakesim::render {

enum class Align { left, centre, right };

class TextRenderer {
 public:
  TextRenderer();  // loads the first font found
  // Draws `text` with its baseline at y; x is the left edge, centre or right edge.
  void draw(Image& image, int x, int y, const std::string& text, float pixel_height, std::array<std::uint8_t, 3> colour,
            Align align = Align::left) const;
  // Same, rotated 90° counter-clockwise (for a y-axis label); (x, y) is the
  // centre of the text's baseline.
  void draw_vertical(Image& image, int x, int y, const std::string& text, float pixel_height,
                     std::array<std::uint8_t, 3> colour) const;
  int width(const std::string& text, float pixel_height) const;

 private:
  std::vector<unsigned char> font_;  // TTF bytes; empty: stroke font
  std::vector<unsigned char> info_;  // stbtt_fontinfo storage
};

}  // namespace bakesim::render
