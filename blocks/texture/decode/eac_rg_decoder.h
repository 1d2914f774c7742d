#pragma once
// EacRgDecoder: one 4x4 block of EAC RG11 (unsigned or signed), Khronos Data Format
// Specification 1.3, "Format Unsigned RG11 EAC" and "Format Signed RG11 EAC": bytes 0-7 are
// the red R11 block, bytes 8-15 the green one, each decoded as EacDecoder does
// (docs/derivations/etc2-eac.md §4).
// Item: one block (16 texels, both channels, decoded at once).
// Arithmetic: two EacDecoder datapaths.
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/decode/decoded_block.h"
#include "blocks/texture/decode/eac_decoder.h"

namespace texsim {

class ConfigReader;

class EacRgDecoder {
 public:
  static constexpr int kBlockBytes = 16;
  static constexpr int kBlockWidth = 4;
  static constexpr int kBlockHeight = 4;
  using Config = EacDecoder::Config;  // snorm, datapath
  using Block = std::span<const uint8_t, kBlockBytes>;
  using Values11 = EacDecoder::Values11;

  EacRgDecoder() = default;
  explicit EacRgDecoder(const Config& c) : channel_(c) {}
  const Config& config() const { return channel_.config(); }

  // The exact 11-bit results of red and green, row-major.
  std::array<Values11, 2> decode_rg11(Block block) const;
  // R and G as EacDecoder gives them; B = 0, A = 1.
  DecodedBlock decode(Block block) const;

  OpCounts ops_per_item() const { return channel_.ops_per_item() * 2; }
  TimingSpec timing(const TechTable& t) const;
  std::string name() const {
    return config().snorm ? "texture.eac_rg11_snorm" : "texture.eac_rg11";
  }
  std::string arithmetic() const { return "two channels of " + channel_.arithmetic(); }

 private:
  EacDecoder channel_{};
};

}  // namespace texsim
