#include "blocks/texture/memory/banked_dram.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<BankedDram>);

namespace {

constexpr uint32_t kMaxTiming = 1000;  // cycles; keeps every read's latency small and exact

// ceil(x) for a ratio of exact figures computed in double: a ratio that is a whole number up
// to rounding (64 / (2 * 6.4)) must not become the next one.
uint64_t ceil_ratio(double x) { return static_cast<uint64_t>(std::ceil(x - 1e-9)); }

}  // namespace

BankedDram::Config BankedDram::Config::preset(const std::string& name) {
  Config c;  // the defaults are the gddr6 preset
  if (name == "gddr6") return c;
  if (name == "lpddr4") {
    c.banks = 8;
    c.tCL = 9;                // 17.5 ns
    c.tRCD = 9;               // 18 ns
    c.tRP = 9;                // 18 ns
    c.tRAS = 21;              // 42 ns
    c.beats_per_cycle = 6.4;  // 3200 MT/s x 2 ns
    return c;
  }
  if (name == "ddr4") {
    c.channels = 1;
    c.row_bytes = 8192;
    c.tCL = 7;    // 13.75 ns
    c.tRCD = 7;   // 13.75 ns
    c.tRP = 7;    // 13.75 ns
    c.tRAS = 16;  // 32 ns
    c.burst_length = 8;
    c.bus_bytes = 8;
    c.beats_per_cycle = 6.4;
    return c;
  }
  throw std::invalid_argument("dram: unknown preset '" + name + "'");
}

BankedDram::Config BankedDram::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"preset", "channels", "banks", "row_bytes", "interleave_bytes", "mapping",
                    "page_policy", "tCL", "tRCD", "tRP", "tRAS", "burst_length", "bus_bytes",
                    "beats_per_cycle"});
  static const std::vector<std::string_view> kPresets = {"gddr6", "lpddr4", "ddr4"};
  // Explicit keys override the preset's figures.
  Config c = preset(std::string(kPresets[r.get_choice("preset", 0, kPresets)]));
  const auto count = [&](const char* key, uint32_t def, int64_t lo, int64_t hi) {
    const auto v = static_cast<uint32_t>(r.get_int(key, def, lo, hi));
    if (!std::has_single_bit(v)) r.fail(key, std::to_string(v) + " is not a power of two");
    return v;
  };
  c.channels = count("channels", c.channels, 1, 64);
  c.banks = count("banks", c.banks, 1, 64);
  c.row_bytes = count("row_bytes", c.row_bytes, 16, 1 << 20);
  c.interleave_bytes = count("interleave_bytes", c.interleave_bytes, 16, 1 << 20);
  if (c.interleave_bytes > c.row_bytes)
    r.fail("interleave_bytes", "must not exceed row_bytes (" + std::to_string(c.row_bytes) + ")");
  c.mapping =
      static_cast<Mapping>(r.get_choice("mapping", static_cast<int>(c.mapping),
                                        {"row_bank_channel", "row_channel_bank", "bank_xor"}));
  c.page_policy = static_cast<PagePolicy>(
      r.get_choice("page_policy", static_cast<int>(c.page_policy), {"open", "closed"}));
  c.tCL = static_cast<uint32_t>(r.get_int("tCL", c.tCL, 1, kMaxTiming));
  c.tRCD = static_cast<uint32_t>(r.get_int("tRCD", c.tRCD, 0, kMaxTiming));
  c.tRP = static_cast<uint32_t>(r.get_int("tRP", c.tRP, 0, kMaxTiming));
  c.tRAS = static_cast<uint32_t>(r.get_int("tRAS", c.tRAS, 0, kMaxTiming));
  c.burst_length = static_cast<uint32_t>(r.get_int("burst_length", c.burst_length, 1, 64));
  c.bus_bytes = static_cast<uint32_t>(r.get_int("bus_bytes", c.bus_bytes, 1, 256));
  c.beats_per_cycle = r.get_double("beats_per_cycle", c.beats_per_cycle);
  if (!(c.beats_per_cycle >= 1.0 / 64 && c.beats_per_cycle <= 1024))
    r.fail("beats_per_cycle", "must be in [1/64, 1024]");
  return c;
}

std::string BankedDram::Config::line_error(uint32_t line_bytes) const {
  if (line_bytes == 0 || !std::has_single_bit(line_bytes))
    return "the line size " + std::to_string(line_bytes) + " is not a power of two";
  if (line_bytes > row_bytes) {
    return "dram.row_bytes (" + std::to_string(row_bytes) + ") is smaller than the " +
           std::to_string(line_bytes) + "-byte line read from it";
  }
  if (line_bytes > interleave_bytes) {
    return "dram.interleave_bytes (" + std::to_string(interleave_bytes) + ") is smaller than the " +
           std::to_string(line_bytes) +
           "-byte line read from it (a line must lie in one channel and bank)";
  }
  return "";
}

BankedDram::BankedDram() : BankedDram(Config{}) {}

BankedDram::BankedDram(const Config& c) : cfg_(c) {
  for (uint64_t v : {c.channels, c.banks, c.row_bytes, c.interleave_bytes}) {
    if (!std::has_single_bit(v)) throw std::invalid_argument("dram: counts must be 2^n");
  }
  if (c.interleave_bytes > c.row_bytes || !(c.beats_per_cycle > 0) || c.bus_bytes == 0 ||
      c.burst_length == 0) {
    throw std::invalid_argument("dram: bad geometry");
  }
  channel_bits_ = static_cast<uint32_t>(std::countr_zero(c.channels));
  bank_bits_ = static_cast<uint32_t>(std::countr_zero(c.banks));
  offset_bits_ = static_cast<uint32_t>(std::countr_zero(c.interleave_bytes));
  column_bits_ = static_cast<uint32_t>(std::countr_zero(c.row_bytes)) - offset_bits_;
  banks_.assign(static_cast<size_t>(c.channels) * c.banks, Bank{});
  bus_free_.assign(c.channels, 0);
  stats_.bus_busy_cycles.assign(c.channels, 0);
}

void BankedDram::validate(uint32_t line_bytes) const {
  if (const std::string e = cfg_.line_error(line_bytes); !e.empty()) throw std::invalid_argument(e);
}

BankedDram::Location BankedDram::locate(uint64_t addr) const {
  // Bit fields above the offset, least significant first.
  uint64_t a = addr >> offset_bits_;
  const auto take = [&a](uint32_t bits) {
    const uint64_t v = a & ((uint64_t{1} << bits) - 1);
    a >>= bits;
    return v;
  };
  Location l;
  if (cfg_.mapping == Mapping::RowChannelBank) {
    l.bank = static_cast<uint32_t>(take(bank_bits_));
    l.channel = static_cast<uint32_t>(take(channel_bits_));
  } else {
    l.channel = static_cast<uint32_t>(take(channel_bits_));
    l.bank = static_cast<uint32_t>(take(bank_bits_));
  }
  l.column = take(column_bits_);
  l.row = a;
  // Rows that share a bank under the plain mapping (a stride of one row) spread over banks.
  if (cfg_.mapping == Mapping::BankXor) l.bank ^= static_cast<uint32_t>(l.row & (cfg_.banks - 1));
  return l;
}

uint64_t BankedDram::transfer_cycles(uint32_t bytes) const {
  const double rate = static_cast<double>(cfg_.bus_bytes) * cfg_.beats_per_cycle;
  return std::max(ceil_ratio(bytes / rate), ceil_ratio(cfg_.burst_length / cfg_.beats_per_cycle));
}

uint64_t BankedDram::read_line(uint64_t now, uint64_t addr, uint32_t bytes, int /*unit*/) {
  if (bytes == 0 || bytes > cfg_.interleave_bytes || !std::has_single_bit(bytes) ||
      addr % bytes != 0) {
    validate(bytes);
    throw std::invalid_argument("dram: line address " + std::to_string(addr) +
                                " is not a multiple of its size " + std::to_string(bytes));
  }
  const Location l = locate(addr);
  Bank& b = banks_[static_cast<size_t>(l.channel) * cfg_.banks + l.bank];
  uint64_t first = 0;   // the read's first command
  uint64_t column = 0;  // its column command
  if (b.open && b.row == l.row) {
    ++stats_.row_hits;
    first = column = std::max(now, b.ready);
  } else {
    if (b.open) {
      ++stats_.row_conflicts;
      first = std::max({now, b.ready, b.last_act + cfg_.tRAS});  // precharge
      b.last_act = first + cfg_.tRP;
    } else {
      ++stats_.row_empty;
      first = b.last_act = std::max(now, b.ready);
    }
    ++stats_.activations;
    column = b.last_act + cfg_.tRCD;
    b.open = true;
    b.row = l.row;
  }
  stats_.bank_wait_cycles += first - now;
  const uint64_t transfer = transfer_cycles(bytes);
  const uint64_t start = std::max(column + cfg_.tCL, bus_free_[l.channel]);
  const uint64_t done = start + transfer;
  bus_free_[l.channel] = done;
  stats_.bus_busy_cycles[l.channel] += transfer;
  b.ready = column + transfer;
  if (cfg_.page_policy == PagePolicy::Closed) {
    const uint64_t precharge = std::max(column, b.last_act + cfg_.tRAS);
    b.ready = std::max(b.ready, precharge + cfg_.tRP);
    b.open = false;
  }
  ++stats_.requests;
  stats_.bytes += bytes;
  return done;
}

TimingSpec BankedDram::timing(const TechTable& tech) const {
  return derive_timing(tech, OpCounts{}, static_cast<double>(cfg_.tRCD + cfg_.tCL),
                       Datapath::Spatial);
}

}  // namespace texsim
