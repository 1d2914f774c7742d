#pragma once
// The input vectors of the RTL blocks' checks, shared by the Verilator lockstep tests and the
// Icarus Verilog runs (test_rtl_iverilog), and the vector-file format the Icarus testbenches
// read (docs/rtl/blocks.md, "Vector files"). No Verilator here.
#include <array>
#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rtl_model/params/rtl_params.h"

namespace texsim::rtl {

// V(d): the P1 breakpoints ±2, every code of the input format once, then seeded random codes.
template <class Fmt>
std::vector<uint32_t> vd_vectors(uint64_t n_random, uint64_t seed) {
  using In = typename Fmt::In;
  std::vector<uint32_t> v;
  const auto& c = VdCoefficientsIn<Fmt>::get();
  for (int64_t b : {c.p1_break[0].raw(), c.p1_break[1].raw()}) {
    for (int64_t k = b - 2; k <= b + 2; ++k) v.push_back(static_cast<uint32_t>(k));
  }
  for (uint32_t d = 0; d <= static_cast<uint32_t>(In::kRawMax); ++d) v.push_back(d);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<uint32_t> code(0, static_cast<uint32_t>(In::kRawMax));
  for (uint64_t i = 0; i < n_random; ++i) v.push_back(code(rng));
  return v;
}

// Bilinear lerp: a quad of four RGBA texels (one word each, R in the low bits) and the weights.
struct LerpIn {
  std::array<uint64_t, 4> quad;
  uint32_t fx, fy;
  std::string text() const {
    std::ostringstream s;
    s << std::hex << "t " << quad[0] << " " << quad[1] << " " << quad[2] << " " << quad[3] << " fx "
      << fx << " fy " << fy;
    return s.str();
  }
};

// Directed corners (zero and full-scale texels, alternating channels, extreme and middle
// weights), then seeded random quads and weights.
inline std::vector<LerpIn> lerp_vectors(const BilinearLerp::Config& c, uint64_t n_random,
                                        uint64_t seed) {
  const uint64_t word = (uint64_t{1} << (4 * c.texel_bits)) - 1;
  const uint32_t wmax = (1u << c.sub_bits) - 1;
  const uint64_t alt = word / ((uint64_t{1} << (2 * c.texel_bits)) + 1) *
                       ((uint64_t{1} << c.texel_bits) - 1);  // channels 0, max, 0, max
  std::vector<LerpIn> v;
  const std::array<uint64_t, 4> quads[] = {{0},
                                           {word, word, word, word},
                                           {0, word, 0, word},
                                           {word, 0, word, 0},
                                           {0, 0, word, word},
                                           {alt, word - alt, word - alt, alt},
                                           {word, 0, 0, word}};
  for (const auto& q : quads) {
    for (uint32_t fx : {0u, 1u, wmax / 2, wmax / 2 + 1, wmax}) {
      for (uint32_t fy : {0u, 1u, wmax / 2, wmax / 2 + 1, wmax}) v.push_back({q, fx, fy});
    }
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<uint64_t> texel(0, word);
  std::uniform_int_distribution<uint32_t> weight(0, wmax);
  for (uint64_t i = 0; i < n_random; ++i) {
    LerpIn in{{texel(rng), texel(rng), texel(rng), texel(rng)}, weight(rng), weight(rng)};
    v.push_back(in);
  }
  return v;
}

// One field of a vector: its value and width in bits (at most 64).
using VectorField = std::pair<uint64_t, int>;

// One line of a vector file: the fields concatenated, the first the most significant, as one
// hexadecimal number of ⌈total bits / 4⌉ digits.
inline std::string vector_line(const std::vector<VectorField>& fields) {
  int total = 0;
  for (const auto& f : fields) total += f.second;
  std::vector<uint8_t> bits(static_cast<size_t>(total), 0);  // bits[0] is the least significant
  int pos = total;
  for (const auto& [value, width] : fields) {
    pos -= width;
    for (int b = 0; b < width; ++b) {
      const int at = pos + b;
      bits[static_cast<size_t>(at)] = static_cast<uint8_t>((value >> b) & 1u);
    }
  }
  const int digits = (total + 3) / 4;
  std::string s(static_cast<size_t>(digits), '0');
  for (int d = 0; d < digits; ++d) {
    int nib = 0;
    for (int b = 0; b < 4; ++b) {
      const int i = 4 * d + b;
      if (i < total && bits[static_cast<size_t>(i)]) nib |= 1 << b;
    }
    const int at = digits - 1 - d;
    s[static_cast<size_t>(at)] = "0123456789abcdef"[nib];
  }
  return s;
}

// A vector file: a comment header (block, field layout, latency, count), then one line each.
inline void write_vector_file(const std::string& path, const std::string& block,
                              const std::string& layout, uint32_t latency,
                              const std::vector<std::string>& lines) {
  std::ofstream f(path);
  f << "// texsim RTL vectors: " << block << "\n// fields, most significant first: " << layout
    << "\n// latency " << latency << " cycles; " << lines.size() << " vectors\n";
  for (const std::string& l : lines) f << l << "\n";
}

}  // namespace texsim::rtl
