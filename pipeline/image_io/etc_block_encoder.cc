#include "pipeline/image_io/etc_block_encoder.h"

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "blocks/texture/decode/etc_tables.h"

namespace texsim {

namespace {

using Rgb = std::array<int, 3>;

// The Khronos Data Format Specification's tables, as the decoders read them.
constexpr const auto& kEtcTables = etc_tables::kModifiers;
constexpr const auto& kEtcDistances = etc_tables::kDistances;
constexpr const auto& kEacTables = etc_tables::kEacModifiers;

void put(uint64_t& w, int lo, int n, int v) {
  const uint64_t mask = ((uint64_t{1} << n) - 1) << lo;
  w = (w & ~mask) | ((static_cast<uint64_t>(v) << lo) & mask);
}
int field(uint64_t w, int lo, int n) {
  return static_cast<int>((w >> lo) & ((uint64_t{1} << n) - 1));
}
// Quantise 0..255 to `bits` bits (nearest), and the spec's bit-replicated value of that.
int quant(int v, int bits) {
  const int top = (1 << bits) - 1;
  return (std::clamp(v, 0, 255) * top + 127) / 255;
}
int expand(int q, int bits) { return (q << (8 - bits)) | (q >> (2 * bits - 8)); }
int clamp8(int v) { return std::clamp(v, 0, 255); }
int sign_extend3(int v) { return v >= 4 ? v - 8 : v; }
// a / b rounded to nearest, halves away from zero (b > 0).
int div_round(int a, int b) { return a >= 0 ? (a + b / 2) / b : -((-a + b / 2) / b); }
Rgb rgb(const std::array<uint8_t, 4>& p) { return {p[0], p[1], p[2]}; }
int dist2(const Rgb& a, const Rgb& b) {
  int s = 0;
  for (size_t k = 0; k < 3; ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return s;
}
Rgb add(const Rgb& c, int d) { return {clamp8(c[0] + d), clamp8(c[1] + d), clamp8(c[2] + d)}; }
Rgb times17(const Rgb& q) { return {q[0] * 17, q[1] * 17, q[2] * 17}; }
Rgb mean(const EtcPixels& px, const std::vector<int>& which) {
  Rgb s{0, 0, 0};
  for (int i : which) {
    for (size_t k = 0; k < 3; ++k) s[k] += px[static_cast<size_t>(i)][k];
  }
  const int n = std::max<int>(1, static_cast<int>(which.size()));
  return {(s[0] + n / 2) / n, (s[1] + n / 2) / n, (s[2] + n / 2) / n};
}
bool transparent(const EtcPixels& px, int i, bool punch) {
  return punch && px[static_cast<size_t>(i)][3] < 128;
}
// The pixel's 2-bit index at its column-major place: msb at bit 16 + i, lsb at bit i.
void put_index(uint64_t& w, int x, int y, int idx) {
  const int i = x * 4 + y;
  put(w, 16 + i, 1, idx >> 1);
  put(w, i, 1, idx & 1);
}
int index_at(uint64_t w, int x, int y) {
  const int i = x * 4 + y;
  return field(w, 16 + i, 1) * 2 + field(w, i, 1);
}
EtcBlock bytes(uint64_t w) {
  EtcBlock b{};
  for (size_t i = 0; i < 8; ++i) b[i] = static_cast<uint8_t>(w >> (56 - 8 * i));
  return b;
}
uint64_t word(const EtcBlock& b) {
  uint64_t w = 0;
  for (uint8_t v : b) w = (w << 8) | v;
  return w;
}

// The mode an RGB ETC2 decoder reads from the word: the differential bit (RGB8 only), then
// which of R, G, B overflows its 5-bit range with the 3-bit delta added.
EtcMode mode_of(uint64_t w, bool punch) {
  if (!punch && field(w, 33, 1) == 0) return EtcMode::Individual;
  for (int c = 0; c < 3; ++c) {
    const int lo = 56 - 8 * c;
    const int s = field(w, lo + 3, 5) + sign_extend3(field(w, lo, 3));
    if (s < 0 || s > 31) return c == 0 ? EtcMode::T : c == 1 ? EtcMode::H : EtcMode::Planar;
  }
  return EtcMode::Differential;
}

// Sets the mode's free bits (`free`) so that the word selects `mode`.
uint64_t force_mode(uint64_t w, const std::vector<int>& free, EtcMode mode, bool punch) {
  for (uint32_t combo = 0; combo < (1U << free.size()); ++combo) {
    for (size_t k = 0; k < free.size(); ++k) put(w, free[k], 1, static_cast<int>((combo >> k) & 1));
    if (mode_of(w, punch) == mode) return w;
  }
  throw std::logic_error("etc_block_encoder: no free bits select the mode");
}

// The four colours an index picks in a subblock: base + a, + b, - a, - b (a = 0 when the
// punch-through opaque bit is clear).
std::array<Rgb, 4> subblock_colours(const Rgb& base, int table, bool opaque) {
  const int a = opaque ? kEtcTables[static_cast<size_t>(table)][0] : 0;
  const int b = kEtcTables[static_cast<size_t>(table)][1];
  return {add(base, a), add(base, b), add(base, -a), add(base, -b)};
}

// Chooses each pixel's index among `cand` (transparent pixels: index 2) and writes it; the sum
// of squared errors.
int choose_indices(uint64_t& w, const EtcPixels& px, bool punch, bool opaque,
                   const std::array<std::array<Rgb, 4>, 2>& cand, bool flip) {
  int err = 0;
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int i = y * 4 + x;
      if (transparent(px, i, punch)) {
        put_index(w, x, y, 2);
        continue;
      }
      const auto& c = cand[(flip ? y : x) >= 2 ? 1 : 0];
      int best = 0, best_e = INT_MAX;
      for (int k = 0; k < 4; ++k) {
        if (!opaque && k == 2) continue;
        const int e = dist2(c[static_cast<size_t>(k)], rgb(px[static_cast<size_t>(i)]));
        if (e < best_e) best_e = e, best = k;
      }
      put_index(w, x, y, best);
      err += best_e;
    }
  }
  return err;
}

// The error of the subblock's pixels `which` with base colour `base` and `table`.
int subblock_error(const EtcPixels& px, const std::vector<int>& which, const Rgb& base, int table,
                   bool opaque) {
  const std::array<Rgb, 4> c = subblock_colours(base, table, opaque);
  int e = 0;
  for (int i : which) {
    int be = INT_MAX;
    for (size_t k = 0; k < 4; ++k) {
      if (!opaque && k == 2) continue;
      be = std::min(be, dist2(c[k], rgb(px[static_cast<size_t>(i)])));
    }
    e += be;
  }
  return e;
}

// A subblock's quantised base colour and table.
struct SubblockFit {
  Rgb q{};
  int table = 0;
  int err = INT_MAX;
};

// The best base (among the quantised mean, or with `refine` every per-channel floor / ceiling
// of it, each channel limited to [lo, hi]) and table for the pixels `which`.
SubblockFit fit_subblock(const EtcPixels& px, const std::vector<int>& which, int bits, bool opaque,
                         bool refine, const Rgb& lo, const Rgb& hi) {
  std::array<std::array<int, 2>, 3> choices{};
  const Rgb m = mean(px, which);
  const int top = (1 << bits) - 1;
  for (size_t k = 0; k < 3; ++k) {
    const int down = m[k] * top / 255;
    choices[k] = refine ? std::array<int, 2>{down, std::min(down + 1, top)}
                        : std::array<int, 2>{quant(m[k], bits), quant(m[k], bits)};
    for (int& c : choices[k]) c = std::clamp(c, lo[k], hi[k]);
  }
  SubblockFit best;
  for (int combo = 0; combo < 8; ++combo) {
    const Rgb q = {choices[0][static_cast<size_t>(combo & 1)],
                   choices[1][static_cast<size_t>((combo >> 1) & 1)],
                   choices[2][static_cast<size_t>((combo >> 2) & 1)]};
    if (combo > 0 && !refine) break;
    const Rgb base = {expand(q[0], bits), expand(q[1], bits), expand(q[2], bits)};
    for (int t = 0; t < 8; ++t) {
      const int e = subblock_error(px, which, base, t, opaque);
      if (e < best.err) best = {q, t, e};
    }
  }
  return best;
}

// Individual or differential mode with the subblocks split by `flip` (2x4 side by side when
// false, 4x2 stacked when true).
uint64_t encode_subblocks(const EtcPixels& px, bool individual, bool punch, bool opaque, bool flip,
                          bool refine) {
  std::array<std::vector<int>, 2> sub;
  for (int i = 0; i < 16; ++i) {
    if (transparent(px, i, punch)) continue;
    sub[((flip ? i / 4 : i % 4) >= 2) ? 1 : 0].push_back(i);
  }
  const int bits = individual ? 4 : 5;
  const int top = (1 << bits) - 1;
  const SubblockFit f0 = fit_subblock(px, sub[0], bits, opaque, refine, {0, 0, 0}, {top, top, top});
  Rgb lo{0, 0, 0}, hi{top, top, top};
  if (!individual) {
    // The second base is the first plus a 3-bit signed delta.
    for (size_t k = 0; k < 3; ++k)
      lo[k] = std::max(0, f0.q[k] - 4), hi[k] = std::min(top, f0.q[k] + 3);
  }
  const SubblockFit f1 = fit_subblock(px, sub[1], bits, opaque, refine, lo, hi);
  uint64_t w = 0;
  for (size_t k = 0; k < 3; ++k) {
    const int at = 56 - 8 * static_cast<int>(k);
    if (individual) {
      put(w, at + 4, 4, f0.q[k]);
      put(w, at, 4, f1.q[k]);
    } else {
      put(w, at + 3, 5, f0.q[k]);
      put(w, at, 3, (f1.q[k] - f0.q[k]) & 7);
    }
  }
  put(w, 33, 1, individual ? 0 : (punch ? (opaque ? 1 : 0) : 1));
  put(w, 32, 1, flip ? 1 : 0);
  put(w, 37, 3, f0.table);
  put(w, 34, 3, f1.table);
  std::array<std::array<Rgb, 4>, 2> cand{};
  for (size_t s = 0; s < 2; ++s) {
    const Rgb q = s == 0 ? f0.q : f1.q;
    const Rgb base = {expand(q[0], bits), expand(q[1], bits), expand(q[2], bits)};
    cand[s] = subblock_colours(base, s == 0 ? f0.table : f1.table, opaque);
  }
  choose_indices(w, px, punch, opaque, cand, flip);
  return w;
}

Rgb quant4(const Rgb& c) { return {quant(c[0], 4), quant(c[1], 4), quant(c[2], 4)}; }

// T mode with 4-bit colours q1 (painted alone) and q2 (painted with ±distance); the distance
// of least error.
uint64_t encode_t_colours(const EtcPixels& px, bool punch, bool opaque, const Rgb& q1,
                          const Rgb& q2) {
  uint64_t w = 0;
  put(w, 59, 2, q1[0] >> 2);
  put(w, 56, 2, q1[0] & 3);
  put(w, 52, 4, q1[1]);
  put(w, 48, 4, q1[2]);
  put(w, 44, 4, q2[0]);
  put(w, 40, 4, q2[1]);
  put(w, 36, 4, q2[2]);
  put(w, 33, 1, opaque ? 1 : 0);
  const Rgb c1 = times17(q1), c2 = times17(q2);
  int best = INT_MAX, best_d = 0;
  for (int d = 0; d < 8; ++d) {
    const int dv = kEtcDistances[static_cast<size_t>(d)];
    const std::array<Rgb, 4> paint = {c1, add(c2, dv), c2, add(c2, -dv)};
    uint64_t trial = w;
    const int e = choose_indices(trial, px, punch, opaque, {paint, paint}, false);
    if (e < best) best = e, best_d = d;
  }
  put(w, 34, 2, best_d >> 1);
  put(w, 32, 1, best_d & 1);
  const int dv = kEtcDistances[static_cast<size_t>(best_d)];
  const std::array<Rgb, 4> paint = {c1, add(c2, dv), c2, add(c2, -dv)};
  choose_indices(w, px, punch, opaque, {paint, paint}, false);
  return force_mode(w, {63, 62, 61, 58}, EtcMode::T, punch);
}

std::vector<int> opaque_pixels(const EtcPixels& px, bool punch) {
  std::vector<int> all;
  for (int i = 0; i < 16; ++i) {
    if (!transparent(px, i, punch)) all.push_back(i);
  }
  return all;
}

// T mode: colour 1 the pixel farthest from the mean, colour 2 the mean of the rest.
uint64_t encode_t(const EtcPixels& px, bool punch, bool opaque) {
  const std::vector<int> all = opaque_pixels(px, punch);
  const Rgb m = mean(px, all);
  int far = all.empty() ? 0 : all[0];
  for (int i : all) {
    if (dist2(rgb(px[static_cast<size_t>(i)]), m) > dist2(rgb(px[static_cast<size_t>(far)]), m))
      far = i;
  }
  std::vector<int> rest;
  for (int i : all) {
    if (i != far) rest.push_back(i);
  }
  return encode_t_colours(px, punch, opaque, quant4(rgb(px[static_cast<size_t>(far)])),
                          quant4(mean(px, rest)));
}

// H mode with 4-bit colours q[0] and q[1] (in the order, and distance, of least error: the
// order gives the distance index its low bit).
uint64_t encode_h_colours(const EtcPixels& px, bool punch, bool opaque,
                          const std::array<Rgb, 2>& q) {
  const auto value = [](const Rgb& c) { return (c[0] << 16) + (c[1] << 8) + c[2]; };
  int best = INT_MAX, best_d = -1;
  bool best_swap = false;
  for (int d = 0; d < 8; ++d) {
    for (bool swap : {false, true}) {
      const Rgb c1 = swap ? q[1] : q[0], c2 = swap ? q[0] : q[1];
      if ((value(c1) >= value(c2) ? 1 : 0) != (d & 1)) continue;
      const int dv = kEtcDistances[static_cast<size_t>(d)];
      const Rgb e1 = times17(c1), e2 = times17(c2);
      const std::array<Rgb, 4> paint = {add(e1, dv), add(e1, -dv), add(e2, dv), add(e2, -dv)};
      uint64_t trial = 0;
      const int e = choose_indices(trial, px, punch, opaque, {paint, paint}, false);
      if (e < best) best = e, best_d = d, best_swap = swap;
    }
  }
  if (best_d < 0) return 0;  // equal colours with no distance of their order: not possible
  const Rgb c1 = best_swap ? q[1] : q[0], c2 = best_swap ? q[0] : q[1];
  uint64_t w = 0;
  put(w, 59, 4, c1[0]);
  put(w, 56, 3, c1[1] >> 1);
  put(w, 52, 1, c1[1] & 1);
  put(w, 51, 1, c1[2] >> 3);
  put(w, 47, 3, c1[2] & 7);
  put(w, 43, 4, c2[0]);
  put(w, 39, 4, c2[1]);
  put(w, 35, 4, c2[2]);
  put(w, 34, 1, best_d >> 2);
  put(w, 33, 1, opaque ? 1 : 0);
  put(w, 32, 1, (best_d >> 1) & 1);
  const int dv = kEtcDistances[static_cast<size_t>(best_d)];
  const Rgb e1 = times17(c1), e2 = times17(c2);
  const std::array<Rgb, 4> paint = {add(e1, dv), add(e1, -dv), add(e2, dv), add(e2, -dv)};
  choose_indices(w, px, punch, opaque, {paint, paint}, false);
  return force_mode(w, {63, 55, 54, 53, 50}, EtcMode::H, punch);
}

// H mode: the pixels above and below the mean luma, each group's mean a base colour.
uint64_t encode_h(const EtcPixels& px, bool punch, bool opaque) {
  std::vector<int> hi, lo;
  const std::vector<int> all = opaque_pixels(px, punch);
  const Rgb m = mean(px, all);
  for (int i : all) {
    const auto& p = px[static_cast<size_t>(i)];
    (p[0] + 2 * p[1] + p[2] >= m[0] + 2 * m[1] + m[2] ? hi : lo).push_back(i);
  }
  return encode_h_colours(px, punch, opaque, {quant4(mean(px, hi)), quant4(mean(px, lo))});
}

// Two clusters of the opaque pixels (a few rounds of 2-means from the two pixels farthest
// apart): their mean colours.
std::array<Rgb, 2> two_clusters(const EtcPixels& px, bool punch) {
  const std::vector<int> all = opaque_pixels(px, punch);
  if (all.empty()) return {};
  int a = all[0], b = all[0];
  for (int i : all) {
    for (int j : all) {
      if (dist2(rgb(px[static_cast<size_t>(i)]), rgb(px[static_cast<size_t>(j)])) >
          dist2(rgb(px[static_cast<size_t>(a)]), rgb(px[static_cast<size_t>(b)])))
        a = i, b = j;
    }
  }
  std::array<Rgb, 2> c = {rgb(px[static_cast<size_t>(a)]), rgb(px[static_cast<size_t>(b)])};
  for (int round = 0; round < 4; ++round) {
    std::array<std::vector<int>, 2> g;
    for (int i : all) {
      const Rgb p = rgb(px[static_cast<size_t>(i)]);
      g[dist2(p, c[0]) <= dist2(p, c[1]) ? 0 : 1].push_back(i);
    }
    for (size_t k = 0; k < 2; ++k) {
      if (!g[k].empty()) c[k] = mean(px, g[k]);
    }
  }
  return c;
}

void put_planar(uint64_t& w, const Rgb& o, const Rgb& h, const Rgb& v) {
  put(w, 57, 6, o[0]);
  put(w, 56, 1, o[1] >> 6);
  put(w, 49, 6, o[1] & 63);
  put(w, 48, 1, o[2] >> 5);
  put(w, 43, 2, (o[2] >> 3) & 3);
  put(w, 39, 3, o[2] & 7);
  put(w, 34, 5, h[0] >> 1);
  put(w, 33, 1, 1);
  put(w, 32, 1, h[0] & 1);
  put(w, 25, 7, h[1]);
  put(w, 19, 6, h[2]);
  put(w, 13, 6, v[0]);
  put(w, 6, 7, v[1]);
  put(w, 0, 6, v[2]);
}

// The planar value at (x, y) from the 8-bit O, H, V of one channel.
int planar_value(int o, int h, int v, int x, int y) {
  return clamp8((x * (h - o) + y * (v - o) + 4 * o + 2) >> 2);
}

// Planar mode, corners: O the top-left pixel, H and V extrapolated from the top-right and
// bottom-left ones to x = 4 and y = 4.
uint64_t encode_planar_corners(const EtcPixels& px, bool punch) {
  Rgb o{}, h{}, v{};
  for (size_t k = 0; k < 3; ++k) {
    const int p0 = px[0][k], px3 = px[3][k], py3 = px[12][k];
    const int bits = k == 1 ? 7 : 6;
    o[k] = quant(p0, bits);
    h[k] = quant(p0 + (px3 - p0) * 4 / 3, bits);
    v[k] = quant(p0 + (py3 - p0) * 4 / 3, bits);
  }
  uint64_t w = 0;
  put_planar(w, o, h, v);
  return force_mode(w, {63, 55, 47, 46, 45, 42}, EtcMode::Planar, punch);
}

// Planar mode, fitted: each channel's least-squares plane c(x, y) = a + b x + c y (x, y in
// 0..3, so b = sum((x - 1.5) v) / 20), O = a, H = a + 4b, V = a + 4c quantised; with `refine`
// each quantised value and its neighbours, channel by channel (their errors are separate).
uint64_t encode_planar_fit(const EtcPixels& px, bool punch, bool refine) {
  Rgb o{}, h{}, v{};
  for (size_t k = 0; k < 3; ++k) {
    int sum = 0, sx = 0, sy = 0;  // sums of v, (2x - 3) v, (2y - 3) v
    for (int i = 0; i < 16; ++i) {
      const int val = px[static_cast<size_t>(i)][k];
      sum += val, sx += (2 * (i % 4) - 3) * val, sy += (2 * (i / 4) - 3) * val;
    }
    // In units of 1/40: b = sx / 40, c = sy / 40, a = sum / 16 - 1.5 (b + c).
    const int a40 = div_round(sum * 40, 16) - 3 * (sx + sy) / 2;
    const int bits = k == 1 ? 7 : 6;
    const int top = (1 << bits) - 1;
    const auto q = [&](int v40) { return std::clamp(div_round(v40 * top, 40 * 255), 0, top); };
    std::array<int, 3> base = {q(a40), q(a40 + 4 * sx), q(a40 + 4 * sy)};
    std::array<int, 3> best = base;
    if (refine) {
      int best_e = INT_MAX;
      for (int combo = 0; combo < 27; ++combo) {
        const int qo = std::clamp(base[0] + combo % 3 - 1, 0, top);
        const int qh = std::clamp(base[1] + combo / 3 % 3 - 1, 0, top);
        const int qv = std::clamp(base[2] + combo / 9 - 1, 0, top);
        const int eo = expand(qo, bits), eh = expand(qh, bits), ev = expand(qv, bits);
        int e = 0;
        for (int i = 0; i < 16; ++i) {
          const int d = planar_value(eo, eh, ev, i % 4, i / 4) - px[static_cast<size_t>(i)][k];
          e += d * d;
        }
        if (e < best_e) best_e = e, best = {qo, qh, qv};
      }
    }
    o[k] = best[0], h[k] = best[1], v[k] = best[2];
  }
  uint64_t w = 0;
  put_planar(w, o, h, v);
  return force_mode(w, {63, 55, 47, 46, 45, 42}, EtcMode::Planar, punch);
}

// Squared error of a block against the pixels: RGB, and for punch-through alpha too (the
// transparent targets (0, 0, 0, 0), as they decode).
int rgb_block_error(const EtcBlock& b, const EtcPixels& px, bool punch) {
  const EtcPixels got = etc_reconstruct_rgb(b, punch);
  int e = 0;
  for (size_t i = 0; i < 16; ++i) {
    const bool clear = transparent(px, static_cast<int>(i), punch);
    for (size_t k = 0; k < (punch ? 4U : 3U); ++k) {
      const int want = clear ? 0 : (k == 3 ? 255 : px[i][k]);
      const int d = got[i][k] - want;
      e += d * d;
    }
  }
  return e;
}

// The planar mode's O, H and V values of the word, 8-bit.
void planar_fields(uint64_t w, Rgb& o, Rgb& h, Rgb& v) {
  o = {expand(field(w, 57, 6), 6), expand((field(w, 56, 1) << 6) | field(w, 49, 6), 7),
       expand((field(w, 48, 1) << 5) | (field(w, 43, 2) << 3) | field(w, 39, 3), 6)};
  h = {expand((field(w, 34, 5) << 1) | field(w, 32, 1), 6), expand(field(w, 25, 7), 7),
       expand(field(w, 19, 6), 6)};
  v = {expand(field(w, 13, 6), 6), expand(field(w, 6, 7), 7), expand(field(w, 0, 6), 6)};
}

// The four paint colours of a T or H block.
std::array<Rgb, 4> paint_colours(uint64_t w, EtcMode mode) {
  if (mode == EtcMode::T) {
    const Rgb c1 =
        times17({(field(w, 59, 2) << 2) | field(w, 56, 2), field(w, 52, 4), field(w, 48, 4)});
    const Rgb c2 = times17({field(w, 44, 4), field(w, 40, 4), field(w, 36, 4)});
    const int d = kEtcDistances[static_cast<size_t>((field(w, 34, 2) << 1) | field(w, 32, 1))];
    return {c1, add(c2, d), c2, add(c2, -d)};
  }
  const Rgb q1 = {field(w, 59, 4), (field(w, 56, 3) << 1) | field(w, 52, 1),
                  (field(w, 51, 1) << 3) | field(w, 47, 3)};
  const Rgb q2 = {field(w, 43, 4), field(w, 39, 4), field(w, 35, 4)};
  const int order = ((q1[0] << 8) | (q1[1] << 4) | q1[2]) >= ((q2[0] << 8) | (q2[1] << 4) | q2[2]);
  const int d =
      kEtcDistances[static_cast<size_t>((field(w, 34, 1) << 2) | (field(w, 32, 1) << 1) | order)];
  const Rgb c1 = times17(q1), c2 = times17(q2);
  return {add(c1, d), add(c1, -d), add(c2, d), add(c2, -d)};
}

}  // namespace

EtcMode etc_block_mode(const EtcBlock& b, bool punch_through) {
  return mode_of(word(b), punch_through);
}

EtcPixels etc_reconstruct_rgb(const EtcBlock& b, bool punch_through) {
  const uint64_t w = word(b);
  const EtcMode mode = mode_of(w, punch_through);
  const bool opaque = !punch_through || field(w, 33, 1) == 1;
  EtcPixels out{};
  const auto set = [&](int x, int y, const Rgb& c, bool clear) {
    auto& p = out[static_cast<size_t>(y) * 4 + static_cast<size_t>(x)];
    for (size_t k = 0; k < 3; ++k) p[k] = static_cast<uint8_t>(clear ? 0 : c[k]);
    p[3] = clear ? 0 : 255;
  };
  if (mode == EtcMode::Planar) {
    Rgb o{}, h{}, v{};
    planar_fields(w, o, h, v);
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 4; ++x) {
        set(x, y,
            {planar_value(o[0], h[0], v[0], x, y), planar_value(o[1], h[1], v[1], x, y),
             planar_value(o[2], h[2], v[2], x, y)},
            false);
      }
    }
    return out;
  }
  std::array<std::array<Rgb, 4>, 2> cand{};
  bool flip = false;
  if (mode == EtcMode::T || mode == EtcMode::H) {
    cand[0] = cand[1] = paint_colours(w, mode);
  } else {
    std::array<Rgb, 2> base{};
    for (size_t k = 0; k < 3; ++k) {
      const int at = 56 - 8 * static_cast<int>(k);
      if (mode == EtcMode::Individual) {
        base[0][k] = expand(field(w, at + 4, 4), 4);
        base[1][k] = expand(field(w, at, 4), 4);
      } else {
        const int q = field(w, at + 3, 5);
        base[0][k] = expand(q, 5);
        base[1][k] = expand(q + sign_extend3(field(w, at, 3)), 5);
      }
    }
    cand[0] = subblock_colours(base[0], field(w, 37, 3), opaque);
    cand[1] = subblock_colours(base[1], field(w, 34, 3), opaque);
    flip = field(w, 32, 1) == 1;
  }
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int idx = index_at(w, x, y);
      set(x, y, cand[(flip ? y : x) >= 2 ? 1 : 0][static_cast<size_t>(idx)], !opaque && idx == 2);
    }
  }
  return out;
}

EtcBlock etc_encode_rgb_mode(const EtcPixels& px, EtcMode mode, bool punch_through) {
  bool opaque = true;
  for (int i = 0; i < 16; ++i) opaque = opaque && !transparent(px, i, punch_through);
  if (punch_through && mode == EtcMode::Individual) mode = EtcMode::Differential;
  const bool flip = (px[0][0] + px[15][1]) % 2 == 1;  // some blocks each way
  switch (mode) {
    case EtcMode::Individual:
      return bytes(encode_subblocks(px, true, false, true, flip, false));
    case EtcMode::Differential:
      return bytes(encode_subblocks(px, false, punch_through, opaque, flip, false));
    case EtcMode::T:
      return bytes(encode_t(px, punch_through, opaque));
    case EtcMode::H:
      return bytes(encode_h(px, punch_through, opaque));
    case EtcMode::Planar:
      return bytes(encode_planar_corners(px, punch_through));
  }
  return {};
}

EtcBlock etc_encode_rgb(const EtcPixels& px, bool punch_through, EtcEffort effort) {
  bool opaque = true;
  for (int i = 0; i < 16; ++i) opaque = opaque && !transparent(px, i, punch_through);
  const bool refine = effort == EtcEffort::Normal;
  std::vector<uint64_t> tries;
  for (bool flip : {false, true}) {
    if (!punch_through) tries.push_back(encode_subblocks(px, true, false, true, flip, refine));
    tries.push_back(encode_subblocks(px, false, punch_through, opaque, flip, refine));
  }
  tries.push_back(encode_t(px, punch_through, opaque));
  tries.push_back(encode_h(px, punch_through, opaque));
  if (refine) {
    const std::array<Rgb, 2> c = two_clusters(px, punch_through);
    const Rgb q0 = quant4(c[0]), q1 = quant4(c[1]);
    tries.push_back(encode_t_colours(px, punch_through, opaque, q0, q1));
    tries.push_back(encode_t_colours(px, punch_through, opaque, q1, q0));
    if (q0 != q1) tries.push_back(encode_h_colours(px, punch_through, opaque, {q0, q1}));
  }
  if (opaque) tries.push_back(encode_planar_fit(px, punch_through, refine));
  EtcBlock best{};
  int best_e = INT_MAX;
  for (uint64_t w : tries) {
    if (w == 0) continue;
    const EtcBlock b = bytes(w);
    const int e = rgb_block_error(b, px, punch_through);
    if (e < best_e) best_e = e, best = b;
  }
  return best;
}

// ---------------------------------------------------------------------------------------------
// EAC

namespace {

struct EacRange {
  int lo, hi, scale;  // decoded range; the multiplier's scale on it
};
EacRange eac_range(EacKind kind) {
  switch (kind) {
    case EacKind::Alpha8:
      return {0, 255, 1};
    case EacKind::R11:
      return {0, 2047, 8};
    case EacKind::SignedR11:
      break;
  }
  return {-1023, 1023, 8};
}
// The decoded value of `base` (the stored codeword: 0..255, or -127..127 signed) with
// multiplier `m` and modifier `mod`.
int eac_value(EacKind kind, int base, int m, int mod) {
  const EacRange r = eac_range(kind);
  int v = 0;
  if (kind == EacKind::Alpha8) {
    v = base + mod * m;
  } else {
    const int b = kind == EacKind::R11 ? base * 8 + 4 : base * 8;
    v = m == 0 ? b + mod : b + mod * m * 8;
  }
  return std::clamp(v, r.lo, r.hi);
}
// The block of base, multiplier and table with each value's nearest index; its squared error
// in `err`.
uint64_t eac_write(const std::array<int, 16>& t, EacKind kind, int base, int m, int table,
                   int64_t* err) {
  uint64_t w = 0;
  put(w, 56, 8, base & 0xFF);
  put(w, 52, 4, m);
  put(w, 48, 4, table);
  const auto& row = kEacTables[static_cast<size_t>(table)];
  std::array<int, 8> val{};
  for (size_t k = 0; k < 8; ++k) val[k] = eac_value(kind, base, m, row[k]);
  int64_t e = 0;
  for (int i = 0; i < 16; ++i) {
    int best = 0, be = INT_MAX;
    for (int k = 0; k < 8; ++k) {
      const int d = std::abs(val[static_cast<size_t>(k)] - t[static_cast<size_t>(i)]);
      if (d < be) be = d, best = k;
    }
    // Values are row-major; the block's indices go column by column (i = x * 4 + y).
    const int x = i % 4, y = i / 4;
    put(w, 45 - 3 * (x * 4 + y), 3, best);
    e += static_cast<int64_t>(be) * be;
  }
  if (err) *err = e;
  return w;
}
// The codeword whose decoded base is nearest `v` (before the modifier).
int eac_base_for(EacKind kind, int v) {
  if (kind == EacKind::Alpha8) return std::clamp(v, 0, 255);
  if (kind == EacKind::R11) return std::clamp(div_round(v - 4, 8), 0, 255);
  return std::clamp(div_round(v, 8), -127, 127);
}

}  // namespace

std::array<int, 16> eac_targets(const std::array<int, 16>& values, EacKind kind) {
  std::array<int, 16> t{};
  for (size_t i = 0; i < 16; ++i) {
    t[i] = kind == EacKind::Alpha8 ? values[i]
           : kind == EacKind::R11  ? (values[i] * 2047 + 127) / 255
                                   : values[i] * 1023 / 127;
  }
  return t;
}

std::array<int, 16> eac_reconstruct(const EtcBlock& b, EacKind kind) {
  const uint64_t w = word(b);
  int base = field(w, 56, 8);
  if (kind == EacKind::SignedR11) base = base >= 128 ? std::max(base - 256, -127) : base;
  const int m = field(w, 52, 4);
  const auto& row = kEacTables[static_cast<size_t>(field(w, 48, 4))];
  std::array<int, 16> out{};
  for (int i = 0; i < 16; ++i) {
    const int x = i % 4, y = i / 4;
    const int idx = field(w, 45 - 3 * (x * 4 + y), 3);
    out[static_cast<size_t>(i)] = eac_value(kind, base, m, row[static_cast<size_t>(idx)]);
  }
  return out;
}

EtcBlock eac_encode(const std::array<int, 16>& values, EacKind kind, EtcEffort effort) {
  const std::array<int, 16> t = eac_targets(values, kind);
  const auto [mn, mx] = std::minmax_element(t.begin(), t.end());
  const int mid = (*mn + *mx) / 2, scale = eac_range(kind).scale;
  const bool refine = effort == EtcEffort::Normal;
  int64_t best_e = INT64_MAX;
  uint64_t best = 0;
  const auto consider = [&](int base, int m, int table) {
    int64_t e = 0;
    const uint64_t w = eac_write(t, kind, base, m, table, &e);
    if (e < best_e) best_e = e, best = w;
  };
  // Multiplier 0: the base alone (Alpha8) or unscaled modifiers (R11), for flat blocks.
  int sum = 0;
  for (int v : t) sum += v;
  for (int table = 0; table < (kind == EacKind::Alpha8 ? 1 : 16); ++table)
    consider(eac_base_for(kind, div_round(sum, 16)), 0, table);
  for (int table = 0; table < 16; ++table) {
    const auto& row = kEacTables[static_cast<size_t>(table)];
    const int span = row[7] - row[3];
    const int m0 = std::clamp(div_round(*mx - *mn, span * scale), 1, 15);
    for (int m = refine ? m0 - 1 : m0; m <= (refine ? m0 + 1 : m0); ++m) {
      if (m < 1 || m > 15) continue;
      // The base that centres the table's modifiers on the values' range.
      const int b0 = eac_base_for(kind, mid - div_round((row[3] + row[7]) * m * scale, 2));
      for (int d = refine ? -1 : 0; d <= (refine ? 1 : 0); ++d) {
        const int b =
            kind == EacKind::SignedR11 ? std::clamp(b0 + d, -127, 127) : std::clamp(b0 + d, 0, 255);
        consider(b, m, table);
      }
    }
  }
  return bytes(best);
}

EtcBlock eac_encode_mode(const std::array<int, 16>& values, EacKind kind, bool zero_multiplier) {
  const std::array<int, 16> t = eac_targets(values, kind);
  const auto [mn, mx] = std::minmax_element(t.begin(), t.end());
  const int mid = (*mn + *mx) / 2;
  const int scale = eac_range(kind).scale;
  int base = kind == EacKind::R11 ? (mid - 4) / 8 : mid / scale;
  base = kind == EacKind::SignedR11 ? std::clamp(base, -127, 127) : std::clamp(base, 0, 255);
  int64_t best_e = INT64_MAX;
  int best_t = 0, best_m = 1;
  for (int tab = 0; tab < 16; ++tab) {
    const auto& row = kEacTables[static_cast<size_t>(tab)];
    const int span = row[7] - row[3];
    const int m = zero_multiplier ? 0 : std::clamp((*mx - *mn) / (span * scale) + 1, 1, 15);
    int64_t e = 0;
    eac_write(t, kind, base, m, tab, &e);
    if (e < best_e) best_e = e, best_t = tab, best_m = m;
  }
  return bytes(eac_write(t, kind, base, best_m, best_t, nullptr));
}

}  // namespace texsim
