#pragma once
// Technology table: latency (cycles) and area (relative units) of one operator of each kind.
// Every block derives its timing and area from this table, never from scattered constants.
#include <array>
#include <map>
#include <string>

#include "blocks/base/op_counts.h"

namespace toml {
inline namespace v3 {
class table;
}
}  // namespace toml

namespace texsim {

struct TechTable {
  // Ranges a scene may set (docs/timing-model.md): they keep every derived latency, area and
  // cycle count finite and far inside 32-bit latencies, and the pipeline's memory (which
  // grows with latency ÷ II) bounded.
  static constexpr double kMaxOpLatency = 1000;  // cycles of one operator
  static constexpr double kMaxOpArea = 1e6;      // adder equivalents of one operator
  static constexpr double kMaxClockMhz = 1e5;
  static constexpr double kMaxBlockArea = 1e9;  // a whole block's measured area

  // Latency in cycles of one operator of each kind (pipelined: one new operation per cycle).
  std::array<double, kOpKinds> latency{};
  // Area of one operator instance, in adder-equivalents (a 32-bit adder = 1).
  std::array<double, kOpKinds> area{};
  // Clock of the texture pipeline, for converting cycles to time in reports.
  double clock_mhz = 500.0;
  // Optional measured areas of whole blocks, by their name in reports (TOML `block_area`), e.g.
  // SB_LUT4 of the real RTL from `texsim study rtl` (its rtl_tech.toml): a block listed here
  // reports this area instead of the one derived from its operators. Empty by default.
  std::map<std::string, double> block_area;

  double lat(OpKind k) const { return latency[static_cast<int>(k)]; }
  double ar(OpKind k) const { return area[static_cast<int>(k)]; }

  // Defaults: a generic FPGA/ASIC-like float32 datapath (docs/timing-model.md explains them).
  static TechTable defaults();
  // Overrides defaults from a TOML table with keys latency.<kind>, area.<kind>, clock_mhz and
  // block_area.<block name>.
  // Throws InputError naming the source, line, column and key on a bad value.
  static TechTable from_toml(const toml::table& t, const std::string& source);

  // Cycles along a critical path that performs `path` operations in sequence.
  double path_latency(const OpCounts& path) const;
  // Area of a datapath that instantiates `units` operators of each kind.
  double area_of(const OpCounts& units) const;
  // The block's measured area from block_area, or `derived` when it has none.
  double block_area_or(const std::string& block, double derived) const;
};

}  // namespace texsim
