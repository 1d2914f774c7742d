#pragma once
// Places text labels next to plotted points so that no two labels overlap each other or cover a
// point: each label tries eight positions around its point (right first), near then farther
// out; a label with no free position is left out, and the caller says how many were.
#include <string>
#include <vector>

namespace texsim {

struct LabelBox {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels, y down
  bool overlaps(const LabelBox& o, double gap) const {
    return x0 < o.x1 + gap && o.x0 < x1 + gap && y0 < o.y1 + gap && o.y0 < y1 + gap;
  }
};

struct LabelRequest {
  double px = 0, py = 0;  // the point, pixels (y down)
  double width = 0, height = 0;
};

struct PlacedLabel {
  bool placed = false;
  LabelBox box;  // where the text goes when placed
};

// Places `labels` (in order: earlier ones win) inside `area`, avoiding each other and every
// point of `labels` (a point is a `marker`-pixel square).
std::vector<PlacedLabel> place_labels(const std::vector<LabelRequest>& labels, const LabelBox& area,
                                      double marker = 8);

}  // namespace texsim
