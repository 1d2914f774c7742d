#pragma once
// A simple ETC2 / EAC encoder for tests: it turns blocks of real images into valid blocks of
// a chosen mode (individual, differential, T, H, planar; EAC with or without multiplier 0), so
// that comparisons against another decoder run every mode on image content. The mode is the
// caller's choice, not the best one; colours are block means and extremes, indices the nearest
// candidate. Its reconstruction rules are written here, apart from the decoders under test.
// Not a hardware block.
#include <array>
#include <cstdint>

namespace texsim {

// 16 RGBA8 pixels of a 4x4 block, row-major.
using EtcTestPixels = std::array<std::array<uint8_t, 4>, 16>;
enum class EtcTestMode { Individual, Differential, T, H, Planar };

// An RGB ETC2 block of `mode`. With `punch_through` (RGB8A1; no individual mode: it becomes
// differential), pixels of alpha < 128 get the transparent index and the block's opaque bit is
// cleared when it has any (planar blocks are always written opaque).
std::array<uint8_t, 8> etc_test_encode_rgb(const EtcTestPixels& px, EtcTestMode mode,
                                           bool punch_through);

// An EAC block of 16 values (row-major): `kind` Alpha8 takes 0..255; R11 takes 0..255 (as
// v / 255 of the range); SignedR11 takes -127..127 (v / 127). `zero_multiplier` writes
// multiplier 0 (R11 kinds: modifiers unscaled; Alpha8: every texel the base codeword).
enum class EacTestKind { Alpha8, R11, SignedR11 };
std::array<uint8_t, 8> etc_test_encode_eac(const std::array<int, 16>& values, EacTestKind kind,
                                           bool zero_multiplier);

}  // namespace texsim
