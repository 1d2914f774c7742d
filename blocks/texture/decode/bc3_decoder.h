#pragma once
// Bc3Decoder: one BC3 block (16 bytes, 4x4 texels) to its texels, as the Khronos Data Format
// Specification 1.3 §"S3TC" decodes it (docs/derivations/bc-formats.md §BC3): 64 bits of
// alpha coded as a UNORM BC4 channel (Bc4Decoder::decode_channel), then a BC1 colour block
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

class Bc3Decoder {
 public:
  static constexpr int kBlockBytes = 16;
  static constexpr int kBlockSize = 4;  // texels per side
  struct Config {
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };

  Bc3Decoder() = default;
  explicit Bc3Decoder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  DecodedBlock decode(std::span<const uint8_t, kBlockBytes> block) const;

  OpCounts ops_per_item() const;
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "texture.decode.bc3"; }
  std::string arithmetic() const {
    return "integer: alpha as BC4 UNORM (8-bit endpoints, 11-bit sums), colour as BC1 "
           "(5/6-bit endpoints, 8-bit sums), constant reciprocal multiplies to float32";
  }

 private:
  Config cfg_{};
};

}  // namespace texsim
