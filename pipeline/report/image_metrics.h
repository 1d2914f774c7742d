#pragma once
// Rendered and reference images, their error metrics and PNG output (via OpenImageIO).
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

namespace texsim {

struct ImageRgb {
  int width = 0, height = 0;
  std::vector<float> rgb;        // 3 floats per pixel
  std::vector<uint8_t> covered;  // 1 where a fragment wrote
  std::vector<int32_t> label;    // what wrote each pixel (e.g. its material); -1 = nothing
  ImageRgb(int w, int h, glm::dvec3 background);
  void set(int x, int y, const glm::vec4& c, int32_t lbl = 0);
  // Grows the image (keeping its pixels); new pixels get `background`.
  void resize(int w, int h, glm::dvec3 background);
};

struct AccuracyMetrics {
  uint64_t pixels = 0;  // covered pixels compared
  double mse = 0;       // mean squared error over R, G, B
  double psnr_db = 0;   // 10 log10(1 / mse), peak 1.0; +inf written as 999 when mse = 0
  double nmse = 0;      // Σ err² / Σ ref²
  double max_abs = 0;   // largest per-channel absolute error
  double mean_abs = 0;
};

// Compares the covered pixels of `img` with `ref` (same size); with `only_label` >= 0, only
// the pixels of img labelled so.
AccuracyMetrics compare_images(const ImageRgb& img, const ImageRgb& ref, int32_t only_label = -1);

// Writes an 8-bit PNG (or any OIIO format by extension) atomically; throws InputError.
void write_image(const std::string& path, const ImageRgb& img);
// Heat map of max-channel absolute error, scaled so `scale` maps to the hottest colour.
void write_error_heatmap(const std::string& path, const ImageRgb& img, const ImageRgb& ref,
                         double scale);

}  // namespace texsim
