#include "pipeline/raster/primitive_raster.h"

#include <vector>

#include "blocks/raster/guard_band_clipper.h"

namespace texsim {

RasterCounters& RasterCounters::operator+=(const RasterCounters& o) {
  primitives += o.primitives;
  triangles += o.triangles;
  rejected += o.rejected;
  rows += o.rows;
  pixels_visited += o.pixels_visited;
  pixels_covered += o.pixels_covered;
  divisions += o.divisions;
  fast_cycles += o.fast_cycles;
  memory_cycles += o.memory_cycles;
  cycles += o.cycles;
  time_ns += o.time_ns;
  quads += o.quads;
  helper_lanes += o.helper_lanes;
  ops += o.ops;
  return *this;
}

namespace {

void edge_triangles(const std::vector<ScreenVertex>& poly, const EdgeRasterizer& er,
                    const TechTable& tech, const Scissor& sc, RasterCounters& c,
                    const std::function<void(int32_t, int32_t)>& visit) {
  EdgeRasterStats st;
  for (const RowSpan& s : rasterize_convex(er, poly, sc, &st)) {
    for (int32_t x = s.x0; x < s.x0 + s.n; ++x) visit(x, s.y);
  }
  c.triangles += st.triangles;
  c.rejected += st.rejected;
  c.rows += st.rows;
  c.pixels_visited += st.pixels_visited;
  c.pixels_covered += st.pixels_covered;
  c.ops += er.triangle_setup_ops() * st.triangles + er.row_ops() * st.rows +
           er.ops_per_item() * st.pixels_visited;
  const TimingSpec t = er.timing(tech);
  const uint64_t cycles = st.pixels_visited * t.ii / t.lanes;
  c.cycles += cycles;
  c.time_ns += static_cast<double>(cycles) * 1000.0 / tech.clock_mhz;
}

void rect_scan_triangles(const std::vector<ScreenVertex>& poly, const PlaneProjection& map,
                         const RectScanRasterizer& rs, const Scissor& sc, RasterCounters& c,
                         const std::function<void(int32_t, int32_t)>& visit) {
  // The rows follow the primitive's constant-depth lines: q = G x + H y + I.
  const ProjectiveMap m = map.texel_map(1, 1);
  const RowLine line = rs.line_for_denominator(static_cast<double>(m.G), static_cast<double>(m.H));
  const std::vector<ScreenVertex> p = within_guard_band(poly, sc, rs.config().subpixel_bits);
  for (size_t i = 1; i + 1 < p.size(); ++i) {
    const ScreenVertex tri[3] = {p[0], p[i], p[i + 1]};
    const RectScanResult r = rs.rasterize(tri, line, sc);
    ++c.triangles;
    if (r.reject != RasterReject::None) ++c.rejected;
    for (const auto& [x, y] : r.pixels) visit(x, y);
    const RectScanStats& s = r.stats;
    c.rows += s.rows_scanned;
    c.pixels_visited += s.pixels_visited;
    c.pixels_covered += s.pixels_textured;
    c.divisions += s.rows_textured;
    c.fast_cycles += s.fast_cycles;
    c.memory_cycles += s.memory_cycles + s.prep_cycles;
    c.time_ns += s.time_ns;
    if (r.reject == RasterReject::None) {
      c.ops += rs.triangle_setup_ops() + rs.row_ops() * s.rows_scanned +
               rs.ops_per_item() * s.pixels_visited;
    }
  }
}

}  // namespace

void rasterize_primitive(const PlaneProjection& map, const RasterSetup& r, const TechTable& tech,
                         int width, int height, RasterCounters& c,
                         const std::function<void(int32_t, int32_t)>& visit) {
  if (map.culled()) return;
  std::vector<ScreenVertex> poly;
  for (const glm::dvec2& v : map.screen_polygon()) poly.push_back({v.x, v.y, 1});
  if (poly.size() < 3) return;
  ++c.primitives;
  const Scissor sc{0, 0, width, height};
  if (r.method == RasterSetup::Method::Edge) {
    edge_triangles(poly, EdgeRasterizer(r.edge), tech, sc, c, visit);
  } else {
    rect_scan_triangles(poly, map, RectScanRasterizer(r.rect_scan), sc, c, visit);
  }
}

}  // namespace texsim
