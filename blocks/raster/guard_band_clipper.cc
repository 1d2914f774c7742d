#include "blocks/raster/guard_band_clipper.h"

#include <algorithm>
#include <cmath>

namespace texsim {

double guard_band_margin(int subpixel_bits) {
  return std::ldexp(1.0, EdgeRasterizer::kCoordBits - subpixel_bits - 1);
}

namespace {

// Keeps the part of `poly` where s·(coordinate axis) <= s·limit (axis 0: x, 1: y).
std::vector<ScreenVertex> clip_axis(const std::vector<ScreenVertex>& poly, int axis, double limit,
                                    double s) {
  std::vector<ScreenVertex> out;
  const size_t n = poly.size();
  auto coord = [axis](const ScreenVertex& p) { return axis == 0 ? p.x : p.y; };
  auto inside = [&](const ScreenVertex& p) { return s * coord(p) <= s * limit; };
  for (size_t i = 0; i < n; ++i) {
    const ScreenVertex& a = poly[i];
    const ScreenVertex& b = poly[(i + 1) % n];
    const bool ia = inside(a), ib = inside(b);
    if (ia) out.push_back(a);
    if (ia == ib) continue;
    const long double t = (static_cast<long double>(limit) - coord(a)) /
                          (static_cast<long double>(coord(b)) - coord(a));
    ScreenVertex c;
    c.x = axis == 0 ? limit : static_cast<double>(a.x + t * (static_cast<long double>(b.x) - a.x));
    c.y = axis == 1 ? limit : static_cast<double>(a.y + t * (static_cast<long double>(b.y) - a.y));
    c.w = static_cast<double>(a.w + t * (static_cast<long double>(b.w) - a.w));
    out.push_back(c);
  }
  return out;
}

}  // namespace

std::vector<ScreenVertex> clip_to_guard_band(const std::vector<ScreenVertex>& poly,
                                             const Scissor& sc, double margin) {
  std::vector<ScreenVertex> p = poly;
  p = clip_axis(p, 0, sc.x1 + margin, 1);
  p = clip_axis(p, 0, sc.x0 - margin, -1);
  p = clip_axis(p, 1, sc.y1 + margin, 1);
  p = clip_axis(p, 1, sc.y0 - margin, -1);
  return p;
}

std::vector<ScreenVertex> within_guard_band(const std::vector<ScreenVertex>& poly,
                                            const Scissor& sc, int subpixel_bits) {
  const double margin = guard_band_margin(subpixel_bits);
  const auto beyond = [&](const ScreenVertex& v) {
    return !(v.x >= sc.x0 - margin && v.x <= sc.x1 + margin && v.y >= sc.y0 - margin &&
             v.y <= sc.y1 + margin);
  };
  const bool all_finite = std::all_of(poly.begin(), poly.end(), [](const ScreenVertex& v) {
    return std::isfinite(v.x) && std::isfinite(v.y);
  });
  return all_finite && std::any_of(poly.begin(), poly.end(), beyond)
             ? clip_to_guard_band(poly, sc, margin)
             : poly;
}

std::vector<RowSpan> rasterize_convex(const EdgeRasterizer& r,
                                      const std::vector<ScreenVertex>& poly, const Scissor& sc,
                                      EdgeRasterStats* stats) {
  const std::vector<ScreenVertex> p = within_guard_band(poly, sc, r.config().subpixel_bits);
  std::vector<RowSpan> spans;
  for (size_t i = 1; i + 1 < p.size(); ++i) {
    const ScreenVertex tri[3] = {p[0], p[i], p[i + 1]};
    const std::vector<RowSpan> t = r.rasterize(tri, sc, stats);
    spans.insert(spans.end(), t.begin(), t.end());
  }
  if (p.size() <= 3) return spans;
  // The fan's triangles tile the convex polygon: per row their spans are adjacent.
  std::sort(spans.begin(), spans.end(), [](const RowSpan& a, const RowSpan& b) {
    return a.y != b.y ? a.y < b.y : a.x0 < b.x0;
  });
  std::vector<RowSpan> rows;
  for (const RowSpan& s : spans) {
    if (!rows.empty() && rows.back().y == s.y && rows.back().x0 + rows.back().n == s.x0) {
      rows.back().n += s.n;
    } else {
      rows.push_back(s);
    }
  }
  return rows;
}

}  // namespace texsim
