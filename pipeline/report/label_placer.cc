#include "pipeline/report/label_placer.h"

#include <array>

namespace texsim {

std::vector<PlacedLabel> place_labels(const std::vector<LabelRequest>& labels, const LabelBox& area,
                                      double marker) {
  std::vector<LabelBox> taken;
  taken.reserve(labels.size() * 2);
  for (const LabelRequest& l : labels) {
    const double h = marker / 2;
    taken.push_back({l.px - h, l.py - h, l.px + h, l.py + h});
  }
  std::vector<PlacedLabel> out(labels.size());
  for (size_t i = 0; i < labels.size(); ++i) {
    const LabelRequest& l = labels[i];
    const double w = l.width, ht = l.height;
    for (const double d : {marker / 2 + 2, marker + 12}) {
      // Top-left corners: right, left, above, below, then the four diagonals.
      const std::array<std::array<double, 2>, 8> at = {{
          {l.px + d, l.py - ht / 2},
          {l.px - d - w, l.py - ht / 2},
          {l.px - w / 2, l.py - d - ht},
          {l.px - w / 2, l.py + d},
          {l.px + d, l.py - d - ht},
          {l.px + d, l.py + d},
          {l.px - d - w, l.py - d - ht},
          {l.px - d - w, l.py + d},
      }};
      for (const auto& c : at) {
        const LabelBox b{c[0], c[1], c[0] + w, c[1] + ht};
        if (b.x0 < area.x0 || b.y0 < area.y0 || b.x1 > area.x1 || b.y1 > area.y1) continue;
        bool free = true;
        for (const LabelBox& t : taken) {
          if (b.overlaps(t, 1)) {
            free = false;
            break;
          }
        }
        if (!free) continue;
        out[i] = {true, b};
        taken.push_back(b);
        break;
      }
      if (out[i].placed) break;
    }
  }
  return out;
}

}  // namespace texsim
