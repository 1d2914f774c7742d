#pragma once
// `texsim study frames`: every frame of a draw trace (a capture of a real application,
// traces/DRAWS.md) rendered through the clocked texture unit, one frame per task of the study
// pool: per frame the draw counts, texture look-ups, cycles, L1 and DRAM figures, the look-ups'
// and the frame's error against the ground truth, and the frame against the application's own
// image where one exists (docs/studies/study-frames.md).
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "pipeline/render/draw_renderer.h"
#include "pipeline/render/frame_compare.h"

namespace texsim {

struct StudyFramesOptions {
  std::string draws;   // draw trace; "": the shipped sample
  std::string frames;  // "A-B" or "A": frame numbers of the capture; "": every frame
  // Folder of the application's images (frame_NNNN.png, as scripts/capture-openarena.sh writes
  // them); "": the folder named like the trace without its extension, when it exists.
  std::string images;
  bool truth = true;  // false: no ground truth (--reference none)
  int threads = 0;    // frames in parallel (0: one per core); the outputs do not depend on it
};

struct FrameStudyRow {
  uint32_t frame = 0;
  DrawRenderCounts counts;
  uint64_t lookups = 0, cycles = 0;
  uint64_t l1_accesses = 0, l1_hits = 0, dram_bytes = 0;
  LookupAccuracy accuracy;  // look-ups against the truth (empty without one)
  FrameComparison truth;    // the frame against the frame shaded with the truth's texels
  bool has_image = false;   // the application's image of the frame was found
  FrameComparison image;    // the frame against it
  double seconds = 0;       // rendering the frame, truth included (wall clock of its task)
};

// Renders the frames, writes frames.csv, frames.md, frames_psnr.png and frames_cycles.png into
// out_dir; returns 0. With `rows` set, the rows are copied there.
int run_study_frames(const std::string& out_dir, std::ostream& log, const StudyFramesOptions& opt,
                     std::vector<FrameStudyRow>* rows = nullptr);

}  // namespace texsim
