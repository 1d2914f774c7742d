#include "blocks/texture/memory/storage_format.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace texsim {

namespace {

using C = ChannelCoding;
constexpr std::array<StorageFormatInfo, static_cast<size_t>(StorageFormat::kCount)> kFormats = {{
    {"r8", 1, 1, {8}, C::Unorm, false},
    {"rg8", 2, 2, {8, 8}, C::Unorm, false},
    {"rgba8", 4, 4, {8, 8, 8, 8}, C::Unorm, false},
    {"r8_snorm", 1, 1, {8}, C::Snorm, false},
    {"rg8_snorm", 2, 2, {8, 8}, C::Snorm, false},
    {"rgba8_snorm", 4, 4, {8, 8, 8, 8}, C::Snorm, false},
    {"srgb8_a8", 4, 4, {8, 8, 8, 8}, C::Srgb, false},
    {"rgb565", 2, 3, {5, 6, 5}, C::Unorm, false},
    {"rgba4444", 2, 4, {4, 4, 4, 4}, C::Unorm, false},
    {"rgb5a1", 2, 4, {5, 5, 5, 1}, C::Unorm, false},
    {"rgb10a2", 4, 4, {10, 10, 10, 2}, C::Unorm, false},
    {"r16f", 2, 1, {16}, C::Float16, false},
    {"rg16f", 4, 2, {16, 16}, C::Float16, false},
    {"rgba16f", 8, 4, {16, 16, 16, 16}, C::Float16, false},
    {"r32f", 4, 1, {32}, C::Float32, false},
    {"rg32f", 8, 2, {32, 32}, C::Float32, false},
    {"rgba32f", 16, 4, {32, 32, 32, 32}, C::Float32, false},
    {"d16", 2, 1, {16}, C::Unorm, true},
    {"d32f", 4, 1, {32}, C::Float32, true},
}};

// UNORM code of f with b bits: clamp, scale in float (the product of the 8-bit texture path),
// nearest with halves up.
uint32_t unorm_code(float f, int b) {
  if (!(f == f)) return 0;
  const auto max = static_cast<float>((1u << b) - 1u);
  const float c = std::clamp(f, 0.0f, 1.0f) * max;
  const auto whole = static_cast<uint32_t>(c);
  return whole + (c - static_cast<float>(whole) >= 0.5f ? 1u : 0u);
}

float unorm_value(uint32_t code, int b) {
  return static_cast<float>(code) / static_cast<float>((1u << b) - 1u);
}

// SNORM code of f with b bits, as a signed integer: nearest, halves away from zero.
int32_t snorm_code(float f, int b) {
  if (!(f == f)) return 0;
  const auto max = static_cast<float>((1 << (b - 1)) - 1);
  return static_cast<int32_t>(std::round(std::clamp(f, -1.0f, 1.0f) * max));
}

float snorm_value(int32_t code, int b) {
  return std::max(static_cast<float>(code) / static_cast<float>((1 << (b - 1)) - 1), -1.0f);
}

double eotf(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

struct SrgbTable {
  std::array<float, 256> v{};
  SrgbTable() {
    for (int i = 0; i < 256; ++i) v[static_cast<size_t>(i)] = static_cast<float>(eotf(i / 255.0));
  }
};

float convert_channel(const StorageFormatInfo& info, int channel, float in) {
  const int b = info.bits[channel];
  switch (info.coding) {
    case C::Unorm:
      return unorm_value(unorm_code(in, b), b);
    case C::Snorm:
      return snorm_value(snorm_code(in, b), b);
    case C::Srgb: {
      const uint32_t code = unorm_code(in, 8);
      return channel == 3 ? unorm_value(code, 8) : srgb_to_linear(static_cast<uint8_t>(code));
    }
    case C::Float16:
      return float_from_half(half_from_float(in));
    case C::Float32:
      return in;
  }
  return in;
}

}  // namespace

const StorageFormatInfo& format_info(StorageFormat f) { return kFormats[static_cast<size_t>(f)]; }

std::optional<StorageFormat> storage_format_from_name(std::string_view name) {
  for (size_t i = 0; i < kFormats.size(); ++i) {
    if (kFormats[i].name == name) return static_cast<StorageFormat>(i);
  }
  return std::nullopt;
}

std::string storage_format_names() {
  std::string s;
  for (const auto& f : kFormats) {
    if (!s.empty()) s += ", ";
    s += f.name;
  }
  return s;
}

glm::vec4 convert_texel(StorageFormat f, const glm::vec4& in) {
  const StorageFormatInfo& info = format_info(f);
  glm::vec4 out(0.0f, 0.0f, 0.0f, 1.0f);
  for (int c = 0; c < info.channels; ++c) out[c] = convert_channel(info, c, in[c]);
  return out;
}

glm::vec4 border_texel(StorageFormat f, const glm::vec4& border) {
  const StorageFormatInfo& info = format_info(f);
  glm::vec4 out(0.0f, 0.0f, 0.0f, 1.0f);
  for (int c = 0; c < info.channels; ++c) {
    const float b = border[c];
    switch (info.coding) {
      case ChannelCoding::Unorm:
      case ChannelCoding::Srgb:
        out[c] = std::clamp(b, 0.0f, 1.0f);
        break;
      case ChannelCoding::Snorm:
        out[c] = std::clamp(b, -1.0f, 1.0f);
        break;
      case ChannelCoding::Float16:
      case ChannelCoding::Float32:
        out[c] = b;
        break;
    }
  }
  return out;
}

bool decodes_to_bytes(StorageFormat f) {
  return f == StorageFormat::R8Unorm || f == StorageFormat::Rg8Unorm ||
         f == StorageFormat::Rgba8Unorm;
}

uint16_t half_from_float(float f) {
  uint32_t x = 0;
  std::memcpy(&x, &f, sizeof x);
  const auto sign = static_cast<uint16_t>((x >> 16) & 0x8000u);
  const uint32_t ax = x & 0x7fffffffu;
  if (ax >= 0x7f800000u) {  // infinity, or NaN (made quiet, top payload bits kept)
    return static_cast<uint16_t>(sign | 0x7c00u |
                                 (ax > 0x7f800000u ? 0x200u | ((ax >> 13) & 0x3ffu) : 0u));
  }
  if (ax >= 0x477ff000u) return static_cast<uint16_t>(sign | 0x7c00u);  // ≥ 65520: infinity
  if (ax >= 0x38800000u) {  // a normal half: rebias the exponent, round the 13 dropped bits
    uint32_t h = ((((ax >> 23) - 127u + 15u) << 10) | ((ax & 0x7fffffu) >> 13));
    const uint32_t rem = ax & 0x1fffu;
    if (rem > 0x1000u || (rem == 0x1000u && (h & 1u))) ++h;  // a carry may reach the exponent
    return static_cast<uint16_t>(sign | h);
  }
  // A subnormal half (or zero): the value in units of 2^-24 is m · 2^-(126 - E).
  const uint32_t e = ax >> 23;
  const uint32_t shift = 126u - e;
  if (e == 0 || shift >= 25u) return sign;  // below a quarter unit: zero
  const uint32_t m = (ax & 0x7fffffu) | 0x800000u;
  uint32_t h = m >> shift;
  const uint32_t rem = m & ((1u << shift) - 1u), half = 1u << (shift - 1u);
  if (rem > half || (rem == half && (h & 1u))) ++h;  // 1024 becomes the smallest normal
  return static_cast<uint16_t>(sign | h);
}

float float_from_half(uint16_t h) {
  const float sign = (h & 0x8000u) ? -1.0f : 1.0f;
  const int e = (h >> 10) & 0x1f;
  const int m = h & 0x3ff;
  if (e == 31) return m ? std::numeric_limits<float>::quiet_NaN() : sign * INFINITY;
  if (e == 0) return sign * std::ldexp(static_cast<float>(m), -24);
  return sign * std::ldexp(static_cast<float>(m + 1024), e - 25);
}

float srgb_eotf(float c) {
  if (!(c == c)) return 0.0f;
  return static_cast<float>(eotf(std::clamp(static_cast<double>(c), 0.0, 1.0)));
}

float srgb_to_linear(uint8_t code) {
  static const SrgbTable table;
  return table.v[code];
}

float srgb_oetf(float linear) {
  if (!(linear == linear)) return 0.0f;
  const double l = std::clamp(static_cast<double>(linear), 0.0, 1.0);
  return static_cast<float>(l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055);
}

uint8_t srgb_code(float linear) {
  int lo = 0, hi = 255;  // the first code whose value is >= linear, then the nearer neighbour
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (srgb_to_linear(static_cast<uint8_t>(mid)) < linear) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  if (lo > 0 && linear - srgb_to_linear(static_cast<uint8_t>(lo - 1)) <
                    srgb_to_linear(static_cast<uint8_t>(lo)) - linear)
    --lo;
  return static_cast<uint8_t>(lo);
}

}  // namespace texsim
