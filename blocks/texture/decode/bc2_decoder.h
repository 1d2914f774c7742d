#pragma once
// Bc2Decoder: one BC2 block (16 bytes, 4x4 texels) to its texels, as the Khronos Data Format
// Specification 1.3 §"S3TC" decodes it (docs/derivations/bc-formats.md §BC2): 64 bits of
// explicit 4-bit alpha (texel t in bits 4t+3..4t, alpha = a / 15), then a BC1 colour block
// always read with four colours.
// Item: one decoded 4x4 block.
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

class Bc2Decoder {
 public:
  static constexpr int kBlockBytes = 16;
  static constexpr int kBlockSize = 4;  // texels per side
  struct Config {
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };

  Bc2Decoder() = default;
  explicit Bc2Decoder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  DecodedBlock decode(std::span<const uint8_t, kBlockBytes> block) const;

  OpCounts ops_per_item() const;
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "texture.decode.bc2"; }
  std::string arithmetic() const {
    return "integer: 4-bit alpha times 1/15; colour as BC1 (5/6-bit endpoints, 8-bit sums) to "
           "float32";
  }

 private:
  Config cfg_{};
};

}  // namespace texsim
