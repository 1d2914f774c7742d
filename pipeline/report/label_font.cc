#include "pipeline/report/label_font.h"

#include <cmath>
#include <cstdio>

namespace texsim {

namespace {

// Rows of each glyph, top to bottom; bit 4 is the leftmost column.
struct Glyph {
  char c;
  std::array<uint8_t, kLabelGlyphH> rows;
};

constexpr Glyph kGlyphs[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {'e', {0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'/', {0x01, 0x01, 0x02, 0x04, 0x08, 0x10, 0x10}},
};

const Glyph* glyph(char c) {
  for (const Glyph& g : kGlyphs)
    if (g.c == c) return &g;
  return nullptr;
}

}  // namespace

int label_width(const std::string& text, int scale) {
  if (text.empty()) return 0;
  return static_cast<int>(text.size()) * (kLabelGlyphW + 1) * scale - scale;
}

void draw_label(std::vector<uint8_t>& rgb, int w, int h, int x, int y, const std::string& text,
                int scale, std::array<uint8_t, 3> colour) {
  for (size_t i = 0; i < text.size(); ++i) {
    const Glyph* g = glyph(text[i]);
    if (g == nullptr) continue;
    const int gx = x + static_cast<int>(i) * (kLabelGlyphW + 1) * scale;
    for (int r = 0; r < kLabelGlyphH; ++r) {
      for (int col = 0; col < kLabelGlyphW; ++col) {
        if (((g->rows[static_cast<size_t>(r)] >> (kLabelGlyphW - 1 - col)) & 1) == 0) continue;
        for (int dy = 0; dy < scale; ++dy) {
          for (int dx = 0; dx < scale; ++dx) {
            const int px = gx + col * scale + dx, py = y + r * scale + dy;
            if (px < 0 || py < 0 || px >= w || py >= h) continue;
            const size_t at =
                (static_cast<size_t>(py) * static_cast<size_t>(w) + static_cast<size_t>(px)) * 3;
            rgb[at] = colour[0];
            rgb[at + 1] = colour[1];
            rgb[at + 2] = colour[2];
          }
        }
      }
    }
  }
}

std::string label_number(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  if (v != 0 && std::abs(v) < 0.001) {
    std::snprintf(buf, sizeof buf, "%.2g", v);
  } else {
    std::snprintf(buf, sizeof buf, "%.3g", v);
  }
  return buf;
}

}  // namespace texsim
