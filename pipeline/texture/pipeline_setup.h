#pragma once
// The scene's [pipeline] table: FIFO depths, texel layout, the blend block, the number of
// texture units and the memory hierarchy behind them (docs/scenes.md#pipeline).
#include <toml++/toml.h>

#include <bit>
#include <cstdint>
#include <string>

#include "blocks/texture/memory/banked_dram.h"
#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/l2_cache.h"
#include "blocks/texture/memory/texture_cache.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/srgb_decoder.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "pipeline/texture/quad_assembler.h"

namespace texsim {

struct PipelineSetup {
  static constexpr uint32_t kMaxUnits = 64;
  uint32_t fifo_depth = 4;
  TexelLayout layout = TexelLayout::Tiled4x4;
  // Texture units, each with its own clocked pipeline and L1 (`cache`); screen tiles of
  // unit_tile × unit_tile pixels go to the units interleaved (unit_of_pixel).
  uint32_t units = 1;
  uint32_t unit_tile = 16;
  // Quads: derivatives from the fragment ("fragment") or from quad differences (Vulkan's
  // coarse or fine rules; with coarse ones a quad's four lanes share one LOD), and whether a
  // quad's lanes share their tag look-ups (one per distinct line of the quad).
  QuadDerivatives derivatives = QuadDerivatives::Own;
  bool quad_merge = false;
  TextureCache::Config cache;  // each unit's L1
  // A shared L2 between the L1s and DRAM ([pipeline.l2] present).
  bool has_l2 = false;
  L2Cache::Config l2;
  // DRAM: the flat channel (latency + bandwidth; `dram`) or channels, banks and row buffers
  // (`banked`), chosen by [pipeline.dram] model.
  enum class DramKind { Flat, Banked };
  DramKind dram_kind = DramKind::Flat;
  DramModel::Config dram;
  BankedDram::Config banked;
  TexelBlend::Config blend;
  // Where block-compressed textures are decoded (docs/timing-model.md#decompression):
  // before_l1: as blocks leave DRAM, every cache holds decoded texels; after_l1: between the
  // L1 and the filter, every cache holds blocks; after_l2: between the L2 and the L1s.
  enum class Decompress { BeforeL1, AfterL1, AfterL2 };
  Decompress decompress = Decompress::AfterL1;
  // Where srgb8_a8 textures are decoded to linear (docs/formats.md#srgb-decode-placement):
  // each texel before the filter (the specification's rule), or the filtered colour after it.
  SrgbDecode srgb_decode = SrgbDecode::BeforeFilter;
  // Reads [pipeline]; errors name file:line:col and the rule broken.
  static PipelineSetup from_toml(const toml::table& t, const std::string& source);

  // The unit that textures pixel (x, y): tiles in a row go to units 0, 1, .., N − 1, and each
  // tile row starts one unit further on, so that neither rows nor columns of tiles share a
  // unit with their neighbours (for N > 1).
  int unit_of_pixel(uint32_t x, uint32_t y) const {
    const int shift = std::countr_zero(unit_tile);  // unit_tile is a power of two
    const uint32_t t = (x >> shift) + (y >> shift);
    return static_cast<int>((units & (units - 1)) == 0 ? t & (units - 1) : t % units);
  }
};

}  // namespace texsim
