#include "blocks/texture/relief/visibility_aware_filter.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<VisibilityAwareFilter>);

namespace {

struct RowTexel {
  int32_t x;
  double w;
};

// The running sums of one lookup and the buffer of counted texels.
struct Accumulator {
  const VisibilityAwareFilter::ColourMap& tex;
  VisibilityAwareFilter::Stats& st;
  std::vector<ReliefRead>* log;
  std::unordered_set<int64_t> counted;
  glm::dvec4 sum{0.0};
  double wsum = 0;

  static int64_t key(int32_t x, int32_t y) {
    return (static_cast<int64_t>(y) << 32) ^ static_cast<int64_t>(static_cast<uint32_t>(x));
  }
  // Counts texel (x, y) with weight w unless the buffer already holds it.
  void count(int32_t x, int32_t y, double w) {
    if (!counted.insert(key(x, y)).second) {
      ++st.buffer_hits;
      return;
    }
    ++st.colour_reads;
    if (log) {
      log->push_back({std::clamp(x, 0, tex.width - 1), std::clamp(y, 0, tex.height - 1),
                      ReliefRead::kColourRead});
    }
    sum += w * glm::dvec4(tex.texel(x, y));
    wsum += w;
  }
};

}  // namespace

glm::vec4 VisibilityAwareFilter::ColourMap::texel(int32_t x, int32_t y) const {
  if (width <= 0 || height <= 0) return glm::vec4(0.0F);
  x = std::clamp(x, 0, width - 1);
  y = std::clamp(y, 0, height - 1);
  return c[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
}

VisibilityAwareFilter::Config VisibilityAwareFilter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"depth_texels", "trace_step", "max_trace_steps", "min_view_z", "max_radius",
                    "row_rule", "visibility", "datapath"});
  Config c;
  c.depth_texels = r.get_double("depth_texels", c.depth_texels);
  c.trace_step = r.get_double("trace_step", c.trace_step);
  c.max_trace_steps =
      static_cast<int32_t>(r.get_int("max_trace_steps", c.max_trace_steps, 1, 4096));
  c.min_view_z = r.get_double("min_view_z", c.min_view_z);
  c.max_radius = static_cast<int32_t>(r.get_int("max_radius", c.max_radius, 1, 256));
  c.row_rule = r.get_bool("row_rule", c.row_rule);
  c.visibility = r.get_bool("visibility", c.visibility);
  c.datapath = parse_datapath(r, c.datapath);
  if (!(c.depth_texels >= 0 && c.depth_texels <= 1024)) {
    r.fail("depth_texels", "must be in [0, 1024]");
  }
  if (!(c.trace_step > 0 && c.trace_step <= 8)) r.fail("trace_step", "must be in (0, 8]");
  if (!(c.min_view_z > 0 && c.min_view_z <= 1)) r.fail("min_view_z", "must be in (0, 1]");
  return c;
}

bool VisibilityAwareFilter::visible(const ReliefHeightMap& hm, int32_t x, int32_t y, double nx,
                                    double ny, double nz, int32_t& ox, int32_t& oy, uint32_t& reads,
                                    bool& capped, std::vector<ReliefRead>* log) const {
  const double d0 = (1.0 - hm.texel(x, y)) * cfg_.depth_texels;
  for (int32_t k = 1; k <= cfg_.max_trace_steps; ++k) {
    const double s = k * cfg_.trace_step;
    const double depth = d0 - nz * s;
    if (depth <= 0) return true;  // above the relief's top
    const auto ix = static_cast<int32_t>(std::floor(x + nx * s + 0.5));
    const auto iy = static_cast<int32_t>(std::floor(y + ny * s + 0.5));
    if (ix < 0 || iy < 0 || ix >= hm.width || iy >= hm.height) return true;  // off the map
    if (ix == x && iy == y) continue;  // a texel does not hide itself
    ++reads;
    if (log) log->push_back({ix, iy, ReliefRead::kHeightRead});
    if ((1.0 - hm.texel(ix, iy)) * cfg_.depth_texels < depth - 1e-9) {
      ox = ix;
      oy = iy;
      return false;
    }
  }
  capped = true;
  return true;
}

VisibilityAwareFilter::Result VisibilityAwareFilter::filter(const ReliefHeightMap& hm,
                                                            const ColourMap& tex,
                                                            const Footprint& fp, double vx,
                                                            double vy, double vz, OpCounts& ops,
                                                            std::vector<ReliefRead>* log) const {
  Result res;
  Stats& st = res.stats;
  const double len = std::sqrt(vx * vx + vy * vy + vz * vz);
  const bool view_ok = std::isfinite(len) && len > 0;
  const bool fp_ok = std::isfinite(fp.u) && std::isfinite(fp.v) && std::isfinite(fp.ux) &&
                     std::isfinite(fp.vx) && std::isfinite(fp.uy) && std::isfinite(fp.vy);
  if (!fp_ok || hm.width <= 0 || hm.height <= 0) {
    st.fallback = true;
    return res;
  }
  const bool vis = cfg_.visibility && view_ok;
  st.fallback = cfg_.visibility && !view_ok;
  const double nx = view_ok ? vx / len : 0, ny = view_ok ? vy / len : 0;
  const double nz = view_ok ? std::max(vz / len, cfg_.min_view_z) : 1;
  // EWA conic with the unit reconstruction filter added: A du² + B du dv + C dv² < F, whose
  // half extents are √C along u and √A along v.
  const double a = fp.vx * fp.vx + fp.vy * fp.vy + 1, c = fp.ux * fp.ux + fp.uy * fp.uy + 1;
  const double b = -2 * (fp.ux * fp.vx + fp.uy * fp.vy), f = a * c - b * b / 4;
  const double ru = std::min(std::sqrt(c), static_cast<double>(cfg_.max_radius));
  const double rv = std::min(std::sqrt(a), static_cast<double>(cfg_.max_radius));
  Accumulator acc{tex, st, log, {}, glm::dvec4(0.0), 0};
  std::vector<RowTexel> row;
  const auto y0 = static_cast<int32_t>(std::ceil(fp.v - rv));
  const auto y1 = static_cast<int32_t>(std::floor(fp.v + rv));
  const auto x0 = static_cast<int32_t>(std::ceil(fp.u - ru));
  const auto x1 = static_cast<int32_t>(std::floor(fp.u + ru));
  for (int32_t y = y0; y <= y1; ++y) {
    row.clear();
    for (int32_t x = x0; x <= x1; ++x) {
      const double du = x - fp.u, dv = y - fp.v;
      const double q = (a * du * du + b * du * dv + c * dv * dv) / f;
      if (q < 1) row.push_back({x, std::exp(-2 * q)});
    }
    st.texels += static_cast<uint32_t>(row.size());
    // One texel: trace it (if visibility is on), then count it or the texel that hides it.
    auto visit = [&](const RowTexel& t) {
      if (!vis) {
        acc.count(t.x, y, t.w);
        return true;
      }
      int32_t ox = 0, oy = 0;
      bool capped = false;
      ++st.traced;
      const bool seen = visible(hm, t.x, y, nx, ny, nz, ox, oy, st.trace_reads, capped, log);
      st.capped += capped ? 1 : 0;
      (seen ? st.visible : st.hidden) += 1;
      if (seen) {
        acc.count(t.x, y, t.w);
      } else {
        acc.count(ox, oy, t.w);
      }
      return seen;
    };
    const auto n = static_cast<int32_t>(row.size());
    int32_t stop = n;  // the forward scan's first hidden texel
    for (int32_t i = 0; i < n; ++i) {
      if (!visit(row[static_cast<size_t>(i)]) && vis && cfg_.row_rule) {
        stop = i;
        break;
      }
    }
    int32_t back = n;  // the backward scan's first hidden texel
    for (int32_t j = n - 1; j > stop; --j) {
      if (!visit(row[static_cast<size_t>(j)])) {
        back = j;
        break;
      }
    }
    if (stop < n && back < n) st.skipped += static_cast<uint32_t>(back - stop - 1);
  }
  OpCounts o = ops_per_item() * st.texels + trace_step_ops() * st.trace_reads;
  o.cmp += st.traced + st.colour_reads + st.buffer_hits;  // buffer look-ups
  o.mem += st.colour_reads;
  ops += o;
  if (!(acc.wsum > 0)) {
    st.fallback = true;
    res.colour = tex.texel(static_cast<int32_t>(std::floor(fp.u + 0.5)),
                           static_cast<int32_t>(std::floor(fp.v + 0.5)));
    return res;
  }
  res.colour = glm::vec4(acc.sum / acc.wsum);
  return res;
}

OpCounts VisibilityAwareFilter::ops_per_item() const {
  // The conic (5 mul, 3 add, 1 mul by 1/F), the range test, exp(-2q) (1 lut, 1 mul), the
  // weighted accumulate of 4 channels and the weight sum; the colour read is counted per
  // texel actually read.
  OpCounts o;
  o.mul = 5 + 1 + 1 + 4;
  o.add = 3 + 4 + 1;
  o.cmp = 1;
  o.lut = 1;
  return o;
}

OpCounts VisibilityAwareFilter::trace_step_ops() const {
  // Position (2 mul, 2 add), depth (1 mul, 1 add), rounding (2 add), the height read, the
  // surface depth (1 mul, 1 add) and the compare, bounds (2 cmp).
  OpCounts o;
  o.mul = 4;
  o.add = 6;
  o.mem = 1;
  o.cmp = 3;
  return o;
}

OpCounts VisibilityAwareFilter::critical_path() const {
  OpCounts p;
  p.mul = 3;
  p.add = 2;
  p.lut = 1;
  p.mem = 1;
  return p;
}

TimingSpec VisibilityAwareFilter::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath, 1, trace_step_ops());
}

}  // namespace texsim
