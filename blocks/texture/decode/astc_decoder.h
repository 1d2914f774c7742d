#pragma once
// AstcDecoder: one 128-bit ASTC block of a 2-D LDR texture (footprints 4×4 to 12×12) to its
// texels, bit-exact to the Khronos Data Format Specification 1.3 ASTC chapter in the LDR
// profile, linear (no sRGB). docs/derivations/astc.md gives the rules as implemented.
//  - Block mode, integer sequence encoding, colour endpoint modes 0, 1, 4, 5, 6, 8, 9, 10, 12,
//    13, weight infill, 2–4 partitions, dual planes, LDR void-extent blocks.
//  - The error colour, opaque magenta (1, 0, 1, 1), for every texel of a reserved or illegal
//    block (the spec's list, "Illegal Encodings") and of an HDR void-extent block, and for the
//    texels of a partition whose endpoint mode is HDR (2, 3, 7, 11, 14, 15): the LDR profile
//    treats HDR features as reserved.
//  - Output (Config::mode): the UNORM16 interpolation result C as C / 65535 (Unorm16, the
//    default); the spec's decode_float16 value (1.0 for C = 65535, else C / 65536 rounded
//    toward zero to FP16; Float16); or its decode_unorm8 value, the top 8 bits of C / 255
//    (Unorm8). Each rounded once to float.
// Item: one block. Arithmetic: integer (fixed point), no floating point before the output.
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/decode/astc_block_mode.h"
#include "blocks/texture/decode/decoded_block.h"

namespace texsim {

class ConfigReader;

// Why a block or texel decodes to the error colour.
enum class AstcError : uint8_t {
  None,
  ReservedBlockMode,        // reserved mode, > 64 weights, weight bits ∉ [24, 96], grid > block
  VoidExtentReservedBits,   // a void-extent block whose bits 11..10 are not 11
  VoidExtentCoordinates,    // a void extent whose low coordinate ≥ its high one (not all 1s)
  HdrVoidExtent,            // an HDR (FP16) void-extent block in the LDR profile
  DualPlaneFourPartitions,  // dual plane with 4 partitions
  TooManyColorValues,       // more than 18 colour endpoint integers
  TooFewColorBits,          // colour bits < ⌈13·C/5⌉: no colour range fits
  HdrEndpointMode,          // some partitions use an HDR endpoint mode (only their texels)
};

// What decode() found, for tests and statistics.
struct AstcBlockInfo {
  AstcBlockMode mode;
  AstcError error = AstcError::None;  // a block-level error, or HdrEndpointMode
  bool void_extent = false;
  int partitions = 1;
  int partition_seed = 0;
  std::array<int, 4> cem{};    // endpoint mode of each partition
  uint8_t hdr_partitions = 0;  // bit p: partition p uses an HDR endpoint mode
  int color_range = -1;        // astc_color_range index of the endpoint integers
  int ccs = -1;                // dual plane: the component that takes the second weight
  std::array<uint8_t, kMaxBlockTexels> partition{};                // each texel's partition
  std::array<std::array<uint16_t, 4>, kMaxBlockTexels> unorm16{};  // each texel's C (RGBA)
};

class AstcDecoder {
 public:
  enum class Mode { Unorm16, Float16, Unorm8 };
  struct Config {
    int block_width = 4;
    int block_height = 4;
    Mode mode = Mode::Unorm16;
    Datapath datapath = Datapath::Spatial;
    // Keys block_width, block_height (one of the 14 2-D footprints), mode ("unorm16" |
    // "float16" | "unorm8"), datapath.
    static Config from_toml(const ConfigReader& r);
  };
  static constexpr int kBlockBytes = 16;

  AstcDecoder();
  explicit AstcDecoder(const Config& c);  // throws std::invalid_argument on a bad footprint
  const Config& config() const { return cfg_; }

  DecodedBlock decode(std::span<const uint8_t, kBlockBytes> block) const {
    return decode(block, nullptr);
  }
  // The same, also filling `info` when it is not null.
  DecodedBlock decode(std::span<const uint8_t, kBlockBytes> block, AstcBlockInfo* info) const;

  // Whether width × height is one of the 14 2-D ASTC footprints.
  static bool valid_footprint(int width, int height);

  // Item: one block of the configured footprint, counted for the costliest legal encoding
  // (4 partitions, the largest grid with infill on two planes of the footprint's texels).
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "texture.astc_decoder"; }
  std::string arithmetic() const { return "integer (fixed point)"; }

 private:
  float output(int c) const;  // C (UNORM16) in the configured output mode
  DecodedBlock error_block(AstcError why, AstcBlockInfo* info) const;
  DecodedBlock void_extent(const AstcBits& bits, AstcBlockInfo* info) const;

  Config cfg_{};
};

}  // namespace texsim
