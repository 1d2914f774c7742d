#pragma once
// What sits behind a texture unit's L1: a memory level that answers a request for one cache
// line at a cycle with the cycle its data has arrived. The flat DRAM (DramModel), the banked
// DRAM (BankedDram) and the shared L2 (L2Cache, which has a LineMemory of its own behind it)
// are levels; MemorySystem (pipeline/texture/memory_system.h) composes them.
// docs/timing-model.md#memory-hierarchy describes the timing of each level.
#include <cstdint>

namespace texsim {

class LineMemory {
 public:
  LineMemory() = default;
  LineMemory(const LineMemory&) = default;
  LineMemory& operator=(const LineMemory&) = default;
  LineMemory(LineMemory&&) = default;
  LineMemory& operator=(LineMemory&&) = default;
  virtual ~LineMemory() = default;
  // A read of the `bytes`-long line at byte address `addr` (a multiple of `bytes`), issued at
  // cycle `now` by unit `unit`; returns the cycle its data has fully arrived (> now).
  // Requests come in non-decreasing `now` from the units' scheduler; a level that forwards
  // a request later (after a queue) may send its own requests out of order, and every level
  // accepts that (a request never starts before the cycle it is issued).
  virtual uint64_t read_line(uint64_t now, uint64_t addr, uint32_t bytes, int unit) = 0;
};

}  // namespace texsim
