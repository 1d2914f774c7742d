#pragma once
// ASTC weights (Khronos Data Format Specification 1.3, "Weight Unquantization" and "Weight
// Infill"; docs/derivations/astc.md §5): a stored weight unquantised to 0..64, and the 2-D
// bilinear infill of a weight grid smaller than the block.
#include <span>

namespace texsim {

// A weight of range `index` (astc_weight_range) unquantised to 0..64.
int astc_unquantize_weight(int value, int index);

// The effective weight of every texel of a block_width × block_height block from a
// grid_width × grid_height grid of unquantised weights (row-major), out row-major. With a grid
// as large as the block every texel takes its own weight (the infill's result then).
void astc_infill_weights(std::span<const int> grid, int grid_width, int grid_height,
                         int block_width, int block_height, std::span<int> out);

}  // namespace texsim
