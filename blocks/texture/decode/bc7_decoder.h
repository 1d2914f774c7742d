#pragma once
// Bc7Decoder: one BC7 block (16 bytes, 4x4 texels) to its texels, as the Khronos Data Format
// Specification 1.3 §"BPTC" decodes it (docs/derivations/bc-formats.md §BC7): the mode (the
// position of the lowest set bit of byte 0), the partition of 1, 2 or 3 subsets, rotation and
// index selection, the endpoints with their per-endpoint or shared p-bits expanded to 8 bits
// by bit replication, primary and secondary indices with one bit less at each subset's anchor
// texel, the 6-bit weights and ((64 - w)·E0 + w·E1 + 32) >> 6; each 8-bit result is k / 255.
// A reserved block (byte 0 = 0, "mode 8") decodes to 0 in all four channels of every texel, as
// DFS 1.3 requires.
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

class Bc7Decoder {
 public:
  static constexpr int kBlockBytes = 16;
  static constexpr int kBlockSize = 4;  // texels per side
  static constexpr int kReservedMode = 8;
  struct Config {
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };

  Bc7Decoder() = default;
  explicit Bc7Decoder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  DecodedBlock decode(std::span<const uint8_t, kBlockBytes> block) const;
  // The block's mode, 0..7, or kReservedMode.
  static int mode_of(std::span<const uint8_t, kBlockBytes> block);

  // The hardware decodes every mode in one datapath: the worst mode's operations.
  OpCounts ops_per_item() const;
  static OpCounts critical_path();
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "texture.decode.bc7"; }
  std::string arithmetic() const {
    return "integer: 4..8-bit endpoints replicated to 8 bits, 6-bit weights, 14-bit "
           "interpolation sums >> 6; one constant 1/255 multiply per channel to float32";
  }

 private:
  Config cfg_{};
};

}  // namespace texsim
