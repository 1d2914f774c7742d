#include "pipeline/render/frame_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "pipeline/image_io/oiio_plugin.h"
#include "pipeline/image_io/png_file.h"

namespace texsim {

namespace {
constexpr int kMaxSide = 16384;
constexpr uint64_t kMaxReferenceBytes = 256 * kMiB;

// Any image OpenImageIO reads, through its plugin.
Rgb8Image read_with_oiio(const std::string& path) {
  std::string error;
  const auto in = oiio_plugin(path).open(path, &error);
  if (!in) throw InputError(path, "cannot read image: " + error);
  const oiio::LevelSpec spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.width > kMaxSide || spec.height > kMaxSide ||
      spec.channels < 3 || spec.channels > 64) {
    throw InputError(path, "not an RGB image of at most 16384 x 16384 pixels");
  }
  Rgb8Image img;
  img.width = spec.width;
  img.height = spec.height;
  img.rgb.resize(static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 3);
  if (!in->read_uint8(3, img.rgb.data()))
    throw InputError(path, "cannot decode image: " + in->error());
  return img;
}
}  // namespace

Rgb8Image read_rgb8_image(const std::string& path) {
  // A regular file of a reference image's size, before it is read: a FIFO or device would
  // never end, and the run's outputs must not replace it.
  const std::string bytes = read_input_file(path, "reference image", kMaxReferenceBytes);
  // 8-bit RGB PNGs through libpng; whatever else, and the PNGs whose
  // pixels OpenImageIO would convert (alpha, 16-bit), through OpenImageIO.
  PngImage png;
  std::string error;
  const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
  switch (read_png_rgb8(data, bytes.size(), kMaxSide, &png, &error)) {
    case PngRead::Ok:
      return {png.width, png.height, std::move(png.rgb)};
    case PngRead::Failed:
      throw InputError(path, "cannot decode image: " + error);
    case PngRead::NotHandled:
      break;
  }
  return read_with_oiio(path);
}

namespace {

// The comparison over every pixel p: ref_drawn(p) and ref_rgb(p) give the other image's
// coverage and colour.
template <class Drawn, class Colour>
FrameComparison compare_pixels(const RenderedFrame& f, Drawn&& ref_drawn, Colour&& ref_rgb) {
  FrameComparison c;
  c.pixels = static_cast<uint64_t>(f.width) * static_cast<uint64_t>(f.height);
  double se = 0, sabs = 0;
  for (size_t p = 0; p < c.pixels; ++p) {
    const bool rd = ref_drawn(p);
    const bool sim_drawn = f.drawn[p] != 0;
    c.drawn_agree += rd == sim_drawn;
    c.drawn_texsim_only += sim_drawn && !rd;
    c.drawn_reference_only += rd && !sim_drawn;
    if (!(rd && sim_drawn)) continue;
    ++c.drawn_both;
    const uint8_t* r = ref_rgb(p);
    const uint8_t* s = f.rgba.data() + 4 * p;
    int worst = 0;
    for (int k = 0; k < 3; ++k) {
      const int d = std::abs(static_cast<int>(s[k]) - static_cast<int>(r[k]));
      worst = std::max(worst, d);
      se += (d / 255.0) * (d / 255.0);
      sabs += d;
    }
    c.max_abs = std::max<uint64_t>(c.max_abs, static_cast<uint64_t>(worst));
    c.off_by_more_than_8 += worst > 8;
    c.equal += worst == 0;
  }
  c.drawn_agreement_pct =
      c.pixels ? 100.0 * static_cast<double>(c.drawn_agree) / static_cast<double>(c.pixels) : 0;
  if (c.drawn_both > 0) {
    const double n = 3.0 * static_cast<double>(c.drawn_both);
    c.mse = se / n;
    c.mean_abs = sabs / n;
    c.psnr_db = c.mse > 0 ? 10 * std::log10(1 / c.mse) : 999;
  }
  return c;
}

}  // namespace

FrameComparison compare_frame(const RenderedFrame& f, const Rgb8Image& ref,
                              const std::string& ref_path, const uint8_t clear[3]) {
  if (f.width != ref.width || f.height != ref.height) {
    throw InputError(ref_path, "is " + std::to_string(ref.width) + " x " +
                                   std::to_string(ref.height) + " but frame " +
                                   std::to_string(f.number) + " was rendered at " +
                                   std::to_string(f.width) + " x " + std::to_string(f.height));
  }
  return compare_pixels(
      f,
      [&](size_t p) {
        const uint8_t* r = ref.rgb.data() + 3 * p;
        return r[0] != clear[0] || r[1] != clear[1] || r[2] != clear[2];
      },
      [&](size_t p) { return ref.rgb.data() + 3 * p; });
}

FrameComparison compare_with_truth(const RenderedFrame& f) {
  if (!f.has_truth()) return {};
  return compare_pixels(
      f, [&](size_t p) { return f.truth_drawn[p] != 0; },
      [&](size_t p) { return f.truth_rgba.data() + 4 * p; });
}

std::vector<uint8_t> difference_image(const RenderedFrame& f, const Rgb8Image& ref, double gain,
                                      const uint8_t clear[3]) {
  const size_t n = static_cast<size_t>(f.width) * static_cast<size_t>(f.height);
  std::vector<uint8_t> out(n, 0);
  for (size_t p = 0; p < n && p * 3 + 2 < ref.rgb.size(); ++p) {
    const uint8_t* r = ref.rgb.data() + 3 * p;
    const bool ref_drawn = r[0] != clear[0] || r[1] != clear[1] || r[2] != clear[2];
    if (ref_drawn != (f.drawn[p] != 0)) out[p] = 255;  // drawn by one only
    if (!ref_drawn || !f.drawn[p]) continue;
    int worst = 0;
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(static_cast<int>(f.rgba[4 * p + static_cast<size_t>(k)]) -
                                       static_cast<int>(ref.rgb[3 * p + static_cast<size_t>(k)])));
    out[p] = static_cast<uint8_t>(std::min(255.0, worst * gain));
  }
  return out;
}

}  // namespace texsim
