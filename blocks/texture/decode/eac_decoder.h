#pragma once
// EacDecoder: one 4x4 block of EAC R11 (unsigned or signed), Khronos Data Format Specification
// 1.3, "Format Unsigned R11 EAC" and "Format Signed R11 EAC" (docs/derivations/etc2-eac.md §4).
// The same datapath gives the 8-bit alpha of RGBA ETC2 (decode_alpha8), where a multiplier of
// 0 multiplies by 0 instead of by 1/8.
// Item: one block (16 texels decoded at once).
// Arithmetic: integers: 8-bit base codeword, 4-bit multiplier, 4-bit signed modifier, an
// 12-bit signed sum clamped to the 11-bit result (0..2047 or -1023..1023).
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/decode/decoded_block.h"

namespace texsim {

class ConfigReader;

class EacDecoder {
 public:
  static constexpr int kBlockBytes = 8;
  static constexpr int kBlockWidth = 4;
  static constexpr int kBlockHeight = 4;
  struct Config {
    bool snorm = false;  // signed R11: results -1023..1023 (-1.0..1.0)
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  using Block = std::span<const uint8_t, kBlockBytes>;
  // The 16 results of one block, row-major (texel (x, y) at y * 4 + x).
  using Values11 = std::array<int16_t, 16>;
  using Values8 = std::array<uint8_t, 16>;

  EacDecoder() = default;
  explicit EacDecoder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // The exact 11-bit results: 0..2047 (UNORM) or -1023..1023 (SNORM).
  Values11 decode_r11(Block block) const;
  // R = value / 2047 (UNORM) or value / 1023 (SNORM), rounded once to float; G = B = 0, A = 1.
  DecodedBlock decode(Block block) const;
  // The alpha block of RGBA ETC2: clamp255(base + modifier * multiplier), multiplier 0 giving 0.
  static Values8 decode_alpha8(Block block);
  // An 11-bit result as float: the nearest float to v / 2047 or v / 1023.
  static float to_float(int v, bool snorm) {
    return static_cast<float>(v) / (snorm ? 1023.0F : 2047.0F);
  }

  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return cfg_.snorm ? "texture.eac_r11_snorm" : "texture.eac_r11"; }
  std::string arithmetic() const {
    return "integer: 8-bit base, 4-bit multiplier x 4-bit modifier, 12-bit signed sum clamped to "
           "11 bits";
  }

 private:
  Config cfg_{};
};

}  // namespace texsim
