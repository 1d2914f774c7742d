#include "blocks/raster/splat_resolve.h"

#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<SplatResolve>);

SplatBuffer::SplatBuffer(int w, int h)
    : width(w),
      height(h),
      rgba(static_cast<size_t>(w) * static_cast<size_t>(h) * 4, 0.0),
      weight(static_cast<size_t>(w) * static_cast<size_t>(h), 0.0),
      depth(static_cast<size_t>(w) * static_cast<size_t>(h), 0.0) {}

SplatResolve::Config SplatResolve::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"lanes"});
  Config c;
  c.lanes = static_cast<int>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

void SplatResolve::weights(double x, double y, int& i, int& j, double s[4]) {
  const double xt = x - 0.5, yt = y - 0.5;
  const double fi = std::floor(xt), fj = std::floor(yt);
  const double fx = xt - fi, fy = yt - fj;
  i = static_cast<int>(fi);
  j = static_cast<int>(fj);
  s[0] = (1 - fx) * (1 - fy);
  s[1] = fx * (1 - fy);
  s[2] = (1 - fx) * fy;
  s[3] = fx * fy;
}

void SplatResolve::splat(SplatBuffer& b, double x, double y, double z, double tol, const Rgba& c,
                         SplatStats& st, OpCounts& ops) const {
  ops += ops_per_item();
  ++st.samples;
  // Far outside the image (or not finite): no target can be on it.
  if (!(x > -1 && y > -1 && x < b.width + 1 && y < b.height + 1)) {
    st.offscreen += 4;
    return;
  }
  int i = 0, j = 0;
  double s[4];
  weights(x, y, i, j, s);
  for (int k = 0; k < 4; ++k) {
    const int px = i + (k & 1), py = j + (k >> 1);
    if (px < 0 || py < 0 || px >= b.width || py >= b.height) {
      ++st.offscreen;
      continue;
    }
    const size_t at = b.index(px, py);
    st.bytes_read += kEntryBytes;
    double& w = b.weight[at];
    double& d = b.depth[at];
    if (w > 0 && z > d + tol) {  // behind the surface already accumulated here
      ++st.depth_dropped;
      continue;
    }
    if (w > 0 && z < d - tol) {  // a nearer surface: start the pixel again
      ++st.depth_resets;
      w = 0;
      for (int ch = 0; ch < 4; ++ch) b.rgba[at * 4 + static_cast<size_t>(ch)] = 0;
    }
    d = w > 0 ? std::min(d, z) : z;
    w += s[k];
    for (int ch = 0; ch < 4; ++ch) b.rgba[at * 4 + static_cast<size_t>(ch)] += s[k] * c[ch];
    ++st.targets;
    st.bytes_written += kEntryBytes;
  }
}

ResolveStats SplatResolve::resolve(const SplatBuffer& b, const std::vector<uint8_t>& covered,
                                   const Rgba& background, std::vector<Rgba>& out,
                                   OpCounts& ops) const {
  ResolveStats rs;
  const size_t n = b.weight.size();
  out.assign(n, background);
  for (size_t p = 0; p < n; ++p) {
    rs.bytes_read += kEntryBytes;
    rs.bytes_written += kOutputBytes;
    const bool cov = p < covered.size() && covered[p] != 0;
    rs.expected += cov;
    ops.cmp += 1;
    // Σ S is a sum of non-negative weights: > 0 or exactly 0, never negative or NaN here.
    if (!(b.weight[p] > 0)) {
      rs.holes += cov;
      continue;
    }
    ops += pixel_ops();
    const double inv = 1.0 / b.weight[p];
    for (int ch = 0; ch < 4; ++ch)
      out[p][ch] = static_cast<float>(b.rgba[p * 4 + static_cast<size_t>(ch)] * inv);
    ++rs.pixels;
  }
  return rs;
}

OpCounts SplatResolve::ops_per_item() const {
  // Weights: 2 add (half-pixel), 2 floor (cmp), 2 add (fractions), 2 add 4 mul (S1..S4).
  // Per target: 2 cmp (depth window, 2 add for d ± tol), 4 mul 5 add (Σ S·I and Σ S), 1 cmp
  // (min depth), 1 mem (read-modify-write of the entry).
  OpCounts o;
  o.add = 6 + 4 * (2 + 5);
  o.mul = 4 + 4 * 4;
  o.cmp = 2 + 4 * 3;
  o.mem = 4;
  return o;
}

OpCounts SplatResolve::pixel_ops() const {
  OpCounts o;
  o.rcp = 1;
  o.mul = 4;
  o.mem = 1;
  return o;
}

TimingSpec SplatResolve::timing(const TechTable& t) const {
  // Critical path of a target: the weight multiply, the depth compare, the accumulate.
  OpCounts path;
  path.mul = 2;
  path.add = 2;
  path.cmp = 1;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial,
                       static_cast<uint32_t>(cfg_.lanes), pixel_ops());
}

}  // namespace texsim
