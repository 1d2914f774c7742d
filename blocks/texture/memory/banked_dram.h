#pragma once
// DRAM with channels, banks and row buffers: command timing of reads, first come first served
// in call order (docs/timing-model.md#memory-hierarchy).
//
// State: per bank the open row, the cycle the bank takes its next command and the cycle of its
// last activate; per channel the cycle its data bus is free. A read of a line:
//   row hit      column at c = max(now, bank ready)
//   empty bank   activate at a = max(now, bank ready), column at c = a + tRCD
//   row conflict precharge at p = max(now, bank ready, last activate + tRAS),
//                activate at a = p + tRP, column at c = a + tRCD
// then its data leaves the bank at c + tCL and holds the channel's bus for
//   transfer = max(ceil(bytes / (bus_bytes * beats_per_cycle)), ceil(burst_length /
//   beats_per_cycle)) cycles from max(c + tCL, bus free); the read is done when the transfer
// ends. The bank takes its next column command at c + transfer (one burst after another). The
// closed-page policy precharges after every column command, at max(c, a + tRAS), and the bank
// is empty again tRP later.
//
// Limits: reads only (the texture path never writes), no refresh, no power-down, no
// FR-FCFS or any reordering, no tFAW, tRRD, tCCD_L, tRTP or command-bus limits, one rank.
//
// Presets (docs/timing-model.md lists them): the datasheet figures in ns, converted to cycles
// of the 500 MHz default pipeline clock by rounding up (2 ns per cycle):
//   gddr6  — Ramulator 2.0's GDDR6 preset (GDDR6_2000_1350mV: tCK 0.57 ns, CL 24, tRCDRD 26,
//            tRP 26, tRAS 53 tCK; JESD250 leaves AC timings to vendors), 14 Gb/s per pin,
//            x16 channels, BL16, 16 banks, 2 KiB rows.
//   lpddr4 — JEDEC JESD209-4 (LPDDR4), LPDDR4-3200: RL 28 tCK at 1600 MHz (17.5 ns), tRCD
//            18 ns, tRPpb 18 ns, tRAS 42 ns, x16 channels, BL16, 8 banks, 2 KiB rows.
//   ddr4   — JEDEC JESD79-4 (DDR4) speed bin DDR4-3200AA (22-22-22): CL 13.75 ns, tRCD
//            13.75 ns, tRP 13.75 ns, tRAS 32 ns, a 64-bit channel, BL8, 16 banks, 8 KiB rows
//            (x8 devices, 1 KiB page each).
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/line_memory.h"

namespace texsim {

class BankedDram : public LineMemory {
 public:
  // Address mappings, named by their fields from the most to the least significant bit above
  // the offset inside an interleave block (docs/timing-model.md#memory-hierarchy):
  //   RowBankChannel  row | column | bank | channel | offset
  //   RowChannelBank  row | column | channel | bank | offset
  //   BankXor         as RowBankChannel, bank XOR the row's low bits (permutation interleave)
  enum class Mapping { RowBankChannel, RowChannelBank, BankXor };
  enum class PagePolicy { Open, Closed };

  struct Config {
    uint32_t channels = 2;
    uint32_t banks = 16;
    uint32_t row_bytes = 2048;        // one bank's row in one channel
    uint32_t interleave_bytes = 256;  // consecutive bytes in one channel, bank and row
    Mapping mapping = Mapping::RowBankChannel;
    PagePolicy page_policy = PagePolicy::Open;
    // Timing in texture-pipeline cycles (gddr6 preset).
    uint32_t tCL = 7;             // column command to first data
    uint32_t tRCD = 8;            // activate to column command
    uint32_t tRP = 8;             // precharge to activate
    uint32_t tRAS = 16;           // activate to precharge, at least
    uint32_t burst_length = 16;   // beats of one column command
    uint32_t bus_bytes = 2;       // bytes per beat per channel
    double beats_per_cycle = 28;  // data beats per pipeline cycle
    static Config from_toml(const ConfigReader& r);
    // The preset's figures ("gddr6", "lpddr4", "ddr4"); throws std::invalid_argument on
    // another name.
    static Config preset(const std::string& name);
    // Empty when lines of `line_bytes` can be read, else what is wrong, naming the key.
    std::string line_error(uint32_t line_bytes) const;
  };
  struct Location {
    uint32_t channel = 0;
    uint32_t bank = 0;
    uint64_t row = 0;
    uint64_t column = 0;  // interleave block inside the row
  };
  struct Stats {
    uint64_t requests = 0;
    uint64_t bytes = 0;
    uint64_t row_hits = 0;
    uint64_t row_empty = 0;
    uint64_t row_conflicts = 0;
    uint64_t activations = 0;
    uint64_t bank_wait_cycles = 0;          // first command of a read minus its `now`
    std::vector<uint64_t> bus_busy_cycles;  // per channel
  };

  BankedDram();
  explicit BankedDram(const Config& c);  // throws std::invalid_argument on a bad geometry
  // Throws std::invalid_argument (naming the key) unless lines of `line_bytes` can be read.
  void validate(uint32_t line_bytes) const;
  uint64_t read_line(uint64_t now, uint64_t addr, uint32_t bytes, int unit) override;
  Location locate(uint64_t addr) const;
  // Cycles one line of `bytes` holds a channel's bus.
  uint64_t transfer_cycles(uint32_t bytes) const;

  const Config& config() const { return cfg_; }
  const Stats& stats() const { return stats_; }

  // Item: one line read (one memory read).
  static OpCounts ops_per_item() {
    OpCounts o;
    o.mem = 1;
    return o;
  }
  // Latency of a read to an empty bank (tRCD + tCL); the banks and buses are modelled by
  // read_line, not by ii.
  TimingSpec timing(const TechTable& tech) const;
  static std::string name() { return "dram"; }
  static std::string arithmetic() { return "none (command timing)"; }

 private:
  struct Bank {
    bool open = false;
    uint64_t row = 0;
    uint64_t ready = 0;     // cycle it takes its next command
    uint64_t last_act = 0;  // cycle of its last activate
  };
  Config cfg_;
  uint32_t channel_bits_ = 0;
  uint32_t bank_bits_ = 0;
  uint32_t column_bits_ = 0;
  uint32_t offset_bits_ = 0;
  std::vector<Bank> banks_;         // channels * banks
  std::vector<uint64_t> bus_free_;  // per channel
  Stats stats_;
};

}  // namespace texsim
