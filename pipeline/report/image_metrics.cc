#include "pipeline/report/image_metrics.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "pipeline/image_io/oiio_plugin.h"
#include "pipeline/image_io/png_file.h"
#include "pipeline/report/label_font.h"

namespace texsim {

ImageRgb::ImageRgb(int w, int h, glm::dvec3 bg) : ImageRgb(0, 0, w, h, w, h, bg) {}

ImageRgb::ImageRgb(int x0_, int y0_, int w, int h, int canvas_w, int canvas_h,
                   glm::dvec3 background_)
    : width(w),
      height(h),
      x0(x0_),
      y0(y0_),
      canvas_width(canvas_w),
      canvas_height(canvas_h),
      background(background_),
      rgb(static_cast<size_t>(w) * h * 3),
      covered(static_cast<size_t>(w) * h, 0),
      label(static_cast<size_t>(w) * h, -1) {
  clear();
}

void ImageRgb::clear() {
  for (size_t i = 0; i < covered.size(); ++i) {
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = background[c];
  }
  std::fill(covered.begin(), covered.end(), 0);
  std::fill(label.begin(), label.end(), -1);
}

void ImageRgb::set(int x, int y, const glm::vec4& c, int32_t lbl) {
  x -= x0;
  y -= y0;
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  const size_t i = static_cast<size_t>(y) * width + x;
  rgb[i * 3] = c.r;
  rgb[i * 3 + 1] = c.g;
  rgb[i * 3 + 2] = c.b;
  covered[i] = 1;
  label[i] = lbl;
}

void ErrorSums::add(const ErrorSums& o) {
  pixels += o.pixels;
  se += o.se;
  sref += o.sref;
  sabs += o.sabs;
  max_abs = std::max(max_abs, o.max_abs);
}

AccuracyMetrics ErrorSums::metrics() const {
  AccuracyMetrics m;
  m.pixels = pixels;
  m.max_abs = max_abs;
  if (pixels == 0) return m;
  const double n = 3.0 * static_cast<double>(pixels);
  m.mse = se / n;
  m.mean_abs = sabs / n;
  m.nmse = sref > 0 ? se / sref : 0;
  m.psnr_db = m.mse > 0 ? 10.0 * std::log10(1.0 / m.mse) : 999.0;
  return m;
}

std::vector<ErrorSums> error_sums(const ImageRgb& img, const ImageRgb& ref, int labels) {
  std::vector<ErrorSums> sums(static_cast<size_t>(1 + std::max(labels, 0)));
  for (size_t i = 0; i < img.covered.size(); ++i) {
    if (!img.covered[i]) continue;
    ErrorSums px;
    px.pixels = 1;
    for (int c = 0; c < 3; ++c) {
      const double e = static_cast<double>(img.rgb[i * 3 + c]) - ref.rgb[i * 3 + c];
      px.se += e * e;
      px.sabs += std::abs(e);
      px.sref += static_cast<double>(ref.rgb[i * 3 + c]) * ref.rgb[i * 3 + c];
      px.max_abs = std::max(px.max_abs, std::abs(e));
    }
    sums[0].add(px);
    if (img.label[i] >= 0 && img.label[i] < labels) sums[1 + img.label[i]].add(px);
  }
  return sums;
}

AccuracyMetrics compare_images(const ImageRgb& img, const ImageRgb& ref, int32_t only_label) {
  const std::vector<ErrorSums> s = error_sums(img, ref, only_label + 1);
  return s[only_label >= 0 ? 1 + only_label : 0].metrics();
}

namespace {
bool is_png_path(const std::string& path) {
  const size_t dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return false;
  std::string ext = path.substr(dot + 1);
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext == "png";
}

void write_rgb8(const std::string& path, int w, int h, const std::vector<uint8_t>& px) {
  // PNGs through libpng; other formats through OpenImageIO, loaded only for them.
  oiio::Plugin* plugin = is_png_path(path) ? nullptr : &oiio_plugin(path);
  const std::string tmp = temp_path_for(path, ".png");
  // Very large images (up to 16384²) are written with fast compression: the default level
  // takes several seconds per image there.
  const bool fast = static_cast<int64_t>(w) * h > (int64_t{1} << 24);
  std::string reason;
  if (!plugin) {
    reason = write_png_rgb8(tmp, w, h, px.data(), fast);
  } else if (!plugin->write_uint8(tmp, path, w, h, 3, px.data(), fast, &reason)) {
    // OpenImageIO picks the writer from `path` (the temporary name ends in .png).
    if (reason.empty()) reason = "unknown error";
  }
  if (!reason.empty()) {
    discard_temp(tmp, path);
    throw InputError(path, "cannot write image: " + reason);
  }
  commit_temp(tmp, path);
}

// The buffer's 8-bit pixels placed on the canvas (outside the buffer: `fill`), with
// `extra_rows` more rows below for the caller.
std::vector<uint8_t> placed(const ImageRgb& img, std::vector<uint8_t> px,
                            const std::array<uint8_t, 3>& fill, int extra_rows = 0) {
  const bool whole = img.x0 == 0 && img.y0 == 0 && img.canvas_width == img.width &&
                     img.canvas_height == img.height;
  const size_t row = static_cast<size_t>(img.canvas_width) * 3;
  if (whole) {
    px.resize(px.size() + row * static_cast<size_t>(extra_rows), 0);
    return px;
  }
  std::vector<uint8_t> canvas(row * static_cast<size_t>(img.canvas_height + extra_rows));
  for (size_t i = 0; i < row * static_cast<size_t>(img.canvas_height); i += 3)
    std::copy(fill.begin(), fill.end(), &canvas[i]);
  for (int y = 0; y < img.height; ++y) {
    const size_t src = static_cast<size_t>(y) * img.width * 3;
    const size_t dst = static_cast<size_t>(y + img.y0) * row + static_cast<size_t>(img.x0) * 3;
    std::copy_n(&px[src], static_cast<size_t>(img.width) * 3, &canvas[dst]);
  }
  return canvas;
}

uint8_t to8(float v) {
  return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}
}  // namespace

void write_image(const std::string& path, const ImageRgb& img) {
  std::vector<uint8_t> px(img.rgb.size());
  for (size_t i = 0; i < px.size(); ++i) px[i] = to8(img.rgb[i]);
  write_rgb8(path, img.canvas_width, img.canvas_height,
             placed(img, std::move(px),
                    {to8(img.background.r), to8(img.background.g), to8(img.background.b)}));
}

std::array<uint8_t, 3> heat_colour(double t) {
  // Black → red → yellow → white.
  t = std::clamp(t, 0.0, 1.0);
  const auto c = [](double v) {
    return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255));
  };
  return {c(3 * t), c(3 * t - 1), c(3 * t - 2)};
}

namespace {

int ramp_rows(int canvas_height) { return std::max(8, canvas_height / 12); }
int label_scale(int canvas_height) { return std::max(1, canvas_height / 240); }
int label_rows(int canvas_height) { return kLabelGlyphH * label_scale(canvas_height) + 4; }

// Under the ramp, the error at the ticks 0, ¼, ½, ¾ and 1 in 8-bit levels (1 LSB = 1/255 of
// full scale), the last followed by the unit; a label that would overlap another or leave
// the image is left out (0 and the scale first, then ½, then ¼ and ¾).
void draw_bar_labels(std::vector<uint8_t>& out, int w, int h, int top, int s, double scale) {
  struct Label {
    std::string text;
    int x0 = 0, x1 = 0;
  };
  std::vector<Label> shown;
  const auto fits = [&](const Label& l) {
    if (l.x0 < 0 || l.x1 > w) return false;
    for (const Label& o : shown)
      if (l.x0 < o.x1 + 2 * s && o.x0 < l.x1 + 2 * s) return false;
    return true;
  };
  for (const int k : {0, 4, 2, 1, 3}) {
    Label l;
    l.text = label_number(scale * 255 * k / 4) + (k == 4 ? " LSB" : "");
    const int lw = label_width(l.text, s), tick = std::min(w - 1, k * (w - 1) / 4);
    l.x0 = k == 0 ? 0 : k == 4 ? w - lw : tick - lw / 2;
    l.x1 = l.x0 + lw;
    if (!fits(l)) continue;
    draw_label(out, w, h, l.x0, top + 2, l.text, s, {200, 200, 200});
    shown.push_back(l);
  }
}

}  // namespace

int colour_bar_rows(int canvas_height) {
  return ramp_rows(canvas_height) + label_rows(canvas_height);
}

void write_error_heatmap(const std::string& path, const ImageRgb& img, const ImageRgb& ref,
                         double scale) {
  std::vector<uint8_t> px(img.rgb.size(), 0);
  for (size_t i = 0; i < img.covered.size(); ++i) {
    if (!img.covered[i]) continue;
    double e = 0;
    for (int c = 0; c < 3; ++c)
      e = std::max(e, std::abs(static_cast<double>(img.rgb[i * 3 + c]) - ref.rgb[i * 3 + c]));
    const auto rgb = heat_colour(scale > 0 ? e / scale : 0.0);
    std::copy(rgb.begin(), rgb.end(), &px[i * 3]);
  }
  // The colour bar below the image: two black rows, the ramp from 0 (left) to `scale`
  // (right), in its last two rows grey ticks at 0, ¼, ½, ¾ and 1 of the width; then the
  // ticks' values on black.
  const int w = img.canvas_width, bar = colour_bar_rows(img.canvas_height);
  const int ramp = ramp_rows(img.canvas_height);
  std::vector<uint8_t> out = placed(img, std::move(px), {0, 0, 0}, bar);
  const size_t row = static_cast<size_t>(w) * 3;
  for (int y = 2; y < ramp; ++y) {
    uint8_t* line = &out[static_cast<size_t>(img.canvas_height + y) * row];
    for (int x = 0; x < w; ++x) {
      const auto rgb = heat_colour(w > 1 ? static_cast<double>(x) / (w - 1) : 1.0);
      std::copy(rgb.begin(), rgb.end(), line + static_cast<size_t>(x) * 3);
    }
    if (y < ramp - 2) continue;
    for (int k = 0; k <= 4; ++k) {
      const int x = std::min(w - 1, k * (w - 1) / 4);
      std::fill_n(line + static_cast<size_t>(x) * 3, 3, uint8_t{128});
    }
  }
  draw_bar_labels(out, w, img.canvas_height + bar, img.canvas_height + ramp,
                  label_scale(img.canvas_height), scale);
  write_rgb8(path, w, img.canvas_height + bar, out);
}

}  // namespace texsim
