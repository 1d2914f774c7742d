#include "pipeline/raster/primitive_raster.h"

#include <optional>
#include <vector>

#include "blocks/raster/guard_band_clipper.h"
#include "blocks/texture/coords/uv_constant_depth.h"

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
  coord_pixels += o.coord_pixels;
  coord_rejected += o.coord_rejected;
  coord_ops += o.coord_ops;
  hazards += o.hazards;
  return *this;
}

namespace {

void edge_triangles(const std::vector<ScreenVertex>& poly, const EdgeRasterizer& er,
                    const TechTable& tech, const Scissor& sc, RasterCounters& c,
                    const RasterVisit& visit) {
  EdgeRasterStats st;
  for (const RowSpan& s : rasterize_convex(er, poly, sc, &st)) {
    for (int32_t x = s.x0; x < s.x0 + s.n; ++x) visit(x, s.y, nullptr);
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

// The constant-depth coordinate block driven by the rectangle scan (seed 002 as one datapath):
// each run of a row gets its line's h, one reciprocal R = 1/q for the row and u += R·(A + B·k)
// per pixel. The map is normalised (q in (0.5, 1] over the primitive's polygon) so that the
// block's lower limit on q means the same in every scene.
struct RowCoords {
  UvConstantDepth block;
  MapCoeffs<double> mc;
  UvConstantDepth::Setup<double> st;
  std::vector<CoordSample> buf;
  RowCoords(const PlaneProjection& map, const std::vector<ScreenVertex>& poly) {
    std::vector<long double> xs, ys;
    for (const ScreenVertex& v : poly) {
      xs.push_back(v.x);
      ys.push_back(v.y);
    }
    mc = to_coeffs<double>(
        map.texel_map(1, 1).normalised(xs.data(), ys.data(), static_cast<int>(xs.size())));
    st = block.setup_triangle(mc);
  }
  // Coordinates of r's pixels (in r.pixels order: the runs are those pixels, run after run).
  void eval(const RectScanResult& r, RasterCounters& c) {
    buf.assign(r.pixels.size(), CoordSample{});
    size_t i = 0;
    for (const RectScanRun& run : r.runs) {
      block.eval_row(mc, st, UvConstantDepth::SlopedSpan{run.major0, run.h, run.n}, &buf[i]);
      i += static_cast<size_t>(run.n);
    }
    if (r.pixels.empty()) return;
    for (const CoordSample& s : buf) (s.valid ? c.coord_pixels : c.coord_rejected) += 1;
    c.coord_ops += block.triangle_setup_ops() + block.row_setup_ops() * r.stats.rows_textured +
                   block.ops_per_item() * r.stats.pixels_textured;
  }
};

void rect_scan_triangles(const std::vector<ScreenVertex>& poly, const PlaneProjection& map,
                         const RasterSetup& setup, const Scissor& sc, RasterCounters& c,
                         const RasterVisit& visit) {
  const RectScanRasterizer rs(setup.rect_scan);
  // The rows follow the primitive's constant-depth lines: q = G x + H y + I.
  const ProjectiveMap m = map.texel_map(1, 1);
  const RowLine line = rs.line_for_denominator(static_cast<double>(m.G), static_cast<double>(m.H));
  const std::vector<ScreenVertex> p = within_guard_band(poly, sc, rs.config().subpixel_bits);
  std::optional<RowCoords> coords;
  if (setup.constant_depth()) coords.emplace(map, p);
  for (size_t i = 1; i + 1 < p.size(); ++i) {
    const ScreenVertex tri[3] = {p[0], p[i], p[i + 1]};
    const RectScanResult r = rs.rasterize(tri, line, sc);
    ++c.triangles;
    if (r.reject != RasterReject::None) ++c.rejected;
    if (coords) coords->eval(r, c);
    for (size_t k = 0; k < r.pixels.size(); ++k) {
      const CoordSample* uv = coords && coords->buf[k].valid ? &coords->buf[k] : nullptr;
      visit(r.pixels[k].first, r.pixels[k].second, uv);
    }
    const RectScanStats& s = r.stats;
    c.rows += s.rows_scanned;
    c.pixels_visited += s.pixels_visited;
    c.pixels_covered += s.pixels_textured;
    c.divisions += s.rows_textured;
    c.fast_cycles += s.fast_cycles;
    c.memory_cycles += s.memory_cycles + s.prep_cycles;
    c.time_ns += s.time_ns;
    c.hazards += s.hazards;
    if (r.reject == RasterReject::None) {
      c.ops += rs.triangle_setup_ops() + rs.row_ops() * s.rows_scanned +
               rs.ops_per_item() * s.pixels_visited;
    }
  }
}

}  // namespace

void rasterize_primitive(const PlaneProjection& map, const RasterSetup& r, const TechTable& tech,
                         int width, int height, RasterCounters& c, const RasterVisit& visit) {
  if (map.culled()) return;
  std::vector<ScreenVertex> poly;
  for (const glm::dvec2& v : map.screen_polygon()) poly.push_back({v.x, v.y, 1});
  if (poly.size() < 3) return;
  ++c.primitives;
  const Scissor sc{0, 0, width, height};
  if (r.method == RasterSetup::Method::Edge) {
    edge_triangles(poly, EdgeRasterizer(r.edge), tech, sc, c, visit);
  } else {
    rect_scan_triangles(poly, map, r, sc, c, visit);
  }
}

}  // namespace texsim
