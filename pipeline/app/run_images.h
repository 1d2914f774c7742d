#pragma once
// The images of a `texsim run`, frame by frame. Buffers cover only the pixels fragments can
// reach (the extent); each frame is compared with its own ground truth when the next frame
// starts, its error sums pooled into the run's totals; one chosen frame's images are kept for
// writing. Memory: one buffer pair (two with more than one frame) of the extent.
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "pipeline/geometry/screen_extent.h"
#include "pipeline/report/image_metrics.h"
#include "pipeline/report/run_report.h"

namespace texsim {

class RunImages {
 public:
  // Estimated bytes of the buffers for `extent` (pairs: 1 or 2) and of writing a canvas.
  static uint64_t estimate_bytes(const PixelRect& extent, int pairs, int canvas_w, int canvas_h);

  // `keep_frame`: the frame whose images image()/reference() return; < 0: the first frame.
  RunImages(const PixelRect& extent, int canvas_w, int canvas_h, glm::dvec3 background,
            int materials, int64_t keep_frame);

  // Records one fragment of `frame` (frames arrive one after the other: a frame seen before
  // throws std::invalid_argument). colour null: not textured, the pixel keeps the background
  // and counts as an error.
  void set(uint32_t frame, int x, int y, const glm::vec4* colour, int material,
           const glm::dvec4& truth);
  // Compares the last frame; call once after the last fragment.
  void finish();

  uint64_t count() const { return count_; }
  bool has_kept_frame() const { return kept_ != nullptr; }
  uint32_t kept_frame() const { return kept_frame_; }
  const ImageRgb& image() const { return kept_->img; }
  const ImageRgb& reference() const { return kept_->ref; }
  const AccuracyMetrics& kept_accuracy() const { return kept_accuracy_; }
  // Pooled over every frame's covered pixels.
  AccuracyMetrics total() const { return total_[0].metrics(); }
  AccuracyMetrics material(int m) const { return total_[1 + static_cast<size_t>(m)].metrics(); }
  const std::vector<FrameAccuracy>& frames() const { return frames_; }

 private:
  struct Pair {
    ImageRgb img, ref;
  };
  std::unique_ptr<Pair> fresh_pair() const;
  void end_frame();

  PixelRect extent_;
  int canvas_w_, canvas_h_;
  glm::dvec3 background_;
  int materials_;
  int64_t keep_;
  std::unique_ptr<Pair> work_, kept_;
  bool in_frame_ = false;
  uint32_t frame_ = 0, kept_frame_ = 0;
  std::set<uint32_t> done_;
  AccuracyMetrics kept_accuracy_;
  std::vector<ErrorSums> total_;
  std::vector<FrameAccuracy> frames_;
  uint64_t count_ = 0;
};

}  // namespace texsim
