#pragma once
// Etc2RgbDecoder: one 4x4 block of RGB ETC2 (ETC1 blocks included: its individual and
// differential modes) or, with punch_through, of RGB ETC2 with punchthrough alpha (RGB8A1),
// Khronos Data Format Specification 1.3, "Format RGB ETC2" and "Format RGB ETC2 with
// punchthrough alpha" (docs/derivations/etc2-eac.md §2-3). Five modes: individual,
// differential, T, H and planar; with punch_through bit 33 is the opaque bit (no individual
// mode) and, when it is 0, index 2 is transparent black and the differential mode's small
// modifiers are 0 (planar blocks stay opaque).
// Item: one block (16 texels decoded at once, all modes' datapaths side by side).
// Arithmetic: integers: 4/5/6/7-bit colour fields widened to 8 bits by bit replication,
// 9-bit signed sums clamped to 0..255; planar: 11-bit signed sums, rounded by (s + 2) >> 2.
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

class Etc2RgbDecoder {
 public:
  static constexpr int kBlockBytes = 8;
  static constexpr int kBlockWidth = 4;
  static constexpr int kBlockHeight = 4;
  struct Config {
    bool punch_through = false;  // RGB8A1: bit 33 is the opaque bit
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  using Block = std::span<const uint8_t, kBlockBytes>;
  // The 16 RGBA8 results of one block, row-major (texel (x, y) at y * 4 + x).
  using Texels8 = std::array<std::array<uint8_t, 4>, 16>;
  enum class Mode { Individual, Differential, T, H, Planar };

  Etc2RgbDecoder() = default;
  explicit Etc2RgbDecoder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // The spec's 8-bit results (alpha 255 unless punch-through makes a texel transparent).
  Texels8 decode_rgba8(Block block) const;
  // Each channel / 255, rounded once to float.
  DecodedBlock decode(Block block) const;
  // The mode the block's bits select.
  Mode mode(Block block) const;

  OpCounts ops_per_item() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const {
    return cfg_.punch_through ? "texture.etc2_rgb8a1" : "texture.etc2_rgb8";
  }
  std::string arithmetic() const {
    return "integer: 4-7-bit colour fields replicated to 8 bits, 9-bit signed sums clamped to "
           "0..255, planar 11-bit sums";
  }

 private:
  Config cfg_{};
};

}  // namespace texsim
