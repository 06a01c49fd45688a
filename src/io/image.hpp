#pragma once
// 8-bit RGB images and their PNG encoding (stb_image_write).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace bakesim {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // row-major from the top-left, 3 bytes per pixel

  Image() = default;
  Image(int w, int h, std::array<std::uint8_t, 3> fill = {255, 255, 255});
  std::uint8_t* at(int x, int y) { return rgb.data() + 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x)); }
  const std::uint8_t* at(int x, int y) const {
    return rgb.data() + 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
  }
  void set(int x, int y, std::array<std::uint8_t, 3> c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    std::uint8_t* p = at(x, y);
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
  }
  // Alpha-blends c over the pixel (coverage in [0, 1]).
  void blend(int x, int y, std::array<std::uint8_t, 3> c, float coverage);
  // Pastes another image with its top-left corner at (x, y), clipped.
  void paste(const Image& other, int x, int y);
};

std::string encode_png(const Image& image);

}  // namespace bakesim
