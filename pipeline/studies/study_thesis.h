#pragma once
// `texsim study thesis`: the thesis configuration (the seed's weight-map transform, formula (5),
// and θ/L/d weight rule, no reconstruction term) beside texsim's own, on shipped scenes: the
// NMSE between weight-map and computed-weight images (the seed: 0.000708), the weight maps'
// speed-up against computed weights and against the V(d) sub-texel weights (the seed: +25 %),
// and the cost of computing weights against uniform ones (the seed: ≤ 5 %), in the pipelined
// texture unit (cycles) and in the shader-like issue model at ALU : texture 4 : 1 (the filter
// study's) and 16 : 1 (the thesis's Radeon RX 460). docs/studies/thesis-configuration.md.
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/studies/shipped_scenes.h"

namespace texsim {

struct StudyThesisOptions {
  std::vector<std::string> scenes = {shipped_scenes_dir() + "/footprint_filters.toml",
                                     shipped_scenes_dir() + "/photo.toml"};
};

// One method over one source (a scene, or a view in tests): totals.
struct ThesisMethodFigures {
  std::string method;
  uint64_t fragments = 0, texels = 0, cycles = 0;
  double shader_4to1 = 0, shader_16to1 = 0;  // shader-like model's cycles, summed
};

// A source's figures: every method of thesis_filter_methods(), and the NMSE of each map (and
// of the thesis weights) against its computed counterpart, Σ(a − b)²/Σb² over RGB.
struct ThesisFigures {
  std::string source;
  std::vector<ThesisMethodFigures> methods;
  struct Pair {
    std::string image, against;
    double nmse = 0;
  };
  std::vector<Pair> nmse;
  const ThesisMethodFigures& at(const std::string& method) const;
};

// Runs every thesis method over `fragments` (texture 0 of `textures`).
ThesisFigures measure_thesis(const std::string& source, TextureSet& textures,
                             const std::vector<Fragment>& fragments);

// Writes thesis.md and thesis.csv into out_dir; returns 0. Progress goes to `log`.
int run_study_thesis(const std::string& out_dir, std::ostream& log, const StudyThesisOptions& opt);

}  // namespace texsim
