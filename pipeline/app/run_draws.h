#pragma once
// `texsim run --draws FILE`: renders one frame of a draw trace (traces/DRAWS.md) through the
// draw renderer, the texture unit and the colour stage, and writes image.png, report.json and
// report.md (the texture unit's figures and the draw-level counts); with --compare, the frame
// against the application's own image of it.
#include <iosfwd>
#include <string>

#include "pipeline/app/run.h"
#include "pipeline/render/frame_compare.h"

namespace texsim {

struct DrawRunOptions {
  RunOptions run;       // scene (for [pipeline], [tech]), out, functional, frame, overrides
  std::string draws;    // the draw trace
  std::string compare;  // the application's image of the frame (PNG); "" = none
};

struct DrawRunSummary {
  RenderedFrame frame;
  uint64_t unit_fragments = 0, cycles = 0;
  bool compared = false;
  FrameComparison comparison;
  FrameComparison truth;   // the frame against the frame shaded with the truth's texels
  std::string truth_text;  // how the truth samples each pixel
  double seconds = 0;      // rendering the frame (wall clock)
};

DrawRunSummary run_draws(const DrawRunOptions& opt, std::ostream& log);

}  // namespace texsim
