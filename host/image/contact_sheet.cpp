#include "image/contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <stb_easy_font.h>

namespace bp {
namespace {

constexpr int kLabelHeight = 28, kGap = 4;

// Draws text with stb_easy_font's quads in linear white, twice the font's size where it fits `width`.
void draw_text(ImageRGB& sheet, int x0, int y0, const std::string& text, int width) {
  const int kTextScale = stb_easy_font_width(const_cast<char*>(text.c_str())) * 2 <= width ? 2 : 1;
  static char buffer[99999];
  int quads = stb_easy_font_print(0.0f, 0.0f, const_cast<char*>(text.c_str()), nullptr, buffer, sizeof buffer);
  const float* v = reinterpret_cast<const float*>(buffer);  // 4 vertices of (x, y, z, rgba) per quad
  for (int q = 0; q < quads; ++q) {
    const float* quad = v + q * 16;
    int xa = x0 + int(quad[0] * kTextScale), ya = y0 + int(quad[1] * kTextScale);
    int xb = x0 + int(quad[8] * kTextScale), yb = y0 + int(quad[9] * kTextScale);
    for (int y = std::max(0, ya); y < std::min(sheet.height, yb); ++y)
      for (int x = std::max(0, xa); x < std::min(sheet.width, xb); ++x)
        for (int c = 0; c < 3; ++c) sheet.pixel(x, y)[c] = 1.0f;
  }
}

}  // namespace

void write_contact_sheet(const std::string& path, const std::vector<SheetPanel>& panels, float exposure_stops,
                         int columns) {
  const ImageRGB* first = nullptr;
  for (const SheetPanel& p : panels)
    if (p.image && !first) first = p.image;
  if (!first || panels.empty()) throw std::runtime_error(path + ": a contact sheet needs at least one image");
  const int w = first->width, h = first->height;
  const int rows = (int(panels.size()) + columns - 1) / columns;
  ImageRGB sheet(columns * w + (columns + 1) * kGap, rows * (h + kLabelHeight) + (rows + 1) * kGap);
  for (float& v : sheet.rgb) v = 0.05f;
  const float scale = std::exp2(exposure_stops);
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const int x0 = kGap + int(i % columns) * (w + kGap), y0 = kGap + int(i / columns) * (h + kLabelHeight + kGap);
    const ImageRGB* img = panels[i].image;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          float v = img && img->width == w && img->height == h ? img->pixel(x, y)[c] * scale : 0.0f;
          sheet.pixel(x0 + x, y0 + y)[c] = std::isfinite(v) ? v : 0.0f;
        }
    std::string label = panels[i].label + (img ? "" : " (not available)");
    draw_text(sheet, x0 + 2, y0 + h + 6, label, w - 4);
  }
  write_png(path, sheet, 0.0f);
}

}  // namespace bp
