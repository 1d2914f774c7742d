#pragma once
// ETC2 / EAC blocks from 4x4 texels: the block level of texsim's ETC encoder (etc_encoder.h
// encodes whole images with it). Two uses:
//  - etc_encode_rgb / eac_encode try every mode (individual, differential with both flips, T,
//    H, planar; EAC tables, multipliers and base values) and keep the block of least squared
//    error;
//  - etc_encode_rgb_mode / eac_encode_mode write a block of a CHOSEN mode, not the best one,
//    so that comparisons against another decoder run every mode on image content.
// Errors are measured under the reconstruction written here (etc_reconstruct_rgb,
// eac_reconstruct): the Khronos Data Format Specification's rules restated apart from the
// decoders in blocks/texture/decode/, which the encoder's blocks are then checked against.
// Not a hardware block.
#include <array>
#include <cstdint>

namespace texsim {

// 16 RGBA8 pixels of a 4x4 block, row-major.
using EtcPixels = std::array<std::array<uint8_t, 4>, 16>;
// One 64-bit ETC2 or EAC block, most significant byte first (as stored).
using EtcBlock = std::array<uint8_t, 8>;
enum class EtcMode { Individual, Differential, T, H, Planar };
// Fast: each mode from the block's mean colours (and extremes) only; Normal: also the
// quantised base colours either side of the means, two-cluster T and H colours, a least-squares
// plane with its neighbours and, for EAC, neighbouring multipliers and base values.
enum class EtcEffort { Fast, Normal };

// The RGB ETC2 block of least squared error. With `punch_through` (RGB8A1), pixels of
// alpha < 128 must decode transparent and the others opaque (an alpha mismatch costs 255² per
// channel); there is no individual mode.
EtcBlock etc_encode_rgb(const EtcPixels& px, bool punch_through, EtcEffort effort);
// An RGB ETC2 block of `mode`. With `punch_through` (no individual mode: it becomes
// differential), pixels of alpha < 128 get the transparent index and the block's opaque bit is
// cleared when it has any (planar blocks are always written opaque).
EtcBlock etc_encode_rgb_mode(const EtcPixels& px, EtcMode mode, bool punch_through);
// The 16 RGBA8 pixels (row-major) the block decodes to; transparent ones are (0, 0, 0, 0).
EtcPixels etc_reconstruct_rgb(const EtcBlock& b, bool punch_through);
// The mode the block's bits select.
EtcMode etc_block_mode(const EtcBlock& b, bool punch_through);

// An EAC block of 16 values (row-major): Alpha8 takes 0..255; R11 takes 0..255 (as v / 255 of
// the range); SignedR11 takes -127..127 (v / 127).
enum class EacKind { Alpha8, R11, SignedR11 };
// The block of least squared error on the decoded scale.
EtcBlock eac_encode(const std::array<int, 16>& values, EacKind kind, EtcEffort effort);
// A block with the multiplier from the values' range, or `zero_multiplier` (R11 kinds:
// modifiers unscaled; Alpha8: every texel the base codeword).
EtcBlock eac_encode_mode(const std::array<int, 16>& values, EacKind kind, bool zero_multiplier);
// The decoded values, row-major: 0..255 (Alpha8), 0..2047 (R11), -1023..1023 (SignedR11).
std::array<int, 16> eac_reconstruct(const EtcBlock& b, EacKind kind);
// The values' targets on that decoded scale.
std::array<int, 16> eac_targets(const std::array<int, 16>& values, EacKind kind);

}  // namespace texsim
