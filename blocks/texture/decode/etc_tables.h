#pragma once
// The tables of the ETC2 and EAC chapters of the Khronos Data Format Specification 1.3, shared by
// the decoders (etc2_rgb_decoder, eac_decoder) and texsim's ETC2 / EAC encoder
// (pipeline/image_io/etc_block_encoder.*).
#include <array>

namespace texsim::etc_tables {

// The intensity modifier sets of the individual and differential modes: the small and large
// value (a, b) of each table codeword.
inline constexpr std::array<std::array<int, 2>, 8> kModifiers = {
    {{2, 8}, {5, 17}, {9, 29}, {13, 42}, {18, 60}, {24, 80}, {33, 106}, {47, 183}}};
// The distance table of the T and H modes.
inline constexpr std::array<int, 8> kDistances = {3, 6, 11, 16, 23, 32, 41, 64};
// The 16 modifier sets of EAC (Table "Intensity modifier sets for RGBA ETC2 alpha component"),
// shared by the alpha of RGBA ETC2 and R11/RG11 EAC.
inline constexpr std::array<std::array<int, 8>, 16> kEacModifiers = {{
    {-3, -6, -9, -15, 2, 5, 8, 14},
    {-3, -7, -10, -13, 2, 6, 9, 12},
    {-2, -5, -8, -13, 1, 4, 7, 12},
    {-2, -4, -6, -13, 1, 3, 5, 12},
    {-3, -6, -8, -12, 2, 5, 7, 11},
    {-3, -7, -9, -11, 2, 6, 8, 10},
    {-4, -7, -8, -11, 3, 6, 7, 10},
    {-3, -5, -8, -11, 2, 4, 7, 10},
    {-2, -6, -8, -10, 1, 5, 7, 9},
    {-2, -5, -8, -10, 1, 4, 7, 9},
    {-2, -4, -8, -10, 1, 3, 7, 9},
    {-2, -5, -7, -10, 1, 4, 6, 9},
    {-3, -4, -7, -10, 2, 3, 6, 9},
    {-1, -2, -3, -10, 0, 1, 2, 9},
    {-4, -6, -8, -9, 3, 5, 7, 8},
    {-3, -5, -7, -9, 2, 4, 6, 8},
}};

}  // namespace texsim::etc_tables
