#pragma once
// Bc5Decoder: one BC5 block (16 bytes, 4x4 texels) to its texels, as the Khronos Data Format
// Specification 1.3 §"RGTC" decodes it (docs/derivations/bc-formats.md §BC5): two BC4
// channel blocks (Bc4Decoder::decode_channel), red then green, UNORM or SNORM; result
// (R, G, 0, 1).
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

class Bc5Decoder {
 public:
  static constexpr int kBlockBytes = 16;
  static constexpr int kBlockSize = 4;  // texels per side
  struct Config {
    bool snorm = false;  // BC5 signed: two's complement endpoints
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };

  Bc5Decoder() = default;
  explicit Bc5Decoder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  DecodedBlock decode(std::span<const uint8_t, kBlockBytes> block) const;

  OpCounts ops_per_item() const;
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "texture.decode.bc5"; }
  std::string arithmetic() const {
    return "integer: two BC4 channels (8-bit endpoints, 11-bit sums), constant reciprocal "
           "multiplies to float32";
  }

 private:
  Config cfg_{};
};

}  // namespace texsim
