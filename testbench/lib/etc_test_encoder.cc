#include "testbench/lib/etc_test_encoder.h"

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <vector>

namespace texsim {

namespace {

using Rgb = std::array<int, 3>;

constexpr std::array<std::array<int, 2>, 8> kEtcTables = {
    {{2, 8}, {5, 17}, {9, 29}, {13, 42}, {18, 60}, {24, 80}, {33, 106}, {47, 183}}};
constexpr std::array<int, 8> kEtcDistances = {3, 6, 11, 16, 23, 32, 41, 64};
constexpr std::array<std::array<int, 8>, 16> kEacTables = {{
    {-3, -6, -9, -15, 2, 5, 8, 14},
    {-3, -7, -10, -13, 2, 6, 9, 12},
    {-2, -5, -8, -13, 1, 4, 7, 12},
    {-2, -4, -6, -13, 1, 3, 5, 12},
    {-3, -6, -8, -12, 2, 5, 7, 11},
    {-3, -7, -9, -11, 2, 6, 8, 10},
    {-4, -7, -8, -11, 3, 6, 7, 10},
    {-3, -5, -8, -11, 2, 4, 7, 10},
    {-2, -6, -8, -10, 1, 5, 7, 9},
    {-2, -5, -8, -10, 1, 4, 7, 9},
    {-2, -4, -8, -10, 1, 3, 7, 9},
    {-2, -5, -7, -10, 1, 4, 6, 9},
    {-3, -4, -7, -10, 2, 3, 6, 9},
    {-1, -2, -3, -10, 0, 1, 2, 9},
    {-4, -6, -8, -9, 3, 5, 7, 8},
    {-3, -5, -7, -9, 2, 4, 6, 8},
}};

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
Rgb rgb(const std::array<uint8_t, 4>& p) { return {p[0], p[1], p[2]}; }
int dist2(const Rgb& a, const Rgb& b) {
  int s = 0;
  for (size_t k = 0; k < 3; ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
  return s;
}
Rgb add(const Rgb& c, int d) { return {clamp8(c[0] + d), clamp8(c[1] + d), clamp8(c[2] + d)}; }
Rgb mean(const EtcTestPixels& px, const std::vector<int>& which) {
  Rgb s{0, 0, 0};
  for (int i : which) {
    for (size_t k = 0; k < 3; ++k) s[k] += px[static_cast<size_t>(i)][k];
  }
  const int n = std::max<int>(1, static_cast<int>(which.size()));
  return {(s[0] + n / 2) / n, (s[1] + n / 2) / n, (s[2] + n / 2) / n};
}
bool transparent(const EtcTestPixels& px, int i, bool punch) {
  return punch && px[static_cast<size_t>(i)][3] < 128;
}
// The pixel's 2-bit index at its column-major place: msb at bit 16 + i, lsb at bit i.
void put_index(uint64_t& w, int x, int y, int idx) {
  const int i = x * 4 + y;
  put(w, 16 + i, 1, idx >> 1);
  put(w, i, 1, idx & 1);
}
std::array<uint8_t, 8> bytes(uint64_t w) {
  std::array<uint8_t, 8> b{};
  for (size_t i = 0; i < 8; ++i) b[i] = static_cast<uint8_t>(w >> (56 - 8 * i));
  return b;
}

// Chooses each pixel's index among `cand` (transparent pixels: index 2) and writes it; the sum
// of squared errors.
int choose_indices(uint64_t& w, const EtcTestPixels& px, bool punch, bool opaque,
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

// The mode an RGB ETC2 decoder reads from the word (the spec's selection, written again here).
EtcTestMode mode_of(uint64_t w, bool punch) {
  if (!punch && field(w, 33, 1) == 0) return EtcTestMode::Individual;
  for (int c = 0; c < 3; ++c) {
    const int lo = 56 - 8 * c;
    int d = field(w, lo, 3);
    if (d >= 4) d -= 8;
    const int s = field(w, lo + 3, 5) + d;
    if (s < 0 || s > 31)
      return c == 0 ? EtcTestMode::T : c == 1 ? EtcTestMode::H : EtcTestMode::Planar;
  }
  return EtcTestMode::Differential;
}

// Sets the mode's free bits (`free`) so that the word selects `mode`.
uint64_t force_mode(uint64_t w, const std::vector<int>& free, EtcTestMode mode, bool punch) {
  for (uint32_t combo = 0; combo < (1U << free.size()); ++combo) {
    for (size_t k = 0; k < free.size(); ++k) put(w, free[k], 1, static_cast<int>((combo >> k) & 1));
    if (mode_of(w, punch) == mode) return w;
  }
  throw std::logic_error("etc_test_encode_rgb: no free bits select the mode");
}

uint64_t encode_subblocks(const EtcTestPixels& px, bool individual, bool punch, bool opaque) {
  const bool flip = (px[0][0] + px[15][1]) % 2 == 1;  // some blocks each way
  std::array<std::vector<int>, 2> sub;
  for (int i = 0; i < 16; ++i) {
    if (transparent(px, i, punch)) continue;
    sub[((flip ? i / 4 : i % 4) >= 2) ? 1 : 0].push_back(i);
  }
  const int bits = individual ? 4 : 5;
  std::array<Rgb, 2> q{};
  for (size_t s = 0; s < 2; ++s) {
    const Rgb m = mean(px, sub[s]);
    for (size_t k = 0; k < 3; ++k) q[s][k] = quant(m[k], bits);
  }
  uint64_t w = 0;
  for (size_t k = 0; k < 3; ++k) {
    const int lo = 56 - 8 * static_cast<int>(k);
    if (individual) {
      put(w, lo + 4, 4, q[0][k]);
      put(w, lo, 4, q[1][k]);
    } else {
      const int d = std::clamp(q[1][k] - q[0][k], -4, 3);
      q[1][k] = q[0][k] + d;
      put(w, lo + 3, 5, q[0][k]);
      put(w, lo, 3, d & 7);
    }
  }
  put(w, 33, 1, individual ? 0 : (punch ? (opaque ? 1 : 0) : 1));
  put(w, 32, 1, flip ? 1 : 0);
  std::array<Rgb, 2> base{};
  for (size_t s = 0; s < 2; ++s) {
    for (size_t k = 0; k < 3; ++k) base[s][k] = expand(q[s][k], bits);
  }
  // Each subblock's table: the one of least error on its own pixels.
  std::array<int, 2> best_t{0, 0}, best_e{INT_MAX, INT_MAX};
  for (int t = 0; t < 8; ++t) {
    std::array<std::array<Rgb, 4>, 2> cand{};
    for (size_t s = 0; s < 2; ++s) {
      const int a = opaque ? kEtcTables[static_cast<size_t>(t)][0] : 0;
      const int b = kEtcTables[static_cast<size_t>(t)][1];
      cand[s] = {add(base[s], a), add(base[s], b), add(base[s], -a), add(base[s], -b)};
    }
    for (size_t s = 0; s < 2; ++s) {
      int e = 0;  // the error of subblock s alone
      for (int i : sub[s]) {
        int be = INT_MAX;
        for (int k = 0; k < 4; ++k) {
          if (!opaque && k == 2) continue;
          be =
              std::min(be, dist2(cand[s][static_cast<size_t>(k)], rgb(px[static_cast<size_t>(i)])));
        }
        e += be;
      }
      if (e < best_e[s]) best_e[s] = e, best_t[s] = t;
    }
  }
  put(w, 37, 3, best_t[0]);
  put(w, 34, 3, best_t[1]);
  std::array<std::array<Rgb, 4>, 2> cand{};
  for (size_t s = 0; s < 2; ++s) {
    const int a = opaque ? kEtcTables[static_cast<size_t>(best_t[s])][0] : 0;
    const int b = kEtcTables[static_cast<size_t>(best_t[s])][1];
    cand[s] = {add(base[s], a), add(base[s], b), add(base[s], -a), add(base[s], -b)};
  }
  choose_indices(w, px, punch, opaque, cand, flip);
  return w;
}

// T mode: colour 1 the pixel farthest from the mean, colour 2 the mean of the rest.
uint64_t encode_t(const EtcTestPixels& px, bool punch, bool opaque) {
  std::vector<int> all;
  for (int i = 0; i < 16; ++i) {
    if (!transparent(px, i, punch)) all.push_back(i);
  }
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
  Rgb q1{}, q2{};
  const Rgb m2 = mean(px, rest);
  for (size_t k = 0; k < 3; ++k) {
    q1[k] = quant(px[static_cast<size_t>(far)][k], 4);
    q2[k] = quant(m2[k], 4);
  }
  uint64_t w = 0;
  put(w, 59, 2, q1[0] >> 2);
  put(w, 56, 2, q1[0] & 3);
  put(w, 52, 4, q1[1]);
  put(w, 48, 4, q1[2]);
  put(w, 44, 4, q2[0]);
  put(w, 40, 4, q2[1]);
  put(w, 36, 4, q2[2]);
  put(w, 33, 1, opaque ? 1 : 0);
  const Rgb c1 = {q1[0] * 17, q1[1] * 17, q1[2] * 17}, c2 = {q2[0] * 17, q2[1] * 17, q2[2] * 17};
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
  return force_mode(w, {63, 62, 61, 58}, EtcTestMode::T, punch);
}

// H mode: the pixels above and below the mean luma, each group's mean a base colour.
uint64_t encode_h(const EtcTestPixels& px, bool punch, bool opaque) {
  std::vector<int> all, hi, lo;
  for (int i = 0; i < 16; ++i) {
    if (!transparent(px, i, punch)) all.push_back(i);
  }
  const Rgb m = mean(px, all);
  for (int i : all) {
    const auto& p = px[static_cast<size_t>(i)];
    (p[0] + 2 * p[1] + p[2] >= m[0] + 2 * m[1] + m[2] ? hi : lo).push_back(i);
  }
  const Rgb mh = mean(px, hi), ml = mean(px, lo);
  std::array<Rgb, 2> q{};
  for (size_t k = 0; k < 3; ++k) q[0][k] = quant(mh[k], 4), q[1][k] = quant(ml[k], 4);
  const auto value = [](const Rgb& c) { return (c[0] << 16) + (c[1] << 8) + c[2]; };
  int best = INT_MAX, best_d = -1;
  bool best_swap = false;
  for (int d = 0; d < 8; ++d) {
    for (bool swap : {false, true}) {
      const Rgb c1 = swap ? q[1] : q[0], c2 = swap ? q[0] : q[1];
      if ((value(c1) >= value(c2) ? 1 : 0) != (d & 1)) continue;
      const int dv = kEtcDistances[static_cast<size_t>(d)];
      const Rgb e1 = {c1[0] * 17, c1[1] * 17, c1[2] * 17},
                e2 = {c2[0] * 17, c2[1] * 17, c2[2] * 17};
      const std::array<Rgb, 4> paint = {add(e1, dv), add(e1, -dv), add(e2, dv), add(e2, -dv)};
      uint64_t trial = 0;
      const int e = choose_indices(trial, px, punch, opaque, {paint, paint}, false);
      if (e < best) best = e, best_d = d, best_swap = swap;
    }
  }
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
  const Rgb e1 = {c1[0] * 17, c1[1] * 17, c1[2] * 17}, e2 = {c2[0] * 17, c2[1] * 17, c2[2] * 17};
  const std::array<Rgb, 4> paint = {add(e1, dv), add(e1, -dv), add(e2, dv), add(e2, -dv)};
  choose_indices(w, px, punch, opaque, {paint, paint}, false);
  return force_mode(w, {63, 55, 54, 53, 50}, EtcTestMode::H, punch);
}

// Planar mode: O the top-left pixel, H and V extrapolated from the top-right and bottom-left
// ones to x = 4 and y = 4.
uint64_t encode_planar(const EtcTestPixels& px, bool punch) {
  Rgb o{}, h{}, v{};
  for (size_t k = 0; k < 3; ++k) {
    const int p0 = px[0][k], px3 = px[3][k], py3 = px[12][k];
    const int bits = k == 1 ? 7 : 6;
    o[k] = quant(p0, bits);
    h[k] = quant(p0 + (px3 - p0) * 4 / 3, bits);
    v[k] = quant(p0 + (py3 - p0) * 4 / 3, bits);
  }
  uint64_t w = 0;
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
  return force_mode(w, {63, 55, 47, 46, 45, 42}, EtcTestMode::Planar, punch);
}

}  // namespace

std::array<uint8_t, 8> etc_test_encode_rgb(const EtcTestPixels& px, EtcTestMode mode,
                                           bool punch_through) {
  bool opaque = true;
  for (int i = 0; i < 16; ++i) opaque = opaque && !transparent(px, i, punch_through);
  if (punch_through && mode == EtcTestMode::Individual) mode = EtcTestMode::Differential;
  switch (mode) {
    case EtcTestMode::Individual:
      return bytes(encode_subblocks(px, true, false, true));
    case EtcTestMode::Differential:
      return bytes(encode_subblocks(px, false, punch_through, opaque));
    case EtcTestMode::T:
      return bytes(encode_t(px, punch_through, opaque));
    case EtcTestMode::H:
      return bytes(encode_h(px, punch_through, opaque));
    case EtcTestMode::Planar:
      return bytes(encode_planar(px, punch_through));
  }
  return {};
}

std::array<uint8_t, 8> etc_test_encode_eac(const std::array<int, 16>& values, EacTestKind kind,
                                           bool zero_multiplier) {
  // Targets on the decoded scale: 0..255 (Alpha8), 0..2047 (R11), -1023..1023 (SignedR11).
  std::array<int, 16> t{};
  for (size_t i = 0; i < 16; ++i) {
    t[i] = kind == EacTestKind::Alpha8 ? values[i]
           : kind == EacTestKind::R11  ? (values[i] * 2047 + 127) / 255
                                       : values[i] * 1023 / 127;
  }
  const auto [mn, mx] = std::minmax_element(t.begin(), t.end());
  const int mid = (*mn + *mx) / 2;
  const int scale = kind == EacTestKind::Alpha8 ? 1 : 8;
  int base = kind == EacTestKind::R11 ? (mid - 4) / 8 : mid / scale;
  base = kind == EacTestKind::SignedR11 ? std::clamp(base, -127, 127) : std::clamp(base, 0, 255);
  const int base_value = kind == EacTestKind::R11 ? base * 8 + 4 : base * scale;
  const int lo = kind == EacTestKind::SignedR11 ? -1023 : 0;
  const int hi = kind == EacTestKind::Alpha8 ? 255 : kind == EacTestKind::R11 ? 2047 : 1023;
  int best_e = INT_MAX, best_t = 0, best_m = 1;
  for (int tab = 0; tab < 16; ++tab) {
    const auto& row = kEacTables[static_cast<size_t>(tab)];
    const int span = row[7] - row[3];
    const int m = zero_multiplier ? 0 : std::clamp((*mx - *mn) / (span * scale) + 1, 1, 15);
    int e = 0;
    for (int v : t) {
      int be = INT_MAX;
      for (int k = 0; k < 8; ++k) {
        const int s = m == 0 && kind != EacTestKind::Alpha8
                          ? row[static_cast<size_t>(k)]
                          : row[static_cast<size_t>(k)] * m * scale;
        be = std::min(be, std::abs(std::clamp(base_value + s, lo, hi) - v));
      }
      e += be;
    }
    if (e < best_e) best_e = e, best_t = tab, best_m = m;
  }
  uint64_t w = 0;
  put(w, 56, 8, base & 0xFF);
  put(w, 52, 4, best_m);
  put(w, 48, 4, best_t);
  const auto& row = kEacTables[static_cast<size_t>(best_t)];
  for (int i = 0; i < 16; ++i) {
    int best = 0, be = INT_MAX;
    for (int k = 0; k < 8; ++k) {
      const int s = best_m == 0 && kind != EacTestKind::Alpha8
                        ? row[static_cast<size_t>(k)]
                        : row[static_cast<size_t>(k)] * best_m * scale;
      const int e = std::abs(std::clamp(base_value + s, lo, hi) - t[static_cast<size_t>(i)]);
      if (e < be) be = e, best = k;
    }
    // Values are row-major; the block's indices go column by column (i = x * 4 + y).
    const int x = i % 4, y = i / 4;
    put(w, 45 - 3 * (x * 4 + y), 3, best);
  }
  return bytes(w);
}

}  // namespace texsim
