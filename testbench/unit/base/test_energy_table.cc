// Energy table: the cited defaults, overrides from [tech.energy], the interpolation between
// SRAM classes, and bad values named by file:line:column and key.
#include <gtest/gtest.h>

#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/energy_table.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"

namespace texsim {
namespace {

constexpr uint64_t kKiB = 1024;

EnergyTable from_text(const std::string& text) {
  return EnergyTable::from_toml(parse_toml(text, "t.toml"), "t.toml");
}

std::string error_of(const std::string& text) {
  try {
    from_text(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(EnergyTable, HorowitzDefaults) {
  const EnergyTable e = EnergyTable::defaults();
  OpCounts ops;
  ops.add = 2;
  ops.mul = 1;
  ops.cmp = 10;
  ops.mem = 7;  // charged per memory level, not here
  EXPECT_DOUBLE_EQ(e.ops_pj(ops), 2 * 0.9 + 3.7 + 10 * 0.1);
  // 64-bit reads: 8 KB 10 pJ, 32 KB 20 pJ, 1 MB 100 pJ.
  EXPECT_DOUBLE_EQ(e.sram_access_pj(8 * kKiB, 8), 10.0);
  EXPECT_DOUBLE_EQ(e.sram_access_pj(32 * kKiB, 8), 20.0);
  EXPECT_DOUBLE_EQ(e.sram_access_pj(1024 * kKiB, 8), 100.0);
  // DRAM 1.3 nJ per 64-bit access at best, 2.6 nJ with an activation.
  EXPECT_DOUBLE_EQ(e.dram_pj(8, 0), 1300.0);
  EXPECT_DOUBLE_EQ(e.dram_pj(8, 1), 2600.0);
  EXPECT_DOUBLE_EQ(e.dram_pj(64, 2), 8 * 1300.0 + 2 * 1300.0);
}

TEST(EnergyTable, SramRuleBetweenClasses) {
  const EnergyTable e = EnergyTable::defaults();
  // 16 KB is half way from 8 KB to 32 KB in log2: (10 + 20) / 2.
  EXPECT_DOUBLE_EQ(e.sram_access_pj(16 * kKiB, 8), 15.0);
  // 256 KB is 3 of the 5 doublings from 32 KB to 1 MB: 20 + 3/5 * 80.
  EXPECT_NEAR(e.sram_access_pj(256 * kKiB, 8), 68.0, 1e-12);
  // Held constant outside the classes.
  EXPECT_DOUBLE_EQ(e.sram_access_pj(1024, 8), 10.0);
  EXPECT_DOUBLE_EQ(e.sram_access_pj(64 * kKiB * 1024, 8), 100.0);
  // Linear in the access width: a 64-byte line from 32 KB is 8 reads of 8 bytes.
  EXPECT_DOUBLE_EQ(e.sram_access_pj(32 * kKiB, 64), 160.0);
  EXPECT_DOUBLE_EQ(e.sram_access_pj(32 * kKiB, 4), 10.0);
}

TEST(EnergyTable, Overrides) {
  const EnergyTable e = from_text(
      "clock_mhz = 800\n"
      "[energy]\n"
      "op = { add = 1.5, div = 20 }\n"
      "dram_byte_pj = 20\n"
      "dram_activation_pj = 900\n"
      "sram_access_bytes = 4\n"
      "sram = [{ capacity_bytes = 1024, pj = 2.0 }, { capacity_bytes = 4096, pj = 6.0 }]\n");
  EXPECT_DOUBLE_EQ(e.op_pj[static_cast<int>(OpKind::Add)], 1.5);
  EXPECT_DOUBLE_EQ(e.op_pj[static_cast<int>(OpKind::Div)], 20.0);
  EXPECT_DOUBLE_EQ(e.op_pj[static_cast<int>(OpKind::Mul)], 3.7);  // default kept
  EXPECT_DOUBLE_EQ(e.dram_pj(10, 1), 10 * 20.0 + 900.0);
  EXPECT_DOUBLE_EQ(e.sram_access_pj(2048, 4), 4.0);  // half way in log2
  EXPECT_DOUBLE_EQ(e.sram_access_pj(2048, 8), 8.0);
  EXPECT_DOUBLE_EQ(e.sram_access_pj(1 << 20, 4), 6.0);
  // No energy table at all: the defaults.
  EXPECT_DOUBLE_EQ(from_text("clock_mhz = 800\n").dram_byte_pj, 162.5);
}

TEST(EnergyTable, TechTableSkipsTheEnergyTable) {
  const toml::table t =
      parse_toml("clock_mhz = 250\n[latency]\nmul = 4\n[energy]\nop = { add = 2 }\n", "t.toml");
  const TechTable tech = TechTable::from_toml(t, "t.toml");
  EXPECT_DOUBLE_EQ(tech.clock_mhz, 250.0);
  EXPECT_DOUBLE_EQ(tech.lat(OpKind::Mul), 4.0);
  EXPECT_DOUBLE_EQ(tech.lat(OpKind::Add), TechTable::defaults().lat(OpKind::Add));
  // Other unknown keys are still errors.
  EXPECT_THROW(TechTable::from_toml(parse_toml("energi = 1\n", "t.toml"), "t.toml"), InputError);
}

TEST(EnergyTable, BadValuesNameTheKey) {
  auto e = error_of("[energy]\nop = { add = -1 }\n");
  EXPECT_NE(e.find("t.toml:2:14"), std::string::npos) << e;
  EXPECT_NE(e.find("tech.energy.op.add: must be in [0, 1e6] pJ"), std::string::npos) << e;
  e = error_of("[energy]\ndram_byte_pj = nan\n");
  EXPECT_NE(e.find("t.toml:2:16"), std::string::npos) << e;
  EXPECT_NE(e.find("tech.energy.dram_byte_pj: must be finite"), std::string::npos) << e;
  e = error_of("[energy]\ndram_activation_pj = -inf\n");
  EXPECT_NE(e.find("tech.energy.dram_activation_pj: must be finite"), std::string::npos) << e;
  e = error_of("[energy]\ndram_bytes_pj = 3\n");
  EXPECT_NE(e.find("t.toml:2:17"), std::string::npos) << e;
  EXPECT_NE(e.find("tech.energy: unknown key 'dram_bytes_pj'"), std::string::npos) << e;
  e = error_of("[energy.op]\nfma = 1\n");
  EXPECT_NE(e.find("tech.energy.op: unknown key 'fma'"), std::string::npos) << e;
  e = error_of("[energy]\nop = { mul = \"x\" }\n");
  EXPECT_NE(e.find("tech.energy.op.mul: expected a number"), std::string::npos) << e;
  e = error_of("[energy]\nsram_access_bytes = 0\n");
  EXPECT_NE(e.find("tech.energy.sram_access_bytes: value 0 out of range"), std::string::npos) << e;
}

TEST(EnergyTable, BadSramClasses) {
  auto e = error_of("[energy]\nsram = []\n");
  EXPECT_NE(e.find("tech.energy.sram: needs at least one capacity class"), std::string::npos) << e;
  e = error_of("[energy]\nsram = 5\n");
  EXPECT_NE(e.find("tech.energy.sram: expected an array"), std::string::npos) << e;
  e = error_of("[energy]\nsram = [3]\n");
  EXPECT_NE(e.find("t.toml:2:9"), std::string::npos) << e;
  EXPECT_NE(e.find("sram[0]: expected a table"), std::string::npos) << e;
  e = error_of(
      "[energy]\nsram = [{ capacity_bytes = 4096, pj = 1.0 },\n"
      "        { capacity_bytes = 4096, pj = 2.0 }]\n");
  EXPECT_NE(e.find("t.toml:3:28"), std::string::npos) << e;
  EXPECT_NE(e.find("tech.energy.sram[1].capacity_bytes: must be larger than the previous"),
            std::string::npos)
      << e;
  e = error_of("[energy]\nsram = [{ capacity_bytes = 4096, pj = -2.0 }]\n");
  EXPECT_NE(e.find("tech.energy.sram[0].pj: must be in [0, 1e6] pJ"), std::string::npos) << e;
  e = error_of("[energy]\nsram = [{ capacity_bytes = 4096 }]\n");
  EXPECT_NE(e.find("tech.energy.sram[0]: needs both capacity_bytes and pj"), std::string::npos)
      << e;
  e = error_of("[energy]\nsram = [{ capacity = 4096, pj = 1.0 }]\n");
  EXPECT_NE(e.find("tech.energy.sram[0]: unknown key 'capacity'"), std::string::npos) << e;
}

}  // namespace
}  // namespace texsim
