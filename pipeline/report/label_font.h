#pragma once
// A 5 × 7 pixel font for the numbers written into texsim's own PNGs (the error map's colour
// bar): digits, '.', '-', '+', 'e', and the letters of the units used there. Drawn into an
// RGB8 buffer at an integer scale; characters it lacks are drawn as a space.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace texsim {

constexpr int kLabelGlyphW = 5, kLabelGlyphH = 7;

// Width in pixels of `text` at `scale` (one blank column between characters).
int label_width(const std::string& text, int scale);
// Draws `text` with its top-left corner at (x, y) into the `w` × `h` RGB8 image `rgb`
// (3 bytes per pixel, rows top-down); pixels outside the image are skipped.
void draw_label(std::vector<uint8_t>& rgb, int w, int h, int x, int y, const std::string& text,
                int scale, std::array<uint8_t, 3> colour);
// A number as the bar labels it: up to 3 significant digits, no trailing zeros ("0", "6.38",
// "12.8", "255", "0.0638"); exponent form below 0.001 ("5e-05").
std::string label_number(double v);

}  // namespace texsim
