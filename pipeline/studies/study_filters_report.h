#pragma once
// The tables and plots of `texsim study filters` (filters.csv, filters.md, filters.png,
// filters_texels.png), written through the shared study writer (study_table.h).
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "pipeline/report/image_metrics.h"
#include "pipeline/studies/study_filter_methods.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

// One texture × view × method.
struct FilterRow {
  std::string texture;
  double nominal = 0;
  double aniso_p50 = 0, aniso_p90 = 0;
  const StudyFilterMethod* method = nullptr;
  AccuracyMetrics acc;      // against the Gaussian-pixel truth
  double se = 0, sref = 0;  // Σ err², Σ ref² (for pooling)
  AccuracyMetrics acc_box;  // against the box-pixel truth
  double se_box = 0, sref_box = 0;
  uint64_t fragments = 0;
  StudyFilterRun run;                 // colours cleared once the row is measured
  double seconds = 0;                 // run time of the method on this view
  double se_pair = 0, sref_pair = 0;  // against method->compare_to's image
};

// One view's two ground truths against each other (the box truth compared with the Gaussian).
struct ViewTruths {
  std::string texture;
  double nominal = 0;
  AccuracyMetrics box_vs_gaussian;
};

void write_study_filters_outputs(const StudyFiles& files, const std::vector<FilterRow>& rows,
                                 const std::vector<ViewTruths>& truths,
                                 const std::vector<StudyFilterMethod>& methods,
                                 const StudyFiltersOptions& opt, std::ostream& log);

}  // namespace texsim
