#pragma once
// Rendered and reference images, their error metrics and PNG output (libpng).
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

namespace texsim {

// A pixel buffer placed on a canvas: the buffer holds the part of the written image that
// fragments can reach (x0, y0, width, height); canvas pixels outside it are the background.
struct ImageRgb {
  int width = 0, height = 0;                // the buffer
  int x0 = 0, y0 = 0;                       // its top-left pixel on the canvas
  int canvas_width = 0, canvas_height = 0;  // the image written
  glm::vec3 background{0.0f};
  std::vector<float> rgb;        // 3 floats per pixel
  std::vector<uint8_t> covered;  // 1 where a fragment wrote
  std::vector<int32_t> label;    // what wrote each pixel (e.g. its material); -1 = nothing
  // A w × h image that is all buffer.
  ImageRgb(int w, int h, glm::dvec3 background);
  // A w × h buffer at (x0, y0) of a canvas_w × canvas_h image.
  ImageRgb(int x0, int y0, int w, int h, int canvas_w, int canvas_h, glm::dvec3 background);
  // Canvas coordinates; pixels outside the buffer are ignored.
  void set(int x, int y, const glm::vec4& c, int32_t lbl = 0);
  // Every pixel back to the background, none covered.
  void clear();
  // Bytes a buffer of `pixels` pixels holds.
  static constexpr uint64_t kBytesPerPixel = 3 * sizeof(float) + 1 + sizeof(int32_t);
};

struct AccuracyMetrics {
  uint64_t pixels = 0;  // covered pixels compared
  double mse = 0;       // mean squared error over R, G, B
  double psnr_db = 0;   // 10 log10(1 / mse), peak 1.0; +inf written as 999 when mse = 0
  double nmse = 0;      // Σ err² / Σ ref²
  double max_abs = 0;   // largest per-channel absolute error
  double mean_abs = 0;
};

// Sums behind AccuracyMetrics, so that several images (frames) pool into one figure.
struct ErrorSums {
  uint64_t pixels = 0;
  double se = 0, sref = 0, sabs = 0;  // Σ err², Σ ref², Σ |err| over R, G, B
  double max_abs = 0;
  void add(const ErrorSums& o);
  AccuracyMetrics metrics() const;
};

// Compares the covered pixels of `img` with `ref` (same size); with `only_label` >= 0, only
// the pixels of img labelled so.
AccuracyMetrics compare_images(const ImageRgb& img, const ImageRgb& ref, int32_t only_label = -1);
// The sums of compare_images: [0] over all covered pixels, [1 + l] over pixels labelled l for
// l < labels (one pass).
std::vector<ErrorSums> error_sums(const ImageRgb& img, const ImageRgb& ref, int labels);

// Writes an 8-bit PNG through libpng (any other extension: the format OpenImageIO writes for
// it, through its plugin) atomically; throws InputError naming the file and the reason.
void write_image(const std::string& path, const ImageRgb& img);
// Heat map of max-channel absolute error: black (0) through red and yellow to white (`scale`
// and above). Below the image (which keeps its size and pixels) a colour bar of
// colour_bar_rows() rows: two black rows, then the ramp from 0 at the left to `scale` at the
// right (max(8, height / 12) rows in all), its last two rows with grey ticks at 0, ¼, ½, ¾ and
// 1 of the width; then the ticks' values in 8-bit levels ("LSB", 1/255 of full scale) as text
// (label_font.h) on black, 7·s + 4 rows with s = max(1, height / 240).
std::array<uint8_t, 3> heat_colour(double t);  // t = error / scale
int colour_bar_rows(int canvas_height);
void write_error_heatmap(const std::string& path, const ImageRgb& img, const ImageRgb& ref,
                         double scale);

}  // namespace texsim
