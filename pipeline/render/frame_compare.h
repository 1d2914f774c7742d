#pragma once
// A rendered frame against the application's own image of it (e.g. glretrace's PNG of the
// same frame of the capture): which pixels both drew, and how close their colours are.
// Arithmetic: double sums of 8-bit differences.
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/render/draw_renderer.h"

namespace texsim {

// An 8-bit RGB image, the top row first.
struct Rgb8Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
};

// Reads a PNG (any 8-bit image OpenImageIO reads; alpha and further channels are ignored):
// 8-bit RGB PNGs through libpng, anything else through OpenImageIO's plugin, the same pixels
// either way. An unreadable file is an InputError naming it.
Rgb8Image read_rgb8_image(const std::string& path);

struct FrameComparison {
  uint64_t pixels = 0;       // of the image
  uint64_t drawn_both = 0;   // drawn by texsim and in the reference
  uint64_t drawn_agree = 0;  // drawn by both or by neither
  uint64_t drawn_texsim_only = 0, drawn_reference_only = 0;
  double drawn_agreement_pct = 0;   // drawn_agree / pixels, in %
  double mse = 0;                   // over the R, G, B of the pixels drawn by both, on [0, 1]
  double psnr_db = 0;               // 10 log10(1 / mse); 999 when equal
  double mean_abs = 0;              // mean |difference| per channel, in 8-bit steps
  uint64_t max_abs = 0;             // largest per-channel difference, in 8-bit steps
  uint64_t equal = 0;               // pixels drawn by both with the same R, G, B
  uint64_t off_by_more_than_8 = 0;  // pixels drawn by both with a channel more than 8 steps off
};

// The colour the application cleared the window to before the frame: ioquake3 with
// `r_clear 1` (scripts/capture-openarena.sh sets it) clears to (1, 0, 0.5).
inline constexpr uint8_t kClearPink[3] = {255, 0, 128};

// The reference has no coverage of its own: a pixel counts as drawn there when it differs from
// the colour the window was cleared to (`clear`, RGB8). Throws InputError when the sizes differ.
FrameComparison compare_frame(const RenderedFrame& f, const Rgb8Image& ref,
                              const std::string& ref_path, const uint8_t clear[3] = kClearPink);

// The frame against its own ground truth's frame (RenderedFrame::truth_rgba, truth_drawn): the
// same figures; all zero without a truth.
FrameComparison compare_with_truth(const RenderedFrame& f);

// |texsim − reference| per pixel drawn by both, the largest channel scaled by `gain`; 255 where
// only one drew, 0 where neither did (grey, the top row first).
std::vector<uint8_t> difference_image(const RenderedFrame& f, const Rgb8Image& ref, double gain,
                                      const uint8_t clear[3] = kClearPink);

}  // namespace texsim
