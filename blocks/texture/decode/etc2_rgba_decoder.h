#pragma once
// Etc2RgbaDecoder: one 4x4 block of RGBA ETC2 (RGBA8 ETC2 EAC), Khronos Data Format
// Specification 1.3, "Format RGBA ETC2": bytes 0-7 are the EAC alpha block (8-bit, a multiplier
// of 0 gives 0), bytes 8-15 an RGB ETC2 block (docs/derivations/etc2-eac.md §5).
// Item: one block (16 texels decoded at once).
// Arithmetic: that of Etc2RgbDecoder beside the 8-bit EAC alpha datapath.
#include <cstdint>
#include <span>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/decode/decoded_block.h"
#include "blocks/texture/decode/etc2_rgb_decoder.h"

namespace texsim {

class ConfigReader;

class Etc2RgbaDecoder {
 public:
  static constexpr int kBlockBytes = 16;
  static constexpr int kBlockWidth = 4;
  static constexpr int kBlockHeight = 4;
  struct Config {
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  using Block = std::span<const uint8_t, kBlockBytes>;
  using Texels8 = Etc2RgbDecoder::Texels8;

  Etc2RgbaDecoder() = default;
  explicit Etc2RgbaDecoder(const Config& c) : cfg_(c), rgb_({false, c.datapath}) {}
  const Config& config() const { return cfg_; }

  // The spec's 8-bit results, row-major.
  Texels8 decode_rgba8(Block block) const;
  // Each channel / 255, rounded once to float.
  DecodedBlock decode(Block block) const;

  OpCounts ops_per_item() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "texture.etc2_rgba8"; }
  std::string arithmetic() const {
    return rgb_.arithmetic() + "; alpha: 8-bit base + 4-bit multiplier x modifier, clamped";
  }

 private:
  Config cfg_{};
  Etc2RgbDecoder rgb_{};
};

}  // namespace texsim
