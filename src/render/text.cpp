#include "render/text.hpp"

#include <stb_easy_font.h>
#include <stb_truetype.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

namespace bakesim::render {

namespace {
const char* const kFontPaths[] = {
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
};
const stbtt_fontinfo* info_of(const std::vector<unsigned char>& storage) {
  return reinterpret_cast<const stbtt_fontinfo*>(storage.data());
}

// UTF-8 to code points (labels carry °, ³, ...); a malformed byte stands for itself.
std::vector<int> code_points(const std::string& s) {
  std::vector<int> out;
  for (std::size_t i = 0; i < s.size();) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    int cp = extra == 0 ? c : c & (0x3F >> extra);
    bool ok = i + std::size_t(extra) < s.size();
    for (int k = 1; ok && k <= extra; ++k) {
      const unsigned char d = static_cast<unsigned char>(s[i + std::size_t(k)]);
      ok = (d & 0xC0) == 0x80;
      cp = (cp << 6) | (d & 0x3F);
    }
    if (!ok)
      cp = c, i += 1;
    else
      i += std::size_t(extra) + 1;
    out.push_back(cp);
  }
  return out;
}
}  // namespace

TextRenderer::TextRenderer() {
  for (const char* path : kFontPaths) {
    std::ifstream in(path, std::ios::binary);
    if (!in) continue;
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<unsigned char> info(sizeof(stbtt_fontinfo));
    if (!bytes.empty() && stbtt_InitFont(reinterpret_cast<stbtt_fontinfo*>(info.data()), bytes.data(), 0)) {
      font_ = std::move(bytes);
      info_ = std::move(info);
      // stbtt_fontinfo points into the font bytes; they moved with the vector's buffer.
      stbtt_InitFont(reinterpret_cast<stbtt_fontinfo*>(info_.data()), font_.data(), 0);
      return;
    }
  }
}

int TextRenderer::width(const std::string& text, float px) const {
  if (font_.empty()) return int(std::lround(stb_easy_font_width(const_cast<char*>(text.c_str())) * px / 10.0f));
  const stbtt_fontinfo* info = info_of(info_);
  const float scale = stbtt_ScaleForPixelHeight(info, px);
  const std::vector<int> cps = code_points(text);
  float w = 0;
  for (std::size_t i = 0; i < cps.size(); ++i) {
    int advance = 0, bearing = 0;
    stbtt_GetCodepointHMetrics(info, cps[i], &advance, &bearing);
    w += advance * scale;
    if (i + 1 < cps.size()) w += scale * stbtt_GetCodepointKernAdvance(info, cps[i], cps[i + 1]);
  }
  return int(std::ceil(w));
}

void TextRenderer::draw(Image& img, int x, int y, const std::string& text, float px, std::array<std::uint8_t, 3> colour,
                        Align align) const {
  const int w = width(text, px);
  if (align == Align::centre) x -= w / 2;
  if (align == Align::right) x -= w;
  if (font_.empty()) {
    // Stroke font: quads of 4 vertices (x, y, z, rgba) in units of ~1/10 of the line height.
    std::vector<char> buffer(text.size() * 270 + 1000);
    const int quads =
        stb_easy_font_print(0, 0, const_cast<char*>(text.c_str()), nullptr, buffer.data(), int(buffer.size()));
    const float s = px / 10.0f;
    const float* v = reinterpret_cast<const float*>(buffer.data());
    for (int q = 0; q < quads; ++q) {
      const float* a = v + q * 16;
      const float x0 = a[0] * s, y0 = a[1] * s, x1 = a[8] * s, y1 = a[9] * s;
      for (int py = int(std::floor(y0)); py < int(std::ceil(y1)); ++py)
        for (int pxl = int(std::floor(x0)); pxl < int(std::ceil(x1)); ++pxl)
          img.set(x + pxl, y - int(px * 0.8f) + py, colour);
    }
    return;
  }
  const stbtt_fontinfo* info = info_of(info_);
  const float scale = stbtt_ScaleForPixelHeight(info, px);
  float pen = float(x);
  const std::vector<int> cps = code_points(text);
  for (std::size_t i = 0; i < cps.size(); ++i) {
    const int c = cps[i];
    int gw = 0, gh = 0, xoff = 0, yoff = 0;
    const float shift = pen - std::floor(pen);
    unsigned char* bitmap = stbtt_GetCodepointBitmapSubpixel(info, scale, scale, shift, 0, c, &gw, &gh, &xoff, &yoff);
    for (int gy = 0; gy < gh; ++gy)
      for (int gx = 0; gx < gw; ++gx)
        img.blend(int(std::floor(pen)) + xoff + gx, y + yoff + gy, colour, bitmap[gy * gw + gx] / 255.0f);
    stbtt_FreeBitmap(bitmap, nullptr);
    int advance = 0, bearing = 0;
    stbtt_GetCodepointHMetrics(info, c, &advance, &bearing);
    pen += advance * scale;
    if (i + 1 < cps.size()) pen += scale * stbtt_GetCodepointKernAdvance(info, c, cps[i + 1]);
  }
}

void TextRenderer::draw_vertical(Image& img, int x, int y, const std::string& text, float px,
                                 std::array<std::uint8_t, 3> colour) const {
  // Draw horizontally on a white scratch image, then copy the inked pixels rotated.
  const int w = width(text, px) + 4, h = int(std::ceil(px * 1.3f));
  Image scratch(w, h);
  draw(scratch, 2, int(px), text, px, {0, 0, 0});
  for (int sy = 0; sy < h; ++sy)
    for (int sx = 0; sx < w; ++sx) {
      const float ink = 1.0f - scratch.at(sx, sy)[0] / 255.0f;
      if (ink <= 0) continue;
      // (sx, sy) → rotated CCW: column from the baseline, rows upward from the centre.
      img.blend(x - int(px) + sy, y + w / 2 - sx, colour, ink);
    }
}

}  // namespace bakesim::render
