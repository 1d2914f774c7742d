// Banked DRAM: directed cases of the command timing, the presets, the address mappings and the
// configuration errors. Every expected cycle is written from the timing rules (banked_dram.h).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/texture/memory/banked_dram.h"

namespace texsim {
namespace {

// Small figures that keep every sum distinct: 64-byte lines take 64 / (8 x 2) = 4 bus cycles.
constexpr uint64_t tCL = 5, tRCD = 7, tRP = 6, tRAS = 20, T = 4;

BankedDram::Config small() {
  BankedDram::Config c;
  c.channels = 2;
  c.banks = 4;
  c.row_bytes = 1024;
  c.interleave_bytes = 64;
  c.mapping = BankedDram::Mapping::RowBankChannel;
  c.tCL = tCL;
  c.tRCD = tRCD;
  c.tRP = tRP;
  c.tRAS = tRAS;
  c.burst_length = 4;
  c.bus_bytes = 8;
  c.beats_per_cycle = 2;
  return c;
}

// row_bank_channel of small(): offset bits 0-5, channel bit 6, bank bits 7-8, column bits
// 9-12 (1024 / 64 = 16 blocks a row), row from bit 13.
uint64_t at(uint64_t channel, uint64_t bank, uint64_t column, uint64_t row) {
  return row << 13 | column << 9 | bank << 7 | channel << 6;
}

BankedDram::Config from_text(const std::string& text) {
  const toml::table t = parse_toml(text, "t.toml");
  return BankedDram::Config::from_toml(ConfigReader(t, "t.toml", "dram"));
}

std::string error_of(const std::string& text) {
  try {
    from_text(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(BankedDram, EmptyBankActivatesThenReads) {
  BankedDram d(small());
  EXPECT_EQ(d.read_line(10, at(0, 0, 0, 0), 64, 0), 10 + tRCD + tCL + T);
  EXPECT_EQ(d.stats().row_empty, 1u);
  EXPECT_EQ(d.stats().activations, 1u);
  EXPECT_EQ(d.stats().bank_wait_cycles, 0u);
  EXPECT_EQ(d.stats().bus_busy_cycles[0], T);
  EXPECT_EQ(d.stats().bus_busy_cycles[1], 0u);
}

TEST(BankedDram, RowHitNeedsOnlyTheColumn) {
  BankedDram d(small());
  d.read_line(0, at(0, 0, 0, 0), 64, 0);
  EXPECT_EQ(d.read_line(100, at(0, 0, 5, 0), 64, 0), 100 + tCL + T);
  EXPECT_EQ(d.stats().row_hits, 1u);
  EXPECT_EQ(d.stats().activations, 1u);
}

TEST(BankedDram, RowConflictWaitsForTras) {
  BankedDram d(small());
  d.read_line(0, at(0, 0, 0, 0), 64, 0);  // activate at 0
  // Precharge not before 0 + tRAS (the bank itself is ready at tRCD + T = 11 < 20).
  const uint64_t precharge = tRAS;
  EXPECT_EQ(d.read_line(0, at(0, 0, 0, 1), 64, 0), precharge + tRP + tRCD + tCL + T);
  EXPECT_EQ(d.stats().row_conflicts, 1u);
  EXPECT_EQ(d.stats().activations, 2u);
  EXPECT_EQ(d.stats().bank_wait_cycles, precharge);
}

TEST(BankedDram, RowConflictAfterTras) {
  BankedDram d(small());
  d.read_line(0, at(0, 0, 0, 0), 64, 0);
  EXPECT_EQ(d.read_line(100, at(0, 0, 0, 1), 64, 0), 100 + tRP + tRCD + tCL + T);
  EXPECT_EQ(d.stats().bank_wait_cycles, 0u);
}

TEST(BankedDram, TwoChannelsOverlap) {
  BankedDram d(small());
  EXPECT_EQ(d.read_line(0, at(0, 0, 0, 0), 64, 0), tRCD + tCL + T);
  EXPECT_EQ(d.read_line(0, at(1, 0, 0, 0), 64, 1), tRCD + tCL + T);
  EXPECT_EQ(d.stats().bus_busy_cycles[0], T);
  EXPECT_EQ(d.stats().bus_busy_cycles[1], T);
}

TEST(BankedDram, OneBankSerialisesConflicts) {
  BankedDram d(small());
  d.read_line(0, at(0, 0, 0, 0), 64, 0);
  // Row 1 at 100: precharge 100, activate 106, column 113, done 122.
  const uint64_t act1 = 100 + tRP;
  const uint64_t col1 = act1 + tRCD;
  EXPECT_EQ(d.read_line(100, at(0, 0, 0, 1), 64, 0), col1 + tCL + T);
  // Row 2 at 100: the bank is busy until col1 + T = 117 and row 1 must stay open until
  // act1 + tRAS = 126, so the precharge waits until 126.
  const uint64_t pre2 = std::max(col1 + T, act1 + tRAS);
  EXPECT_EQ(pre2, 126u);
  EXPECT_EQ(d.read_line(100, at(0, 0, 0, 2), 64, 0), pre2 + tRP + tRCD + tCL + T);
  EXPECT_EQ(d.stats().bank_wait_cycles, pre2 - 100);
}

TEST(BankedDram, OneBankSerialisesRowHits) {
  BankedDram d(small());
  d.read_line(0, at(0, 0, 0, 0), 64, 0);
  EXPECT_EQ(d.read_line(100, at(0, 0, 1, 0), 64, 0), 100 + tCL + T);
  // The bank takes the next column one burst later.
  EXPECT_EQ(d.read_line(100, at(0, 0, 2, 0), 64, 0), 100 + T + tCL + T);
  EXPECT_EQ(d.stats().bank_wait_cycles, T);
}

TEST(BankedDram, TwoBanksShareTheChannelBus) {
  BankedDram d(small());
  EXPECT_EQ(d.read_line(0, at(0, 0, 0, 0), 64, 0), tRCD + tCL + T);
  // Bank 1 has its data at tRCD + tCL too, but the bus is busy until tRCD + tCL + T.
  EXPECT_EQ(d.read_line(0, at(0, 1, 0, 0), 64, 0), tRCD + tCL + 2 * T);
  EXPECT_EQ(d.stats().bus_busy_cycles[0], 2 * T);
  EXPECT_EQ(d.stats().bank_wait_cycles, 0u);
}

TEST(BankedDram, ClosedPagePrechargesAfterEveryRead) {
  BankedDram::Config c = small();
  c.page_policy = BankedDram::PagePolicy::Closed;
  BankedDram d(c);
  EXPECT_EQ(d.read_line(0, at(0, 0, 0, 0), 64, 0), tRCD + tCL + T);
  // Auto-precharge at max(column 7, activate 0 + tRAS) = 20; the bank is empty at 26.
  const uint64_t ready = std::max(tRCD, tRAS) + tRP;
  EXPECT_EQ(d.read_line(10, at(0, 0, 1, 0), 64, 0), ready + tRCD + tCL + T);
  EXPECT_EQ(d.stats().row_hits, 0u);
  EXPECT_EQ(d.stats().row_conflicts, 0u);
  EXPECT_EQ(d.stats().row_empty, 2u);
  EXPECT_EQ(d.stats().activations, 2u);
  // Long after: an empty bank, no precharge on the way.
  EXPECT_EQ(d.read_line(1000, at(0, 0, 0, 3), 64, 0), 1000 + tRCD + tCL + T);
}

TEST(BankedDram, TransferIsAtLeastOneBurst) {
  BankedDram d(small());
  // 16 bytes would take one cycle at 16 bytes a cycle, but a burst of 4 beats takes 2.
  EXPECT_EQ(d.transfer_cycles(16), 2u);
  EXPECT_EQ(d.transfer_cycles(64), T);
  EXPECT_EQ(d.read_line(0, at(0, 0, 0, 0), 16, 0), tRCD + tCL + 2);
}

// Each preset from its datasheet figures in ns, rounded up to 2 ns cycles (500 MHz).
struct PresetCase {
  const char* name;
  double cl_ns, rcd_ns, rp_ns;
  double bytes_per_ns;  // channel: pins x Gb/s per pin / 8
  double burst_ns;      // one burst: burst length / data rate
};

TEST(BankedDram, PresetLatencies) {
  const PresetCase cases[] = {
      // GDDR6 14 Gb/s, tCK 0.57 ns: CL 24, tRCD 26, tRP 26 tCK; x16, BL16.
      {"gddr6", 24 * 0.57, 26 * 0.57, 26 * 0.57, 16 * 14.0 / 8, 16 / 14.0},
      // LPDDR4-3200: RL 28 at 1600 MHz, tRCD 18 ns, tRPpb 18 ns; x16, BL16.
      {"lpddr4", 28 / 1.6, 18, 18, 16 * 3.2 / 8, 16 / 3.2},
      // DDR4-3200AA: 13.75 ns each; x64, BL8.
      {"ddr4", 13.75, 13.75, 13.75, 64 * 3.2 / 8, 8 / 3.2},
  };
  for (const PresetCase& p : cases) {
    SCOPED_TRACE(p.name);
    const auto cycles = [](double ns) { return static_cast<uint64_t>(std::ceil(ns / 2 - 1e-9)); };
    const uint64_t cl = cycles(p.cl_ns), rcd = cycles(p.rcd_ns), rp = cycles(p.rp_ns);
    const uint64_t transfer = std::max(cycles(64 / p.bytes_per_ns), cycles(p.burst_ns));
    BankedDram d(from_text(std::string("preset = \"") + p.name + "\"\n"));
    // Row miss (an empty bank), then a row hit long after, then a conflict long after.
    EXPECT_EQ(d.read_line(0, 0, 64, 0), rcd + cl + transfer);
    EXPECT_EQ(d.read_line(1000, 64, 64, 0) - 1000, cl + transfer);
    const uint64_t next_row =
        uint64_t{d.config().row_bytes} * d.config().channels * d.config().banks;
    EXPECT_EQ(d.read_line(2000, next_row, 64, 0) - 2000, rp + rcd + cl + transfer);
  }
  // The figures the presets hold, for the record: gddr6 7/8/8, lpddr4 9/9/9, ddr4 7/7/7.
  EXPECT_EQ(from_text("preset = \"lpddr4\"").tRAS, 21u);  // 42 ns
  EXPECT_EQ(from_text("preset = \"ddr4\"").tRAS, 16u);    // 32 ns
  EXPECT_EQ(from_text("preset = \"gddr6\"").tRAS, 16u);   // 53 x 0.57 = 30.2 ns
}

TEST(BankedDram, ExplicitKeysOverrideThePreset) {
  const BankedDram::Config c = from_text("preset = \"ddr4\"\ntCL = 9\n");
  EXPECT_EQ(c.tCL, 9u);
  EXPECT_EQ(c.tRCD, 7u);
  EXPECT_EQ(c.bus_bytes, 8u);
  EXPECT_EQ(c.burst_length, 8u);
}

TEST(BankedDram, AddressMappings) {
  BankedDram::Config c = small();
  {
    BankedDram d(c);  // row | column | bank | channel | offset
    const auto l = d.locate((uint64_t{5} << 13) | (uint64_t{9} << 9) | (2u << 7) | (1u << 6) | 17);
    EXPECT_EQ(l.channel, 1u);
    EXPECT_EQ(l.bank, 2u);
    EXPECT_EQ(l.column, 9u);
    EXPECT_EQ(l.row, 5u);
    // Consecutive lines: channel 0, 1, then the next bank.
    EXPECT_EQ(d.locate(64).channel, 1u);
    EXPECT_EQ(d.locate(128).channel, 0u);
    EXPECT_EQ(d.locate(128).bank, 1u);
  }
  {
    c.mapping = BankedDram::Mapping::RowChannelBank;  // row | column | channel | bank | offset
    BankedDram d(c);
    const auto l = d.locate((uint64_t{5} << 13) | (uint64_t{9} << 9) | (1u << 8) | (2u << 6));
    EXPECT_EQ(l.bank, 2u);
    EXPECT_EQ(l.channel, 1u);
    EXPECT_EQ(l.column, 9u);
    EXPECT_EQ(l.row, 5u);
    EXPECT_EQ(d.locate(64).bank, 1u);
    EXPECT_EQ(d.locate(64).channel, 0u);
  }
  {
    c.mapping = BankedDram::Mapping::BankXor;  // bank 2 XOR (row 7 mod 4 = 3) = 1
    BankedDram d(c);
    const auto l = d.locate((uint64_t{7} << 13) | (2u << 7) | (1u << 6));
    EXPECT_EQ(l.bank, 1u);
    EXPECT_EQ(l.channel, 1u);
    EXPECT_EQ(l.row, 7u);
    // A stride of one row (8 KiB) hits one bank under the plain mapping, four under XOR.
    BankedDram plain(small());
    for (uint64_t r = 0; r < 4; ++r) {
      EXPECT_EQ(plain.locate(r << 13).bank, 0u);
      EXPECT_EQ(d.locate(r << 13).bank, r);
    }
  }
}

TEST(BankedDram, ConfigErrorsNameTheKey) {
  auto e = error_of("channels = 3\n");
  EXPECT_NE(e.find("t.toml:1:12"), std::string::npos) << e;
  EXPECT_NE(e.find("dram.channels: 3 is not a power of two"), std::string::npos) << e;
  e = error_of("banks = 128\n");
  EXPECT_NE(e.find("dram.banks: value 128 out of range [1, 64]"), std::string::npos) << e;
  e = error_of("row_bytes = 1024\ninterleave_bytes = 2048\n");
  EXPECT_NE(e.find("t.toml:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("dram.interleave_bytes: must not exceed row_bytes (1024)"), std::string::npos)
      << e;
  e = error_of("preset = \"hbm\"\n");
  EXPECT_NE(e.find("dram.preset: unknown value 'hbm'"), std::string::npos) << e;
  e = error_of("mapping = \"random\"\n");
  EXPECT_NE(e.find("dram.mapping: unknown value 'random'"), std::string::npos) << e;
  e = error_of("page_policy = \"adaptive\"\n");
  EXPECT_NE(e.find("dram.page_policy"), std::string::npos) << e;
  e = error_of("tCL = 0\n");
  EXPECT_NE(e.find("dram.tCL: value 0 out of range [1, 1000]"), std::string::npos) << e;
  e = error_of("tRAS = 5000\n");
  EXPECT_NE(e.find("dram.tRAS: value 5000 out of range"), std::string::npos) << e;
  e = error_of("beats_per_cycle = 0\n");
  EXPECT_NE(e.find("dram.beats_per_cycle: must be in"), std::string::npos) << e;
  e = error_of("tcl = 5\n");
  EXPECT_NE(e.find("dram: unknown key 'tcl'"), std::string::npos) << e;
}

TEST(BankedDram, LineLargerThanARowIsRejected) {
  BankedDram::Config c = small();
  c.interleave_bytes = 1024;
  BankedDram d(c);
  EXPECT_NO_THROW(d.validate(1024));
  try {
    d.validate(2048);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dram.row_bytes (1024) is smaller than the 2048-byte"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(BankedDram(small()).validate(128), std::invalid_argument);  // interleave 64
  EXPECT_THROW(d.read_line(0, 2048, 2048, 0), std::invalid_argument);
  EXPECT_THROW(d.read_line(0, 32, 64, 0), std::invalid_argument);  // not line-aligned
}

}  // namespace
}  // namespace texsim
