#pragma once
// Bc1Decoder: one BC1 block (8 bytes, 4x4 texels) to its texels, as the Khronos Data Format
// Specification 1.3 §"S3TC" decodes it (docs/derivations/bc-formats.md §BC1):
//  - colour0, colour1: RGB565 endpoints, each channel k / (2^n - 1) (n = 5, 6, 5);
//  - colour0 > colour1 (as 16-bit integers): four colours, the two interpolated ones the exact
//    thirds (2·c0 + c1) / 3 and (c0 + 2·c1) / 3;
//  - colour0 <= colour1: three colours, the exact half (c0 + c1) / 2, and code 3 = black, with
//    alpha 0 in "BC1 with alpha" (Config::alpha) and alpha 1 in "BC1 with no alpha".
// Every value is its exact rational (an integer over 31, 63, 93, 189, 62 or 126) rounded once
// to float. The colour half of BC2 and BC3 is the same block always read with four colours
// (decode_colour with three_colour_mode = false).
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

class Bc1Decoder {
 public:
  static constexpr int kBlockBytes = 8;
  static constexpr int kBlockSize = 4;  // texels per side
  struct Config {
    bool alpha = false;  // "BC1 with alpha": code 3 of a three-colour block is transparent
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };

  Bc1Decoder() = default;
  explicit Bc1Decoder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  DecodedBlock decode(std::span<const uint8_t, kBlockBytes> block) const;

  // The colour block of BC1/BC2/BC3 into out.texels' RGB (and A: 1, or 0 for a transparent
  // texel when alpha_punch_through). three_colour_mode: colour0 <= colour1 selects three
  // colours (BC1); false: always four (BC2, BC3).
  static void decode_colour(std::span<const uint8_t, kBlockBytes> block, bool three_colour_mode,
                            bool alpha_punch_through, DecodedBlock& out);
  // Operations of decode_colour for one block and its longest dependent chain.
  static OpCounts colour_ops(bool three_colour_mode, bool alpha_out);
  static OpCounts colour_path();

  OpCounts ops_per_item() const { return colour_ops(true, cfg_.alpha); }
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "texture.decode.bc1"; }
  std::string arithmetic() const {
    return "integer: 5/6-bit endpoints, 8-bit palette sums (2c0+c1 <= 189), one constant "
           "reciprocal multiply per palette channel to float32";
  }

 private:
  Config cfg_{};
};

}  // namespace texsim
