#include "blocks/texture/volume/volume_address_gen.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace texsim {

namespace {

double finite_or_zero(double x) { return std::isfinite(x) ? x : 0.0; }

// Bits of v spread to every third position (3-D Morton interleave of one coordinate).
uint64_t spread3(uint32_t v) {
  uint64_t s = v & 0x1fffff;
  s = (s | (s << 32)) & 0x1f00000000ffffULL;
  s = (s | (s << 16)) & 0x1f0000ff0000ffULL;
  s = (s | (s << 8)) & 0x100f00f00f00f00fULL;
  s = (s | (s << 4)) & 0x10c30c30c30c30c3ULL;
  s = (s | (s << 2)) & 0x1249249249249249ULL;
  return s;
}

uint64_t pow2_ceil(int n) { return std::bit_ceil(static_cast<uint64_t>(std::max(n, 1))); }

}  // namespace

VolumeSize VolumeAddressGen::level_size(VolumeSize base, int level) {
  const auto half = [level](int n) { return std::max(1, n >> std::min(level, 30)); };
  return {half(base.width), half(base.height), half(base.depth)};
}

int VolumeAddressGen::level_count(VolumeSize base) {
  const int m = std::max({base.width, base.height, base.depth, 1});
  return static_cast<int>(std::bit_width(static_cast<unsigned>(m)));
}

float VolumeAddressGen::lambda(const double ddx[3], const double ddy[3], VolumeSize base) {
  const double size[3] = {static_cast<double>(base.width), static_cast<double>(base.height),
                          static_cast<double>(base.depth)};
  double lx = 0, ly = 0;
  for (int k = 0; k < 3; ++k) {
    const double a = finite_or_zero(ddx[k]) * size[k], b = finite_or_zero(ddy[k]) * size[k];
    lx += a * a;
    ly += b * b;
  }
  const double rho2 = std::max(lx, ly);
  if (!(rho2 > 0)) return -INFINITY;
  return static_cast<float>(0.5 * std::log2(std::min(rho2, 1e300)));
}

int VolumeAddressGen::address(int64_t i, int size, AddressMode m) {
  if (i >= 0 && i < size) return static_cast<int>(i);
  switch (m) {
    case AddressMode::Wrap: {
      const int64_t r = i % size;
      return static_cast<int>(r < 0 ? r + size : r);
    }
    case AddressMode::Clamp:
      return i < 0 ? 0 : size - 1;
    case AddressMode::Mirror: {
      const int64_t period = 2 * static_cast<int64_t>(size);
      int64_t r = i % period;
      if (r < 0) r += period;
      return static_cast<int>(r < size ? r : period - 1 - r);
    }
    case AddressMode::Border:
      return -1;
    case AddressMode::MirrorClamp: {
      const int64_t r = i < 0 ? -(i + 1) : i;
      return static_cast<int>(r < size ? r : size - 1);
    }
  }
  return 0;
}

int VolumeAddressGen::level_taps(VolumeSize s, int level, double u, double v, double r,
                                 float weight, VolumeTap* out) const {
  const int n[3] = {s.width, s.height, s.depth};
  const double c[3] = {u, v, r};
  const AddressMode m[3] = {config_.address_u, config_.address_v, config_.address_w};
  int64_t i0[3];
  float f[3];
  for (int k = 0; k < 3; ++k) {
    // Coordinates beyond ±2^40 texels are clamped first: every mode repeats within that.
    const double t = std::clamp(c[k] * n[k] - 0.5, -0x1p40, 0x1p40);
    const double fl = std::floor(t);
    i0[k] = static_cast<int64_t>(fl);
    f[k] = static_cast<float>(t - fl);
  }
  int count = 0;
  for (int corner = 0; corner < 8; ++corner) {
    float w = weight;
    int a[3];
    bool border = false;
    for (int k = 0; k < 3; ++k) {
      const int hi = (corner >> k) & 1;
      w *= hi ? f[k] : 1.0f - f[k];
      a[k] = address(i0[k] + hi, n[k], m[k]);
      border = border || a[k] < 0;
    }
    out[count++] = {level, border ? -1 : a[0], a[1], a[2], w};
  }
  return count;
}

int VolumeAddressGen::taps(VolumeSize base, double u, double v, double r, float lambda,
                           Taps& out) const {
  u = finite_or_zero(u);
  v = finite_or_zero(v);
  r = finite_or_zero(r);
  const int top = level_count(base) - 1;
  const float lam = std::isnan(lambda) ? 0.0f : std::clamp(lambda, 0.0f, static_cast<float>(top));
  if (config_.filter == FilterMode::Nearest) {
    // Level: ⌈λ + ½⌉ − 1 (Vulkan's nearest-mip rounding), then the nearest texel per axis.
    const int level = std::clamp(static_cast<int>(std::ceil(lam + 0.5f)) - 1, 0, top);
    const VolumeSize s = level_size(base, level);
    const int n[3] = {s.width, s.height, s.depth};
    const double c[3] = {u, v, r};
    const AddressMode m[3] = {config_.address_u, config_.address_v, config_.address_w};
    int a[3];
    for (int k = 0; k < 3; ++k)
      a[k] = address(static_cast<int64_t>(std::floor(std::clamp(c[k] * n[k], -0x1p40, 0x1p40))),
                     n[k], m[k]);
    const bool border = a[0] < 0 || a[1] < 0 || a[2] < 0;
    out[0] = {level, border ? -1 : a[0], a[1], a[2], 1.0f};
    return 1;
  }
  if (config_.filter == FilterMode::Bilinear) {
    const int level = std::clamp(static_cast<int>(std::ceil(lam + 0.5f)) - 1, 0, top);
    return level_taps(level_size(base, level), level, u, v, r, 1.0f, out.data());
  }
  const int lo = static_cast<int>(std::floor(lam));
  const int hi = std::min(lo + 1, top);
  const float frac = lam - static_cast<float>(lo);
  int count = level_taps(level_size(base, lo), lo, u, v, r, 1.0f - frac, out.data());
  count += level_taps(level_size(base, hi), hi, u, v, r, frac, out.data() + count);
  return count;
}

uint64_t VolumeAddressGen::texel_index(TexelLayout layout, VolumeSize s, int x, int y, int z) {
  const auto ux = static_cast<uint64_t>(x), uy = static_cast<uint64_t>(y),
             uz = static_cast<uint64_t>(z);
  const auto w = static_cast<uint64_t>(s.width), h = static_cast<uint64_t>(s.height);
  switch (layout) {
    case TexelLayout::Linear:
      return (uz * h + uy) * w + ux;
    case TexelLayout::Tiled4x4: {
      // 4×4×4 bricks of 64 texels, brick after brick in x, y, z order; x fastest inside.
      const uint64_t bx = (w + 3) / 4, by = (h + 3) / 4;
      const uint64_t brick = ((uz >> 2) * by + (uy >> 2)) * bx + (ux >> 2);
      return brick * 64 + (uz & 3) * 16 + (uy & 3) * 4 + (ux & 3);
    }
    case TexelLayout::Morton:
      return spread3(static_cast<uint32_t>(x)) | (spread3(static_cast<uint32_t>(y)) << 1) |
             (spread3(static_cast<uint32_t>(z)) << 2);
  }
  return 0;
}

uint64_t VolumeAddressGen::level_texels(TexelLayout layout, VolumeSize s) {
  const auto w = static_cast<uint64_t>(s.width), h = static_cast<uint64_t>(s.height),
             d = static_cast<uint64_t>(s.depth);
  switch (layout) {
    case TexelLayout::Linear:
      return w * h * d;
    case TexelLayout::Tiled4x4:
      return ((w + 3) / 4) * ((h + 3) / 4) * ((d + 3) / 4) * 64;
    case TexelLayout::Morton: {
      // The interleave's range: every axis padded to the largest power of two.
      const uint64_t p = std::max({pow2_ceil(s.width), pow2_ceil(s.height), pow2_ceil(s.depth)});
      return p * p * p;
    }
  }
  return 0;
}

}  // namespace texsim
