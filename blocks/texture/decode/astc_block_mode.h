#pragma once
// ASTC 2-D block mode (bits 10..0 of a block; Khronos Data Format Specification 1.3, "Block
// mode"; docs/derivations/astc.md §2): the weight grid's size, the weights' range and whether
// there are two weight planes, with every legality rule of the block mode itself.
#include <cstdint>

#include "blocks/texture/decode/astc_integer_sequence.h"

namespace texsim {

// The twelve weight ranges, indexed by ρ − 2 + 6·P: 0..1, 0..2, 0..3, 0..4, 0..5, 0..7,
// 0..9, 0..11, 0..15, 0..19, 0..23, 0..31.
AstcRange astc_weight_range(int index);

struct AstcBlockMode {
  enum class Kind {
    Normal,      // a weight grid follows
    VoidExtent,  // bits 8..0 = 111111100: a constant-colour block
    Reserved,    // a reserved or illegal mode: the error colour
  };
  Kind kind = Kind::Reserved;
  int grid_width = 0, grid_height = 0;
  bool dual_plane = false;
  int weight_range = 0;  // index into astc_weight_range()
  int weight_count = 0;  // grid_width · grid_height · planes
  int weight_bits = 0;   // bits of the weights' integer sequence
};

// Decodes the 11-bit block mode for a block of block_width × block_height texels. Reserved:
// the modes the spec lists as reserved, more than 64 weights, fewer than 24 or more than 96
// weight bits, or a grid larger than the block in either axis.
AstcBlockMode astc_decode_block_mode(uint32_t mode, int block_width, int block_height);

}  // namespace texsim
