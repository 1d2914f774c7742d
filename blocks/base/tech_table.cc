#include "blocks/base/tech_table.h"

#include <cmath>

#include "blocks/base/config_reader.h"

namespace texsim {

TechTable TechTable::defaults() {
  TechTable t;
  // Latencies typical of a pipelined float32 datapath at a few hundred MHz.
  //            add  mul  div  rcp  sqrt lut  cmp  mem
  t.latency = {1.0, 3.0, 12.0, 6.0, 8.0, 2.0, 1.0, 2.0};
  // Areas relative to a 32-bit adder (a multiplier is roughly the square of the width / 32).
  t.area = {1.0, 8.0, 24.0, 12.0, 16.0, 4.0, 0.5, 0.0};
  return t;
}

TechTable TechTable::from_toml(const toml::table& table, const std::string& source) {
  TechTable t = defaults();
  ConfigReader r(table, source, "tech");
  // `energy` belongs to EnergyTable::from_toml (blocks/base/energy_table.h).
  r.reject_unknown({"latency", "area", "clock_mhz", "block_area", "energy"});
  t.clock_mhz = r.get_double("clock_mhz", t.clock_mhz);
  if (!(t.clock_mhz > 0 && t.clock_mhz <= kMaxClockMhz))
    r.fail("clock_mhz", "must be in (0, " + std::to_string(static_cast<int>(kMaxClockMhz)) + "]");
  std::vector<std::string_view> kinds(kOpKindNames.begin(), kOpKindNames.end());
  for (const char* group : {"latency", "area"}) {
    ConfigReader g = r.sub(group);
    g.reject_unknown(kinds);
    auto& arr = std::string_view(group) == "latency" ? t.latency : t.area;
    for (int k = 0; k < kOpKinds; ++k) {
      arr[k] = g.get_double(kOpKindNames[k], arr[k]);
      const double hi = std::string_view(group) == "latency" ? kMaxOpLatency : kMaxOpArea;
      if (!(arr[k] >= 0 && arr[k] <= hi))
        g.fail(kOpKindNames[k], "must be in [0, " + std::to_string(static_cast<int>(hi)) + "]");
    }
  }
  if (const toml::table* blocks = r.subtable("block_area")) {
    const ConfigReader b = r.sub("block_area");
    for (const auto& [key, node] : *blocks) {
      const std::string name(key.str());
      const double a = b.get_double(name, -1);
      if (!(a >= 0 && a <= kMaxBlockArea))
        b.fail(name, "must be in [0, " + std::to_string(static_cast<int>(kMaxBlockArea)) + "]");
      t.block_area[name] = a;
    }
  }
  return t;
}

double TechTable::block_area_or(const std::string& block, double derived) const {
  const auto it = block_area.find(block);
  return it == block_area.end() ? derived : it->second;
}

double TechTable::path_latency(const OpCounts& path) const {
  double c = 0;
  for (int k = 0; k < kOpKinds; ++k) {
    c += static_cast<double>(path.get(static_cast<OpKind>(k))) * latency[k];
  }
  return c;
}

double TechTable::area_of(const OpCounts& units) const {
  double a = 0;
  for (int k = 0; k < kOpKinds; ++k) {
    a += static_cast<double>(units.get(static_cast<OpKind>(k))) * area[k];
  }
  return a;
}

}  // namespace texsim
