#pragma once
// `texsim study filters`: every anisotropic filter method and variant (EWA, weight maps,
// multi-ellipse probes, Feline, SPAF, the trilinear baselines, OpenImageIO's TextureSystem and
// Mesa's softpipe and llvmpipe)
// on the same planes at anisotropy 1:1 … 64:1, against two ground truths (a Gaussian pixel and
// a box pixel; the ranking of the filters depends on which):
// PSNR, NMSE, max error, ops per fragment by kind, texels fetched, cache misses and cycles per
// fragment (docs/studies/study-filters.md explains the set-up and the results).
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"

namespace texsim {

struct StudyFiltersOptions {
  int size = 128;                                               // image width = height (pixels)
  std::vector<double> anisotropies = {1, 2, 4, 8, 16, 32, 64};  // nominal, at the image centre
  double texels_per_pixel = 1.5;  // minor axis at the centre (level-0 texels)
  bool oiio = true;               // include OpenImageIO's TextureSystem
  bool mesa = true;  // include Mesa's softpipe and llvmpipe where they start (else skipped)
  bool write_images = false;  // also write each view's images (PNG)
  int threads = 0;            // worker threads (0: one per core); the outputs do not depend on it
};

// Writes filters.csv, filters_truths.csv, filters.md, filters.png (NMSE against cycles per
// fragment) and filters_texels.png (NMSE against texels fetched per fragment) into out_dir; returns
// 0. Progress and a summary go to `log`.
int run_study_filters(const std::string& out_dir, std::ostream& log);
int run_study_filters(const std::string& out_dir, std::ostream& log,
                      const StudyFiltersOptions& opt);

// The fragments of the study's view at nominal anisotropy `aniso` for a texture of
// `texture_size` texels square, in pixel order (what every method filters).
std::vector<Fragment> study_filter_fragments(double aniso, const StudyFiltersOptions& opt,
                                             int texture_size);

}  // namespace texsim
