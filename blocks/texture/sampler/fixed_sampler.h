#pragma once
// FixedSampler: the bilinear/trilinear sampler (LOD → texel addresses → texel reads → blend) in
// fixed point only, the functional core the RTL sampler rtl_model/rtl/texsim_sampler.v
// matches bit for bit (docs/rtl/blocks.md). The texture unit's own path (LodUnit,
// TexelAddressGen, TexelBlend) is float32; this is its integer form, built from the same
// rules: λ = ½·log2 ρ² (log2 by a 257-entry table with linear interpolation), bias, the
// [min_lod, max_lod] and pyramid clamps, the level and fraction at `mip_bits`; texel
// coordinates at `sub_bits`, rounded half to even as TexelAddressGen's converter; Vulkan's
// wrap/clamp/mirror/mirror-clamp on any size; the linear, 4x4-tiled and Morton addresses of
// Texture::texel_index; BilinearLerp per level and one rounded lerp between the levels.
// Not covered: anisotropic LOD, border addressing, explicit LOD/gather/reduction operations,
// layered and compressed textures, texel formats other than RGBA8.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

class FixedSampler {
 public:
  static constexpr int kCoordFrac = 32;  // u, v and derivatives: s15.32 (48 bits)
  static constexpr int kCoordBits = 48;
  static constexpr int kDerivFrac = 16;   // derivatives in texels of level 0: s15.16
  static constexpr int kLodFrac = 20;     // log2 ρ², λ, bias and LOD limits: s11.20 (32 bits)
  static constexpr int kLog2Index = 8;    // table index: the mantissa's top 8 bits
  static constexpr int kLog2Interp = 12;  // interpolation weight: its next 12 bits
  static constexpr int kMaxLevels = 16;
  static constexpr int kQuadWords = 8;  // texel reads per fragment: two quads
  // log2 of ρ² = 0 (−∞): below every λ, so min_lod (or level 0) wins the clamp.
  static constexpr int64_t kLog2Zero = -(int64_t{64} << kLodFrac);

  struct Config {
    bool trilinear = true;
    AddressMode address_u = AddressMode::Wrap, address_v = AddressMode::Wrap;
    int sub_bits = 8, mip_bits = 8;
    int offset_u = 0, offset_v = 0;
    int32_t bias = 0;                          // s11.20 raw
    int32_t min_lod = 0, max_lod = INT32_MAX;  // s11.20 raws
  };
  // The level-0 size, level count, layout and each level's first texel word (Level::offset
  // in 4-byte words) of one texture.
  struct TextureDesc {
    int w0 = 1, h0 = 1, levels = 1;
    TexelLayout layout = TexelLayout::Linear;
    std::array<uint32_t, kMaxLevels> base{};
  };
  // One fragment, s15.32 raws.
  struct Input {
    int64_t u = 0, v = 0, dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;
  };
  struct Result {
    int32_t level_hi = 0, level_lo = 0;
    uint32_t delta = 0;                       // weight of level_lo, u0.mip_bits
    std::array<uint32_t, kQuadWords> addr{};  // (x0,y0) (x1,y0) (x0,y1) (x1,y1), hi then lo
    uint32_t rgba = 0;                        // RGBA8, R in the low byte
  };
  // The memory the RTL reads, by word address (0 past its end).
  using Memory = std::span<const uint32_t>;

  explicit FixedSampler(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Whether a material's sampler is one this covers; `why` says what is not.
  static bool covers(const TexelAddressGen::Config& a, const LodUnit::Config& l, std::string* why);
  // Whether the texture is one this samples (2D, RGBA8 unorm, uncompressed, at most kMaxLevels
  // levels); `why` says what is not.
  static bool covers_texture(const Texture& tex, std::string* why);
  // The configuration of a covered material (float LOD values rounded half to even).
  static Config config_of(const TexelAddressGen::Config& a, const LodUnit::Config& l);
  static TextureDesc describe(const Texture& tex);
  // The texture's texels as the memory image the RTL reads: word base[L] + texel_index.
  static std::vector<uint32_t> memory_image(const Texture& tex);
  // The host's converter: doubles → float32 (as the texture unit takes them) → s15.32,
  // rounded half to even, saturated; non-finite values become 0.
  static Input to_input(const Fragment& f);
  static int64_t to_coord(double x);
  static int32_t to_lod(float x);

  // λ after bias and the [min_lod, max_lod] clamp (s11.20).
  int32_t lambda(const Input& in, const TextureDesc& t) const;
  Result sample(const Input& in, const TextureDesc& t, const Memory& mem) const;
  // The operands of one level's bilinear lerp (BilinearLerp::lerp): the four texels as read,
  // (x0,y0) (x1,y0) (x0,y1) (x1,y1), and the u0.sub_bits weights of the +1 texels.
  struct LerpInput {
    std::array<uint64_t, 4> quad{};
    uint32_t fx = 0, fy = 0;
  };
  // As sample(), and the finer and coarser level's lerp operands into `lerps` (the coarser one
  // equal to the finer when bilinear).
  Result sample(const Input& in, const TextureDesc& t, const Memory& mem,
                std::array<LerpInput, 2>* lerps) const;

  // The log2 table: round(log2(1 + i/256)·2^20), i = 0..256.
  static const std::array<uint32_t, 257>& log2_table();
  // Round half to even of x / 2^k (k ≥ 1), floor-based so it holds for negative x.
  static int64_t round_half_even(int64_t x, int k) {
    const int64_t t = x >> k, rem = x & ((int64_t{1} << k) - 1), half = int64_t{1} << (k - 1);
    return t + ((rem > half || (rem == half && (t & 1) != 0)) ? 1 : 0);
  }

  // Latency: LodUnit (isotropic) + TexelAddressGen + one memory read cycle + BilinearLerp +
  // the level lerp (add, mul, add), one fragment per cycle.
  static uint32_t lod_latency(const TechTable& tech);
  // The address generator's latency in its trilinear configuration: the RTL is one datapath
  // for both filters (bilinear reads its one level twice and passes the finer colour on).
  static uint32_t address_latency(const TechTable& tech);
  static uint32_t lerp_latency(const TechTable& tech);
  static uint32_t mip_latency(const TechTable& tech);
  static constexpr uint32_t kMemLatency = 1;
  static uint32_t latency(const TechTable& tech);
  // Operations per fragment: LodUnit's, TexelAddressGen's (level selection and one probe),
  // BilinearLerp's per level and the level lerp's 2 add + 1 mul per channel (trilinear).
  OpCounts ops_per_item(const TexelAddressGen::Config& a, const LodUnit::Config& l) const;

 private:
  Config cfg_;
};

}  // namespace texsim
