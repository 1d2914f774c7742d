#include "pipeline/image_io/bc7_encoder.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <string>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {

constexpr int kMaxSide = 16384;
// The specification's interpolation weights (of 64) for 2- and 4-bit indices.
constexpr std::array<int, 4> kWeights2 = {0, 21, 43, 64};
constexpr std::array<int, 16> kWeights4 = {0,  4,  9,  13, 17, 21, 26, 30,
                                           34, 38, 43, 47, 51, 55, 60, 64};

using Vec4 = std::array<float, 4>;
using Indices = std::array<int, 16>;

int interpolate(int e0, int e1, int w) { return ((64 - w) * e0 + w * e1 + 32) >> 6; }

// The block's bits, least significant first (bit 0 is byte 0's lowest).
class BitWriter {
 public:
  void put(int n, uint32_t v) {
    for (int i = 0; i < n; ++i, ++pos_) {
      if ((v >> i) & 1U)
        b_[static_cast<size_t>(pos_ / 8)] |= static_cast<uint8_t>(1U << (pos_ % 8));
    }
  }
  const Bc7Block& block() const { return b_; }

 private:
  Bc7Block b_{};
  int pos_ = 0;
};
class BitReader {
 public:
  explicit BitReader(const Bc7Block& b) : b_(b) {}
  int get(int n) {
    int v = 0;
    for (int i = 0; i < n; ++i, ++pos_)
      v |= ((b_[static_cast<size_t>(pos_ / 8)] >> (pos_ % 8)) & 1) << i;
    return v;
  }

 private:
  const Bc7Block& b_;
  int pos_ = 0;
};

int sq(int v) { return v * v; }
// The 7-bit value nearest v / 2 (v an 8-bit value less the p-bit).
int round_to(float v, int top) { return std::clamp(static_cast<int>(std::lround(v)), 0, top); }

// The principal axis of `n`-channel points (power iteration on their covariance), and their
// mean; endpoints at the extreme projections, clamped to 0..255.
void axis_endpoints(const std::array<Vec4, 16>& p, int n, Vec4& e0, Vec4& e1) {
  Vec4 m{};
  for (const Vec4& v : p) {
    for (int k = 0; k < n; ++k) m[static_cast<size_t>(k)] += v[static_cast<size_t>(k)] / 16.0F;
  }
  std::array<Vec4, 4> cov{};
  for (const Vec4& v : p) {
    for (size_t i = 0; i < static_cast<size_t>(n); ++i) {
      for (size_t j = 0; j < static_cast<size_t>(n); ++j)
        cov[i][j] += (v[i] - m[i]) * (v[j] - m[j]);
    }
  }
  Vec4 axis = {1.0F, 1.0F, 1.0F, n == 4 ? 1.0F : 0.0F};
  for (int it = 0; it < 8; ++it) {
    Vec4 next{};
    float len = 0;
    for (size_t i = 0; i < static_cast<size_t>(n); ++i) {
      for (size_t j = 0; j < static_cast<size_t>(n); ++j) next[i] += cov[i][j] * axis[j];
      len += next[i] * next[i];
    }
    if (len < 1e-12F) break;  // no spread along the axis: keep it
    len = std::sqrt(len);
    for (float& a : next) a /= len;
    axis = next;
  }
  float lo = 0, hi = 0;
  for (const Vec4& v : p) {
    float t = 0;
    for (size_t k = 0; k < static_cast<size_t>(n); ++k) t += (v[k] - m[k]) * axis[k];
    lo = std::min(lo, t), hi = std::max(hi, t);
  }
  for (size_t k = 0; k < 4; ++k) {
    e0[k] = std::clamp(m[k] + lo * axis[k], 0.0F, 255.0F);
    e1[k] = std::clamp(m[k] + hi * axis[k], 0.0F, 255.0F);
  }
}

// The endpoints minimising the squared error of the points given their weights (of 64), the
// channels 0..n-1; false when every weight is the same (no unique solution).
bool least_squares(const std::array<Vec4, 16>& p, const Indices& idx, const int* weights, int n,
                   Vec4& e0, Vec4& e1) {
  float a = 0, b = 0, c = 0;
  Vec4 x0{}, x1{};
  for (size_t i = 0; i < 16; ++i) {
    const float w = static_cast<float>(weights[idx[i]]) / 64.0F, u = 1.0F - w;
    a += u * u, b += u * w, c += w * w;
    for (size_t k = 0; k < static_cast<size_t>(n); ++k) x0[k] += u * p[i][k], x1[k] += w * p[i][k];
  }
  const float det = a * c - b * b;
  if (std::fabs(det) < 1e-6F) return false;
  for (size_t k = 0; k < static_cast<size_t>(n); ++k) {
    e0[k] = std::clamp((c * x0[k] - b * x1[k]) / det, 0.0F, 255.0F);
    e1[k] = std::clamp((a * x1[k] - b * x0[k]) / det, 0.0F, 255.0F);
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// Mode 6

struct Mode6 {
  std::array<int, 4> q0{}, q1{};  // 7-bit endpoints
  int p0 = 0, p1 = 0;
  Indices idx{};
  int err = INT_MAX;
};

// The quantised endpoints (every p-bit pair tried) and nearest indices for float endpoints.
Mode6 fit_mode6(const Bc7Pixels& px, const Vec4& e0, const Vec4& e1) {
  Mode6 best;
  for (int pp = 0; pp < 4; ++pp) {
    Mode6 m;
    m.p0 = pp & 1, m.p1 = pp >> 1;
    std::array<std::array<int, 4>, 16> pal{};
    for (size_t k = 0; k < 4; ++k) {
      m.q0[k] = round_to((e0[k] - static_cast<float>(m.p0)) / 2.0F, 127);
      m.q1[k] = round_to((e1[k] - static_cast<float>(m.p1)) / 2.0F, 127);
      for (size_t w = 0; w < 16; ++w)
        pal[w][k] = interpolate(m.q0[k] * 2 + m.p0, m.q1[k] * 2 + m.p1, kWeights4[w]);
    }
    m.err = 0;
    for (size_t i = 0; i < 16; ++i) {
      int be = INT_MAX;
      for (size_t w = 0; w < 16; ++w) {
        int e = 0;
        for (size_t k = 0; k < 4; ++k) e += sq(pal[w][k] - px[i][k]);
        if (e < be) be = e, m.idx[i] = static_cast<int>(w);
      }
      m.err += be;
    }
    if (m.err < best.err) best = m;
  }
  return best;
}

Bc7Block write_mode6(Mode6 m) {
  if (m.idx[0] >= 8) {  // the anchor index's top bit is implicit 0: swap the endpoints
    std::swap(m.q0, m.q1);
    std::swap(m.p0, m.p1);
    for (int& i : m.idx) i = 15 - i;
  }
  BitWriter w;
  w.put(7, 1U << 6);
  for (size_t k = 0; k < 4; ++k) {
    w.put(7, static_cast<uint32_t>(m.q0[k]));
    w.put(7, static_cast<uint32_t>(m.q1[k]));
  }
  w.put(1, static_cast<uint32_t>(m.p0));
  w.put(1, static_cast<uint32_t>(m.p1));
  for (size_t i = 0; i < 16; ++i) w.put(i == 0 ? 3 : 4, static_cast<uint32_t>(m.idx[i]));
  return w.block();
}

std::array<Vec4, 16> as_floats(const Bc7Pixels& px) {
  std::array<Vec4, 16> p{};
  for (size_t i = 0; i < 16; ++i) {
    for (size_t k = 0; k < 4; ++k) p[i][k] = px[i][k];
  }
  return p;
}

Bc7Block encode_mode6(const Bc7Pixels& px, int passes) {
  const std::array<Vec4, 16> p = as_floats(px);
  Vec4 e0{}, e1{};
  axis_endpoints(p, 4, e0, e1);
  Mode6 best = fit_mode6(px, e0, e1);
  for (int pass = 0; pass < passes; ++pass) {
    if (!least_squares(p, best.idx, kWeights4.data(), 4, e0, e1)) break;
    const Mode6 next = fit_mode6(px, e0, e1);
    if (next.err >= best.err) break;
    best = next;
  }
  return write_mode6(best);
}

// ---------------------------------------------------------------------------------------------
// Mode 5

// The pixels with alpha swapped into the channel `rotation` names (1 R, 2 G, 3 B; 0 none): the
// decoder swaps them back.
Bc7Pixels rotated(const Bc7Pixels& px, int rotation) {
  Bc7Pixels r = px;
  if (rotation == 0) return r;
  for (auto& p : r) std::swap(p[static_cast<size_t>(rotation - 1)], p[3]);
  return r;
}

struct Mode5Part {
  std::array<int, 3> q0{}, q1{};  // 7-bit colour or (q0[0], q1[0]) 8-bit alpha endpoints
  Indices idx{};
  int err = INT_MAX;
};

// Colour (channels 0..2, 7-bit endpoints) or alpha (channel 3, 8-bit) with 2-bit indices.
Mode5Part fit_mode5_part(const Bc7Pixels& px, bool alpha, const Vec4& e0, const Vec4& e1) {
  Mode5Part m;
  const size_t first = alpha ? 3 : 0, n = alpha ? 1 : 3;
  std::array<std::array<int, 3>, 4> pal{};
  for (size_t k = 0; k < n; ++k) {
    int v0 = 0, v1 = 0;
    if (alpha) {
      v0 = m.q0[k] = round_to(e0[first], 255);
      v1 = m.q1[k] = round_to(e1[first], 255);
    } else {
      m.q0[k] = round_to(e0[k] * 127.0F / 255.0F, 127);
      m.q1[k] = round_to(e1[k] * 127.0F / 255.0F, 127);
      v0 = (m.q0[k] << 1) | (m.q0[k] >> 6);
      v1 = (m.q1[k] << 1) | (m.q1[k] >> 6);
    }
    for (size_t w = 0; w < 4; ++w) pal[w][k] = interpolate(v0, v1, kWeights2[w]);
  }
  m.err = 0;
  for (size_t i = 0; i < 16; ++i) {
    int be = INT_MAX;
    for (size_t w = 0; w < 4; ++w) {
      int e = 0;
      for (size_t k = 0; k < n; ++k) e += sq(pal[w][k] - px[i][first + k]);
      if (e < be) be = e, m.idx[i] = static_cast<int>(w);
    }
    m.err += be;
  }
  return m;
}

Mode5Part encode_mode5_part(const Bc7Pixels& px, bool alpha, int passes) {
  const std::array<Vec4, 16> p = as_floats(px);
  Vec4 e0{}, e1{};
  if (alpha) {
    e0[3] = 255, e1[3] = 0;
    for (const Vec4& v : p) e0[3] = std::min(e0[3], v[3]), e1[3] = std::max(e1[3], v[3]);
  } else {
    axis_endpoints(p, 3, e0, e1);
  }
  Mode5Part best = fit_mode5_part(px, alpha, e0, e1);
  for (int pass = 0; pass < passes; ++pass) {
    std::array<Vec4, 16> q = p;
    if (alpha) {
      for (Vec4& v : q) v[0] = v[3];  // least squares on channel 0
    }
    Vec4 l0{}, l1{};
    if (!least_squares(q, best.idx, kWeights2.data(), alpha ? 1 : 3, l0, l1)) break;
    if (alpha) l0[3] = l0[0], l1[3] = l1[0];
    const Mode5Part next = fit_mode5_part(px, alpha, l0, l1);
    if (next.err >= best.err) break;
    best = next;
  }
  return best;
}

Bc7Block encode_mode5(const Bc7Pixels& px, int rotation, int passes) {
  const Bc7Pixels r = rotated(px, rotation);
  Mode5Part c = encode_mode5_part(r, false, passes), a = encode_mode5_part(r, true, passes);
  for (Mode5Part* part : {&c, &a}) {
    if (part->idx[0] >= 2) {  // anchor index top bit implicit 0
      std::swap(part->q0, part->q1);
      for (int& i : part->idx) i = 3 - i;
    }
  }
  BitWriter w;
  w.put(6, 1U << 5);
  w.put(2, static_cast<uint32_t>(rotation));
  for (size_t k = 0; k < 3; ++k) {
    w.put(7, static_cast<uint32_t>(c.q0[k]));
    w.put(7, static_cast<uint32_t>(c.q1[k]));
  }
  w.put(8, static_cast<uint32_t>(a.q0[0]));
  w.put(8, static_cast<uint32_t>(a.q1[0]));
  for (size_t i = 0; i < 16; ++i) w.put(i == 0 ? 1 : 2, static_cast<uint32_t>(c.idx[i]));
  for (size_t i = 0; i < 16; ++i) w.put(i == 0 ? 1 : 2, static_cast<uint32_t>(a.idx[i]));
  return w.block();
}

int block_error(const Bc7Block& b, const Bc7Pixels& px) {
  Bc7Pixels got{};
  if (!bc7_reconstruct(b, &got)) return INT_MAX;
  int e = 0;
  for (size_t i = 0; i < 16; ++i) {
    for (size_t k = 0; k < 4; ++k) e += sq(got[i][k] - px[i][k]);
  }
  return e;
}

}  // namespace

const char* bc7_quality_name(Bc7Quality q) { return q == Bc7Quality::Fast ? "fast" : "normal"; }

bool bc7_reconstruct(const Bc7Block& b, Bc7Pixels* out) {
  BitReader r(b);
  if (b[0] & 0x40 && !(b[0] & 0x3F)) {  // mode 6: bits 0..5 clear, bit 6 set
    r.get(7);
    std::array<int, 4> e0{}, e1{};
    for (size_t k = 0; k < 4; ++k) e0[k] = r.get(7) << 1, e1[k] = r.get(7) << 1;
    const int p0 = r.get(1), p1 = r.get(1);
    for (size_t k = 0; k < 4; ++k) e0[k] |= p0, e1[k] |= p1;
    for (size_t i = 0; i < 16; ++i) {
      const int w = kWeights4[static_cast<size_t>(r.get(i == 0 ? 3 : 4))];
      for (size_t k = 0; k < 4; ++k)
        (*out)[i][k] = static_cast<uint8_t>(interpolate(e0[k], e1[k], w));
    }
    return true;
  }
  if (!(b[0] & 0x20) || (b[0] & 0x1F)) return false;  // mode 5: bits 0..4 clear, bit 5 set
  r.get(6);
  const int rotation = r.get(2);
  std::array<int, 4> e0{}, e1{};
  for (size_t k = 0; k < 3; ++k) {
    e0[k] = r.get(7), e1[k] = r.get(7);
    e0[k] = (e0[k] << 1) | (e0[k] >> 6), e1[k] = (e1[k] << 1) | (e1[k] >> 6);
  }
  e0[3] = r.get(8), e1[3] = r.get(8);
  Indices ci{}, ai{};
  for (size_t i = 0; i < 16; ++i) ci[i] = r.get(i == 0 ? 1 : 2);
  for (size_t i = 0; i < 16; ++i) ai[i] = r.get(i == 0 ? 1 : 2);
  for (size_t i = 0; i < 16; ++i) {
    auto& p = (*out)[i];
    for (size_t k = 0; k < 4; ++k) {
      const int w = kWeights2[static_cast<size_t>(k == 3 ? ai[i] : ci[i])];
      p[k] = static_cast<uint8_t>(interpolate(e0[k], e1[k], w));
    }
    if (rotation > 0) std::swap(p[static_cast<size_t>(rotation - 1)], p[3]);
  }
  return true;
}

Bc7Block bc7_encode_block(const Bc7Pixels& px, Bc7Quality q) {
  Bc7Block best = encode_mode6(px, q == Bc7Quality::Fast ? 1 : 3);
  if (q == Bc7Quality::Fast) return best;
  int best_e = block_error(best, px);
  for (int rotation = 0; rotation < 4 && best_e > 0; ++rotation) {
    const Bc7Block b = encode_mode5(px, rotation, 2);
    const int e = block_error(b, px);
    if (e < best_e) best_e = e, best = b;
  }
  return best;
}

EncodedLevel bc7_encode(const Rgba8Image& img, FileBlockFormat format, Bc7Quality q) {
  const std::string who = "texsim bc7 encoder";
  check_encoder_input(img, who, kMaxSide);
  if (format != FileBlockFormat::Bc7Unorm)
    throw InputError(who, std::string(format_name(format)) + " is not encoded (BC7_UNORM is)");
  const Rgba8Image padded = padded_to_blocks(img, 4, 4);
  EncodedLevel out;
  out.format = format;
  out.width = img.width;
  out.height = img.height;
  const int bx = padded.width / 4, by = padded.height / 4;
  out.bytes.resize(static_cast<size_t>(bx) * static_cast<size_t>(by) * 16);
  const auto row_bytes = static_cast<size_t>(padded.width) * 4;
  uint8_t* at = out.bytes.data();
  for (int y = 0; y < by; ++y) {
    for (int x = 0; x < bx; ++x) {
      Bc7Pixels px{};
      for (size_t i = 0; i < 16; ++i) {
        const size_t from = (static_cast<size_t>(y) * 4 + i / 4) * row_bytes +
                            (static_cast<size_t>(x) * 4 + i % 4) * 4;
        std::memcpy(px[i].data(), padded.rgba.data() + from, 4);
      }
      const Bc7Block b = bc7_encode_block(px, q);
      std::memcpy(at, b.data(), b.size());
      at += b.size();
    }
  }
  out.provenance = std::string("texsim bc7 encoder (") +
                   (q == Bc7Quality::Fast ? "mode 6, fast" : "modes 6 and 5, normal") + ")";
  return out;
}

}  // namespace texsim
