#include "blocks/raster/row_rasterizer.h"

#include <algorithm>
#include <cmath>

namespace texsim {

std::vector<RowSpan> rasterize_rows(const double x[3], const double y[3], int32_t w, int32_t h) {
  std::vector<RowSpan> rows;
  const long double area =
      (static_cast<long double>(x[1]) - x[0]) * (static_cast<long double>(y[2]) - y[0]) -
      (static_cast<long double>(x[2]) - x[0]) * (static_cast<long double>(y[1]) - y[0]);
  if (!(std::fabs(area) > 0) || !std::isfinite(area)) return rows;
  const long double sgn = area > 0 ? 1 : -1;
  long double ylo = std::min({y[0], y[1], y[2]}), yhi = std::max({y[0], y[1], y[2]});
  const int32_t j0 = static_cast<int32_t>(std::max<long double>(0, std::ceil(ylo)));
  const int32_t j1 = static_cast<int32_t>(std::min<long double>(h - 1, std::floor(yhi)));
  for (int32_t j = j0; j <= j1; ++j) {
    long double lo = 0, hi = w - 1;
    bool empty = false;
    for (int e = 0; e < 3; ++e) {
      const long double ax = x[e], ay = y[e], bx = x[(e + 1) % 3], by = y[(e + 1) % 3];
      // sgn·((bx-ax)(j-ay) - (by-ay)(xp-ax)) >= 0: c0 + c1·xp >= 0.
      const long double c1 = -sgn * (by - ay);
      const long double c0 = sgn * ((bx - ax) * (j - ay) + (by - ay) * ax);
      if (c1 > 0) {
        lo = std::max(lo, -c0 / c1);
      } else if (c1 < 0) {
        hi = std::min(hi, -c0 / c1);
      } else if (c0 < 0) {
        empty = true;
      }
    }
    if (empty) continue;
    const long double a = std::ceil(lo), b = std::floor(hi);
    if (a > b) continue;
    rows.push_back({static_cast<int32_t>(a), j, static_cast<int32_t>(b - a) + 1});
  }
  return rows;
}

}  // namespace texsim
