#pragma once
// ASTC colour endpoints (Khronos Data Format Specification 1.3, "Endpoint Unquantization" and
// "LDR Endpoint Decoding"; docs/derivations/astc.md §4): the range the endpoint integers use,
// their unquantisation to 0..255 and the ten LDR colour endpoint modes. The six HDR modes
// (2, 3, 7, 11, 14, 15) are not decoded: in the LDR profile they give the error colour.
#include <array>
#include <span>

#include "blocks/texture/decode/astc_integer_sequence.h"

namespace texsim {

// The colour ranges from 0..5 up to 0..255, smallest first (index 0..16).
inline constexpr int kAstcColorRanges = 17;
AstcRange astc_color_range(int index);

// The largest colour range whose sequence of `value_count` integers fits in `available_bits`,
// or -1 when not even 0..5 fits (an illegal block).
int astc_select_color_range(int value_count, int available_bits);

// One endpoint integer of range `index` unquantised to 0..255 (bit replication, or the spec's
// A/B/C/D procedure for trits and quints).
int astc_unquantize_color(int value, int index);

// Whether a colour endpoint mode is one of the LDR modes 0, 1, 4, 5, 6, 8, 9, 10, 12, 13.
bool astc_is_ldr_endpoint_mode(int cem);

// The two RGBA endpoints (each component 0..255) of LDR endpoint mode `cem` from its
// 2·(cem/4 + 1) unquantised values. Precondition: astc_is_ldr_endpoint_mode(cem).
struct AstcEndpoints {
  std::array<int, 4> e0{}, e1{};
};
AstcEndpoints astc_decode_ldr_endpoints(int cem, std::span<const int> v);

}  // namespace texsim
