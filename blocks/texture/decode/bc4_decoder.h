#pragma once
// Bc4Decoder: one BC4 block (8 bytes, 4x4 texels of one channel) to its texels, as the Khronos
// Data Format Specification 1.3 §"RGTC" decodes it (docs/derivations/bc-formats.md §BC4):
//  - red0, red1: 8-bit endpoints, UNORM k / 255; SNORM k / 127 with -128 read as -1;
//  - red0 > red1 (compared as the stored integers, signed for SNORM): six exact sevenths
//    between the endpoints; otherwise four exact fifths and the constants min and max
//    (0 and 1 UNORM, -1 and 1 SNORM);
//  - result (R, 0, 0, 1).
// The channel itself (decode_channel) is also BC3's alpha and each of BC5's two channels.
// SNORM red0 = -127, red1 = -128 (which the DFS leaves undefined) compares the stored
// integers: -127 > -128 selects the sevenths, all of whose values are then -1.
// Item: one decoded 4x4 block.
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

class Bc4Decoder {
 public:
  static constexpr int kBlockBytes = 8;
  static constexpr int kBlockSize = 4;  // texels per side
  struct Config {
    bool snorm = false;  // BC4 signed: two's complement endpoints
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };

  Bc4Decoder() = default;
  explicit Bc4Decoder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  DecodedBlock decode(std::span<const uint8_t, kBlockBytes> block) const;

  // The 16 values (row-major) of one BC4 channel block.
  static std::array<float, 16> decode_channel(std::span<const uint8_t, kBlockBytes> block,
                                              bool snorm);
  // Operations of decode_channel for one block and its longest dependent chain.
  static OpCounts channel_ops(bool snorm);
  static OpCounts channel_path(bool snorm);

  OpCounts ops_per_item() const { return channel_ops(cfg_.snorm); }
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "texture.decode.bc4"; }
  std::string arithmetic() const {
    return "integer: 8-bit endpoints, 11-bit weighted sums (6a0+a1 <= 1785), one constant "
           "reciprocal multiply per palette entry to float32";
  }

 private:
  Config cfg_{};
};

}  // namespace texsim
