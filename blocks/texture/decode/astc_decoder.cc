#include "blocks/texture/decode/astc_decoder.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/texture/decode/astc_endpoints.h"
#include "blocks/texture/decode/astc_integer_sequence.h"
#include "blocks/texture/decode/astc_partition.h"
#include "blocks/texture/decode/astc_weights.h"
#include "blocks/texture/decode/compressed_format.h"

namespace texsim {

static_assert(Block<AstcDecoder>);

namespace {

constexpr glm::vec4 kErrorColor{1.0F, 0.0F, 1.0F, 1.0F};  // opaque magenta

// C / 65536 rounded toward zero to FP16 (11 significant bits; below 2^-14 the FP16 denormals
// hold C / 65536 exactly), as a float.
float float16_toward_zero(int c) {
  int kept = c;
  int width = 0;
  while ((c >> width) != 0) ++width;
  if (width > 11) kept = (c >> (width - 11)) << (width - 11);
  return static_cast<float>(kept) / 65536.0F;
}

// The colour endpoint layout of a block: partitions, their modes and where the fields lie.
struct Layout {
  int partitions = 1;
  int seed = 0;
  std::array<int, 4> cem{};
  int extra_cem_bits = 0;  // CEM bits below the weights
  int config_bits = 17;    // bits before the colour data, plus the CCS of a dual plane
  int color_start = 17;    // first bit of the colour integers
  int value_count = 0;     // colour integers
};

Layout read_layout(const AstcBits& bits, const AstcBlockMode& mode) {
  Layout l;
  l.partitions = static_cast<int>(bits.get(11, 2)) + 1;
  if (l.partitions == 1) {
    l.cem[0] = static_cast<int>(bits.get(13, 4));
  } else {
    l.seed = static_cast<int>(bits.get(13, 10));
    l.color_start = 29;
    uint32_t field = bits.get(23, 6);
    if ((field & 3U) == 0) {
      for (int p = 0; p < l.partitions; ++p)
        l.cem[static_cast<size_t>(p)] = static_cast<int>(field >> 2);
      l.config_bits = 29;
    } else {
      l.extra_cem_bits = 3 * l.partitions - 4;
      l.config_bits = 25 + 3 * l.partitions;
      field |= bits.get(128 - mode.weight_bits - l.extra_cem_bits, l.extra_cem_bits) << 6;
      const int base_class = static_cast<int>(field & 3U) - 1;
      for (int p = 0; p < l.partitions; ++p) {
        const int cls = base_class + static_cast<int>((field >> (2 + p)) & 1U);
        const int low = static_cast<int>((field >> (2 + l.partitions + 2 * p)) & 3U);
        l.cem[static_cast<size_t>(p)] = (cls << 2) | low;
      }
    }
  }
  if (mode.dual_plane) l.config_bits += 2;
  for (int p = 0; p < l.partitions; ++p)
    l.value_count += 2 * ((l.cem[static_cast<size_t>(p)] >> 2) + 1);
  return l;
}

}  // namespace

AstcDecoder::Config AstcDecoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"block_width", "block_height", "mode", "datapath"});
  Config c;
  c.block_width = static_cast<int>(r.get_int("block_width", c.block_width, 4, 12));
  c.block_height = static_cast<int>(r.get_int("block_height", c.block_height, 4, 12));
  c.mode = static_cast<Mode>(r.get_choice("mode", 0, {"unorm16", "float16", "unorm8"}));
  c.datapath = parse_datapath(r, c.datapath);
  if (!valid_footprint(c.block_width, c.block_height)) {
    r.fail("block_width",
           "block_width × block_height must be an ASTC 2-D footprint (4x4, 5x4, "
           "5x5, 6x5, 6x6, 8x5, 8x6, 8x8, 10x5, 10x6, 10x8, 10x10, 12x10, 12x12)");
  }
  return c;
}

AstcDecoder::AstcDecoder() : AstcDecoder(Config{}) {}

AstcDecoder::AstcDecoder(const Config& c) : cfg_(c) {
  if (!valid_footprint(c.block_width, c.block_height)) {
    throw std::invalid_argument("AstcDecoder: " + std::to_string(c.block_width) + "x" +
                                std::to_string(c.block_height) + " is not an ASTC 2-D footprint");
  }
}

bool AstcDecoder::valid_footprint(int width, int height) {
  // The 14 footprints are the ASTC rows of the compressed formats' table.
  for (int f = 0; f < kCompressedFormats; ++f) {
    const CompressedFormatInfo& i = format_info(static_cast<CompressedFormat>(f));
    if (i.family == CodecFamily::Astc && i.block_w == width && i.block_h == height) return true;
  }
  return false;
}

float AstcDecoder::output(int c) const {
  switch (cfg_.mode) {
    case Mode::Unorm16:
      return static_cast<float>(c) / 65535.0F;
    case Mode::Float16:
      return c == 65535 ? 1.0F : float16_toward_zero(c);
    case Mode::Unorm8:
      return static_cast<float>(c >> 8) / 255.0F;
  }
  return 0.0F;
}

DecodedBlock AstcDecoder::error_block(AstcError why, AstcBlockInfo* info) const {
  DecodedBlock out;
  out.width = cfg_.block_width;
  out.height = cfg_.block_height;
  const int n = out.width * out.height;
  std::fill_n(out.texels.begin(), n, kErrorColor);
  if (info != nullptr) info->error = why;
  return out;
}

DecodedBlock AstcDecoder::void_extent(const AstcBits& bits, AstcBlockInfo* info) const {
  if (info != nullptr) info->void_extent = true;
  if (bits.get(10, 2) != 3) return error_block(AstcError::VoidExtentReservedBits, info);
  const uint32_t min_s = bits.get(12, 13), max_s = bits.get(25, 13);
  const uint32_t min_t = bits.get(38, 13), max_t = bits.get(51, 13);
  const bool all_ones = min_s == 0x1FFF && max_s == 0x1FFF && min_t == 0x1FFF && max_t == 0x1FFF;
  if (!all_ones && (min_s >= max_s || min_t >= max_t)) {
    return error_block(AstcError::VoidExtentCoordinates, info);
  }
  if (bits.get(9, 1) != 0) return error_block(AstcError::HdrVoidExtent, info);
  DecodedBlock out;
  out.width = cfg_.block_width;
  out.height = cfg_.block_height;
  std::array<uint16_t, 4> c{};
  glm::vec4 colour;
  for (int ch = 0; ch < 4; ++ch) {
    c[static_cast<size_t>(ch)] = static_cast<uint16_t>(bits.get(64 + 16 * ch, 16));
    colour[ch] = output(c[static_cast<size_t>(ch)]);
  }
  const int n = out.width * out.height;
  std::fill_n(out.texels.begin(), n, colour);
  if (info != nullptr) std::fill_n(info->unorm16.begin(), n, c);
  return out;
}

DecodedBlock AstcDecoder::decode(std::span<const uint8_t, kBlockBytes> block,
                                 AstcBlockInfo* info) const {
  const int bw = cfg_.block_width, bh = cfg_.block_height;
  const AstcBits bits(block);
  const AstcBlockMode mode = astc_decode_block_mode(bits.get(0, 11), bw, bh);
  if (info != nullptr) *info = AstcBlockInfo{.mode = mode};
  if (mode.kind == AstcBlockMode::Kind::VoidExtent) return void_extent(bits, info);
  if (mode.kind == AstcBlockMode::Kind::Reserved) {
    return error_block(AstcError::ReservedBlockMode, info);
  }
  const Layout l = read_layout(bits, mode);
  if (mode.dual_plane && l.partitions == 4) {
    return error_block(AstcError::DualPlaneFourPartitions, info);
  }
  if (l.value_count > 18) return error_block(AstcError::TooManyColorValues, info);
  const int color_range =
      astc_select_color_range(l.value_count, 128 - l.config_bits - mode.weight_bits);
  if (color_range < 0) return error_block(AstcError::TooFewColorBits, info);

  // Weights: the stream grows down from bit 127, plane 0 and plane 1 interleaved.
  std::array<int, kAstcMaxSequence> stored{};
  astc_decode_sequence(bits.reversed(), 0, mode.weight_count, astc_weight_range(mode.weight_range),
                       stored);
  const int planes = mode.dual_plane ? 2 : 1;
  const int grid_size = mode.grid_width * mode.grid_height;
  std::array<std::array<int, kMaxBlockTexels>, 2> weights{};
  for (int p = 0; p < planes; ++p) {
    std::array<int, kAstcMaxSequence> grid{};
    for (int i = 0; i < grid_size; ++i) {
      const int k = i * planes + p;  // the planes' weights are interleaved
      grid[static_cast<size_t>(i)] =
          astc_unquantize_weight(stored[static_cast<size_t>(k)], mode.weight_range);
    }
    astc_infill_weights(std::span<const int>(grid.data(), static_cast<size_t>(grid_size)),
                        mode.grid_width, mode.grid_height, bw, bh, weights[static_cast<size_t>(p)]);
  }
  const int ccs = mode.dual_plane
                      ? static_cast<int>(bits.get(128 - mode.weight_bits - l.extra_cem_bits - 2, 2))
                      : -1;

  // Colour endpoints of each partition.
  std::array<int, 18> values{};
  astc_decode_sequence(bits, l.color_start, l.value_count, astc_color_range(color_range), values);
  std::array<AstcEndpoints, 4> ends{};
  uint8_t hdr = 0;
  for (int p = 0, v = 0; p < l.partitions; ++p) {
    const int cem = l.cem[static_cast<size_t>(p)];
    const int count = 2 * ((cem >> 2) + 1);
    std::array<int, 8> unq{};
    for (int i = 0; i < count; ++i) {
      unq[static_cast<size_t>(i)] = astc_unquantize_color(
          values.at(static_cast<size_t>(v) + static_cast<size_t>(i)), color_range);
    }
    v += count;
    if (astc_is_ldr_endpoint_mode(cem)) {
      ends[static_cast<size_t>(p)] = astc_decode_ldr_endpoints(
          cem, std::span<const int>(unq.data(), static_cast<size_t>(count)));
    } else {
      hdr = static_cast<uint8_t>(hdr | (1U << p));
    }
  }
  if (info != nullptr) {
    info->error = hdr != 0 ? AstcError::HdrEndpointMode : AstcError::None;
    info->partitions = l.partitions;
    info->partition_seed = l.seed;
    info->cem = l.cem;
    info->hdr_partitions = hdr;
    info->color_range = color_range;
    info->ccs = ccs;
  }

  // Texels: partition, then per component C = ⌊(C0·(64 − i) + C1·i + 32) / 64⌋ with the
  // endpoints expanded to 16 bits by replication (e·257).
  DecodedBlock out;
  out.width = bw;
  out.height = bh;
  const bool small_block = bw * bh < 31;
  for (int y = 0; y < bh; ++y) {
    for (int x = 0; x < bw; ++x) {
      const int texel = y * bw + x;
      const auto t = static_cast<size_t>(texel);
      const int part =
          l.partitions > 1 ? astc_select_partition(l.seed, x, y, 0, l.partitions, small_block) : 0;
      if (info != nullptr) info->partition[t] = static_cast<uint8_t>(part);
      if ((hdr >> part) & 1U) {
        out.texels[t] = kErrorColor;
        continue;
      }
      const AstcEndpoints& e = ends[static_cast<size_t>(part)];
      for (int ch = 0; ch < 4; ++ch) {
        const int w = weights[ch == ccs ? 1 : 0][t];
        const int c0 = e.e0[static_cast<size_t>(ch)] * 257;
        const int c1 = e.e1[static_cast<size_t>(ch)] * 257;
        const int c = (c0 * (64 - w) + c1 * w + 32) >> 6;
        out.texels[t][ch] = output(c);
        if (info != nullptr) info->unorm16[t][static_cast<size_t>(ch)] = static_cast<uint16_t>(c);
      }
    }
  }
  return out;
}

OpCounts AstcDecoder::ops_per_item() const {
  const uint64_t n =
      static_cast<uint64_t>(cfg_.block_width) * static_cast<uint64_t>(cfg_.block_height);
  OpCounts o;
  // Integer sequence decoding: a table look-up per trit/quint group and per unquantised value
  // (64 weights, 18 colour integers).
  o.lut += 64 + 18 + (64 + 4) / 5 + (18 + 4) / 5;
  // Endpoint modes of 4 partitions: bit transfer, offsets, blue contraction and clamps.
  o.add += 32;  // 4 partitions × 8
  o.cmp += 32;
  o.mul += 12;  // 4 partitions × 3: base+scale modes
  // Partition hash: hash52 (10 shift/add/xor), then per texel four 2-term dot products and
  // a 3-compare maximum.
  o.add += 10 + n * 8;
  o.mul += n * 8;
  o.cmp += n * 3;
  // Infill on two planes, per texel: w11 (1 mul, 1 add), w10 and w01 (1 add each), w00
  // (3 adds) and the rounded 4-term sum (4 mul, 4 add).
  o.mul += n * 2 * 5;
  o.add += n * 2 * 10;
  o.lut += n * 2 * 4;  // the four grid weights read from the unpacked grid
  // Interpolation of 4 components: 2 mul, 3 add each; the output conversion (a scale).
  o.mul += n * 4 * 3;
  o.add += n * 4 * 3;
  return o;
}

OpCounts AstcDecoder::critical_path() const {
  // Unpack a weight (table), unquantise (table), infill (w11 mul, w00 add, product mul, a
  // 2-level sum), interpolate (mul, 2-level sum), convert (mul).
  OpCounts p;
  p.lut = 2;
  p.mul = 4;
  p.add = 5;
  return p;
}

TimingSpec AstcDecoder::timing(const TechTable& tech) const {
  return derive_timing(tech, ops_per_item(), critical_path(), cfg_.datapath);
}

}  // namespace texsim
