#pragma once
// The block behind a board, as the board's firmware sees it: a name, its widths, a
// configuration it can load, and a run of input vectors turned into results and cycles.
// The virtual board runs it in process; a C++ functional core (vd_core_block.h) implements it
// today, and a Verilated RTL model can implement the same interface to run the RTL instead.
// Inputs and results are raw bit patterns, right-aligned in 32 bits.
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "rtl_model/link/commands.h"

namespace texsim::link {

class BoardBlock {
 public:
  virtual ~BoardBlock() = default;
  // Name, input and result widths (of the current configuration) and latency.
  virtual BlockCaps caps() const = 0;
  // Loads block-specific configuration bytes; returns "" or what is wrong with them.
  virtual std::string configure(std::span<const uint8_t> config) = 0;
  // Feeds `in` back to back (one per cycle if the block is pipelined) and writes one result per
  // input into `out` (same size); returns the cycles from the first input to the last result.
  // Every input is below 2^caps().in_bits (the board checks that first).
  virtual uint64_t apply(std::span<const uint32_t> in, std::span<uint32_t> out) = 0;
};

}  // namespace texsim::link
