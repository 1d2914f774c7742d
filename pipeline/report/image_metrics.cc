#include "pipeline/report/image_metrics.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"

namespace texsim {

ImageRgb::ImageRgb(int w, int h, glm::dvec3 background)
    : width(w),
      height(h),
      rgb(static_cast<size_t>(w) * h * 3),
      covered(static_cast<size_t>(w) * h, 0),
      label(static_cast<size_t>(w) * h, -1) {
  for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i) {
    rgb[i * 3] = static_cast<float>(background.x);
    rgb[i * 3 + 1] = static_cast<float>(background.y);
    rgb[i * 3 + 2] = static_cast<float>(background.z);
  }
}

void ImageRgb::set(int x, int y, const glm::vec4& c, int32_t lbl) {
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  const size_t i = static_cast<size_t>(y) * width + x;
  rgb[i * 3] = c.r;
  rgb[i * 3 + 1] = c.g;
  rgb[i * 3 + 2] = c.b;
  covered[i] = 1;
  label[i] = lbl;
}

void ImageRgb::resize(int w, int h, glm::dvec3 background) {
  ImageRgb g(w, h, background);
  for (int y = 0; y < std::min(h, height); ++y) {
    for (int x = 0; x < std::min(w, width); ++x) {
      const size_t s = static_cast<size_t>(y) * width + x, d = static_cast<size_t>(y) * w + x;
      for (int c = 0; c < 3; ++c) g.rgb[d * 3 + c] = rgb[s * 3 + c];
      g.covered[d] = covered[s];
      g.label[d] = label[s];
    }
  }
  *this = std::move(g);
}

AccuracyMetrics compare_images(const ImageRgb& img, const ImageRgb& ref, int32_t only_label) {
  AccuracyMetrics m;
  double se = 0, sref = 0, sabs = 0;
  for (size_t i = 0; i < img.covered.size(); ++i) {
    if (!img.covered[i] || (only_label >= 0 && img.label[i] != only_label)) continue;
    ++m.pixels;
    for (int c = 0; c < 3; ++c) {
      const double e = static_cast<double>(img.rgb[i * 3 + c]) - ref.rgb[i * 3 + c];
      se += e * e;
      sabs += std::abs(e);
      sref += static_cast<double>(ref.rgb[i * 3 + c]) * ref.rgb[i * 3 + c];
      m.max_abs = std::max(m.max_abs, std::abs(e));
    }
  }
  if (m.pixels == 0) return m;
  const double n = 3.0 * static_cast<double>(m.pixels);
  m.mse = se / n;
  m.mean_abs = sabs / n;
  m.nmse = sref > 0 ? se / sref : 0;
  m.psnr_db = m.mse > 0 ? 10.0 * std::log10(1.0 / m.mse) : 999.0;
  return m;
}

namespace {
void write_rgb8(const std::string& path, int w, int h, const std::vector<uint8_t>& px) {
  const std::string tmp = temp_path_for(path, ".png");
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw InputError(path, "no image writer for this file type: " + OIIO::geterror());
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  // The temporary name keeps the real extension's writer (created above from `path`).
  errno = 0;
  if (!out->open(tmp, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px.data()) ||
      !out->close()) {
    // The reason, in terms of the file asked for (the library's message names the temporary).
    const std::string reason = errno ? std::strerror(errno) : out->geterror();
    discard_temp(tmp, path);
    throw InputError(path, "cannot write image: " + reason);
  }
  commit_temp(tmp, path);
}
}  // namespace

void write_image(const std::string& path, const ImageRgb& img) {
  std::vector<uint8_t> px(img.rgb.size());
  for (size_t i = 0; i < px.size(); ++i) {
    px[i] = static_cast<uint8_t>(std::lround(std::clamp(img.rgb[i], 0.0f, 1.0f) * 255.0f));
  }
  write_rgb8(path, img.width, img.height, px);
}

void write_error_heatmap(const std::string& path, const ImageRgb& img, const ImageRgb& ref,
                         double scale) {
  std::vector<uint8_t> px(img.rgb.size(), 0);
  for (size_t i = 0; i < img.covered.size(); ++i) {
    if (!img.covered[i]) continue;
    double e = 0;
    for (int c = 0; c < 3; ++c)
      e = std::max(e, std::abs(static_cast<double>(img.rgb[i * 3 + c]) - ref.rgb[i * 3 + c]));
    const double t = scale > 0 ? std::clamp(e / scale, 0.0, 1.0) : 0.0;
    // Black → red → yellow → white ramp.
    const double r = std::clamp(3 * t, 0.0, 1.0), g = std::clamp(3 * t - 1, 0.0, 1.0),
                 b = std::clamp(3 * t - 2, 0.0, 1.0);
    px[i * 3] = static_cast<uint8_t>(std::lround(r * 255));
    px[i * 3 + 1] = static_cast<uint8_t>(std::lround(g * 255));
    px[i * 3 + 2] = static_cast<uint8_t>(std::lround(b * 255));
  }
  write_rgb8(path, img.width, img.height, px);
}

}  // namespace texsim
