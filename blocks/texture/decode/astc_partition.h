#pragma once
// ASTC partition pattern generation (Khronos Data Format Specification 1.3, "Partition Pattern
// Generation"; docs/derivations/astc.md §6): the partition of a texel from the 10-bit pattern
// index (the seed) through the hash52 function. Hardware evaluates it per texel; no table.
#include <cstdint>

namespace texsim {

// The spec's 32-bit seed hash.
uint32_t astc_hash52(uint32_t p);

// The partition (0..partition_count − 1) of texel (x, y, z) for pattern `seed` (0..1023);
// small_block: the block has fewer than 31 texels (coordinates are doubled).
int astc_select_partition(int seed, int x, int y, int z, int partition_count, bool small_block);

}  // namespace texsim
