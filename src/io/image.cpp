#include "io/image.hpp"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace bakesim {

Image::Image(int w, int h, std::array<std::uint8_t, 3> fill)
    : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3) {
  for (std::size_t i = 0; i < rgb.size(); i += 3) rgb[i] = fill[0], rgb[i + 1] = fill[1], rgb[i + 2] = fill[2];
}

void Image::blend(int x, int y, std::array<std::uint8_t, 3> c, float coverage) {
  if (x < 0 || y < 0 || x >= width || y >= height || !(coverage > 0)) return;
  coverage = std::min(coverage, 1.0f);
  std::uint8_t* p = at(x, y);
  for (int k = 0; k < 3; ++k) p[k] = std::uint8_t(std::lround(p[k] + (float(c[k]) - p[k]) * coverage));
}

void Image::paste(const Image& o, int x0, int y0) {
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x) {
      const std::uint8_t* s = o.at(x, y);
      set(x0 + x, y0 + y, {s[0], s[1], s[2]});
    }
}

std::string encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0) throw IoError("cannot encode an empty image as PNG");
  std::string out;
  auto sink = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
  };
  if (!stbi_write_png_to_func(sink, &out, image.width, image.height, 3, image.rgb.data(), image.width * 3))
    throw IoError("PNG encoding failed");
  return out;
}

}  // namespace bakesim
