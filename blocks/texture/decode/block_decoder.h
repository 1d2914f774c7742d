#pragma once
// One entry point over the texel decoder blocks of every compressed format (BC, ETC2/EAC,
// ASTC; docs/formats.md#block-compressed-formats): a block decoded, and the decoder's cost.
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/decode/compressed_format.h"
#include "blocks/texture/decode/decoded_block.h"

namespace texsim {

// The texels of one block of `f` (format_info(f).block_bytes bytes at `block`).
DecodedBlock decode_block(CompressedFormat f, const uint8_t* block);
// The decoder block of `f`: its operations per block, timing and area, report name
// ("decode.<format>") and arithmetic.
OpCounts decoder_ops(CompressedFormat f);
TimingSpec decoder_timing(CompressedFormat f, const TechTable& tech);
std::string decoder_name(CompressedFormat f);
std::string decoder_arithmetic(CompressedFormat f);

}  // namespace texsim
