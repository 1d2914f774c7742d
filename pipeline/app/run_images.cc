#include "pipeline/app/run_images.h"

#include <algorithm>
#include <stdexcept>

#include "pipeline/scene/scene_memory.h"

namespace texsim {

uint64_t RunImages::estimate_bytes(const PixelRect& extent, int pairs, int canvas_w, int canvas_h) {
  // Each pair is an image and its reference; writing builds the buffer's 8-bit pixels and the
  // canvas's (3 bytes each) for one image at a time.
  // Saturating: an estimate that wraps would pass the --max-memory check.
  const uint64_t canvas = sat_mul(static_cast<uint64_t>(std::max(canvas_w, 0)),
                                  static_cast<uint64_t>(std::max(canvas_h, 0)));
  const uint64_t px = extent.pixels();
  return sat_add(
      sat_mul(sat_mul(static_cast<uint64_t>(std::max(pairs, 0)) * 2, px), ImageRgb::kBytesPerPixel),
      sat_mul(3, sat_add(px, canvas)));
}

RunImages::RunImages(const PixelRect& extent, int canvas_w, int canvas_h, glm::dvec3 background,
                     int materials, int64_t keep_frame)
    : extent_(extent),
      canvas_w_(canvas_w),
      canvas_h_(canvas_h),
      background_(background),
      materials_(materials),
      keep_(keep_frame),
      work_(fresh_pair()),
      total_(static_cast<size_t>(1 + materials)) {}

std::unique_ptr<RunImages::Pair> RunImages::fresh_pair() const {
  const int w = extent_.x1 - extent_.x0, h = extent_.y1 - extent_.y0;
  auto make = [&] {
    return ImageRgb(extent_.x0, extent_.y0, w, h, canvas_w_, canvas_h_, background_);
  };
  return std::make_unique<Pair>(Pair{make(), make()});
}

void RunImages::set(uint32_t frame, int x, int y, const glm::vec4* colour, int material,
                    const glm::dvec4& truth) {
  if (!in_frame_ || frame != frame_) {
    if (in_frame_) end_frame();
    if (done_.count(frame) != 0) {
      throw std::invalid_argument("frame " + std::to_string(frame) + " appears again after frame " +
                                  std::to_string(frame_) +
                                  " (a frame's fragments must be contiguous)");
    }
    if (!work_) work_ = fresh_pair();
    in_frame_ = true;
    frame_ = frame;
  }
  work_->img.set(x, y, colour ? *colour : glm::vec4(glm::dvec4(background_, 1.0)), material);
  work_->ref.set(x, y, glm::vec4(truth));
  ++count_;
}

void RunImages::end_frame() {
  const std::vector<ErrorSums> sums = error_sums(work_->img, work_->ref, materials_);
  for (size_t i = 0; i < sums.size(); ++i) total_[i].add(sums[i]);
  frames_.push_back({frame_, sums[0].metrics()});
  done_.insert(frame_);
  const bool keep = kept_ == nullptr && (keep_ < 0 || static_cast<int64_t>(frame_) == keep_);
  if (keep) {
    kept_ = std::move(work_);  // a fresh pair is made if another frame follows
    kept_frame_ = frame_;
    kept_accuracy_ = sums[0].metrics();
  } else {
    work_->img.clear();
    work_->ref.clear();
  }
  in_frame_ = false;
}

void RunImages::finish() {
  if (in_frame_) end_frame();
}

}  // namespace texsim
