#include "blocks/base/energy_table.h"

#include <cmath>

#include "blocks/base/config_reader.h"

namespace texsim {

EnergyTable EnergyTable::defaults() {
  EnergyTable e;
  // Horowitz (ISSCC 2014, 45 nm) gives add, mul and integer add. The rest are assumptions:
  //  lut  2.5 — a table of at most 1 KB read 32 bits wide: half the width of the smallest
  //             SRAM figure (8 KB, 64 bits, 10 pJ) and taken as half again for the smaller array;
  //  rcp 10.8 — a table seed and one Newton-Raphson step x(2 - ax): lut + 2 mul + 1 add;
  //  div 14.5 — a reciprocal and a multiply: rcp + mul;
  //  sqrt 18.2 — a 1/sqrt seed, one Newton-Raphson step y(1.5 - 0.5 a y^2) and a·y:
  //             lut + 4 mul + 1 add;
  //  cmp  0.1 — a 32-bit integer subtract (Horowitz's 32-bit integer add);
  //  mem  0   — memory reads are charged per level with sram_access_pj and dram_pj; pricing
  //             the op as well would count them twice.
  //            add  mul  div   rcp   sqrt  lut  cmp  mem
  e.op_pj = {0.9, 3.7, 14.5, 10.8, 18.2, 2.5, 0.1, 0.0};
  constexpr uint64_t kKiB = 1024;
  e.sram = {{8 * kKiB, 10.0}, {32 * kKiB, 20.0}, {1024 * kKiB, 100.0}};
  e.sram_access_bytes = 8;
  // 1.3-2.6 nJ per 64-bit access: the low end taken as a row-buffer hit (1.3 nJ / 8 bytes) and
  // the spread as the row activation an access may need (2.6 - 1.3 nJ).
  e.dram_byte_pj = 1300.0 / 8;
  e.dram_activation_pj = 1300.0;
  return e;
}

namespace {

double read_pj(const ConfigReader& r, std::string_view key, double def) {
  const double v = r.get_double(key, def);
  if (!(v >= 0 && v <= EnergyTable::kMaxPj)) r.fail(key, "must be in [0, 1e6] pJ");
  return v;
}

// `sram` = [{ capacity_bytes = N, pj = E }, ...], by strictly increasing capacity.
std::vector<EnergyTable::SramClass> read_sram(const ConfigReader& r) {
  const toml::node* n = r.table().get("sram");
  const toml::array* a = n ? n->as_array() : nullptr;
  if (!a) r.fail("sram", "expected an array of tables {capacity_bytes, pj}");
  if (a->empty()) r.fail("sram", "needs at least one capacity class");
  std::vector<EnergyTable::SramClass> out;
  for (size_t i = 0; i < a->size(); ++i) {
    const toml::node& item = *a->get(i);
    const toml::table* t = item.as_table();
    const std::string name = r.block() + ".sram[" + std::to_string(i) + "]";
    if (!t)
      r.fail_at(item, "sram[" + std::to_string(i) + "]: expected a table {capacity_bytes, pj}");
    const ConfigReader c(*t, r.source(), name);
    c.reject_unknown({"capacity_bytes", "pj"});
    if (!t->contains("capacity_bytes") || !t->contains("pj"))
      c.fail_at(item, "needs both capacity_bytes and pj");
    EnergyTable::SramClass k;
    k.capacity_bytes = static_cast<uint64_t>(c.get_int("capacity_bytes", 0, 1, int64_t{1} << 40));
    k.pj = read_pj(c, "pj", 0);
    if (!out.empty() && k.capacity_bytes <= out.back().capacity_bytes)
      c.fail("capacity_bytes", "must be larger than the previous class's");
    out.push_back(k);
  }
  return out;
}

}  // namespace

EnergyTable EnergyTable::from_toml(const toml::table& tech, const std::string& source) {
  EnergyTable e = defaults();
  const ConfigReader r = ConfigReader(tech, source, "tech").sub("energy");
  r.reject_unknown({"op", "sram", "sram_access_bytes", "dram_byte_pj", "dram_activation_pj"});
  const ConfigReader op = r.sub("op");
  op.reject_unknown(std::vector<std::string_view>(kOpKindNames.begin(), kOpKindNames.end()));
  for (int k = 0; k < kOpKinds; ++k) e.op_pj[k] = read_pj(op, kOpKindNames[k], e.op_pj[k]);
  if (r.table().contains("sram")) e.sram = read_sram(r);
  e.sram_access_bytes =
      static_cast<uint32_t>(r.get_int("sram_access_bytes", e.sram_access_bytes, 1, 4096));
  e.dram_byte_pj = read_pj(r, "dram_byte_pj", e.dram_byte_pj);
  e.dram_activation_pj = read_pj(r, "dram_activation_pj", e.dram_activation_pj);
  return e;
}

double EnergyTable::ops_pj(const OpCounts& ops) const {
  double pj = 0;
  for (int k = 0; k < kOpKinds; ++k)
    pj += static_cast<double>(ops.get(static_cast<OpKind>(k))) * op_pj[k];
  return pj;
}

double EnergyTable::sram_access_pj(uint64_t capacity_bytes, uint32_t access_bytes) const {
  const double width = static_cast<double>(access_bytes) / sram_access_bytes;
  if (sram.empty()) return 0;
  if (capacity_bytes <= sram.front().capacity_bytes) return sram.front().pj * width;
  if (capacity_bytes >= sram.back().capacity_bytes) return sram.back().pj * width;
  size_t i = 1;
  while (sram[i].capacity_bytes < capacity_bytes) ++i;
  const SramClass& lo = sram[i - 1];
  const SramClass& hi = sram[i];
  const double base = static_cast<double>(lo.capacity_bytes);
  const double f = std::log2(static_cast<double>(capacity_bytes) / base) /
                   std::log2(static_cast<double>(hi.capacity_bytes) / base);
  return (lo.pj + f * (hi.pj - lo.pj)) * width;
}

double EnergyTable::dram_pj(uint64_t bytes, uint64_t activations) const {
  return static_cast<double>(bytes) * dram_byte_pj +
         static_cast<double>(activations) * dram_activation_pj;
}

}  // namespace texsim
