#pragma once
// DRAM behind the texture cache: fixed access latency plus a bandwidth-limited channel that
// serialises line transfers (docs/timing-model.md#memory).
#include <cstdint>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/line_memory.h"

namespace texsim {

class DramModel final : public LineMemory {
 public:
  struct Config {
    uint32_t latency = 100;       // cycles from request to first data
    double bytes_per_cycle = 16;  // channel bandwidth
    static Config from_toml(const ConfigReader& r);
  };
  struct Stats {
    uint64_t requests = 0;
    uint64_t bytes = 0;
    uint64_t busy_cycles = 0;  // cycles the channel was transferring (rounded up once)
  };

  DramModel();
  explicit DramModel(const Config& c) : cfg_(c) {}
  // A read of `bytes` issued at cycle `now`; returns the cycle its data has fully arrived.
  uint64_t read(uint64_t now, uint32_t bytes);
  // As a level behind an L1: the flat channel does not look at the address or the unit.
  uint64_t read_line(uint64_t now, uint64_t /*addr*/, uint32_t bytes, int /*unit*/) override {
    return read(now, bytes);
  }
  const Stats& stats() const { return stats_; }
  const Config& config() const { return cfg_; }
  // Smallest bandwidth a scene may set: 64-byte lines then take 65,536 cycles each, which keeps
  // a 10^7-fragment trace's cycle count far below 2^53 (where double stops counting exactly).
  static constexpr double kMinBytesPerCycle = 1.0 / 1024;

  // Item: one line request (one memory read).
  static OpCounts ops_per_item() {
    OpCounts o;
    o.mem = 1;
    return o;
  }
  // The access latency (at least one cycle, as for every block); the channel's occupancy is
  // modelled by read(), not by ii.
  TimingSpec timing(const TechTable& tech) const;
  static std::string name() { return "dram"; }
  static std::string arithmetic() { return "none (bandwidth-limited channel)"; }

 private:
  Config cfg_;
  double busy_ = 0;          // exact transfer time, summed; busy_cycles is its ceiling
  double channel_free_ = 0;  // cycle the channel finishes its current transfer
  Stats stats_;
};

}  // namespace texsim
