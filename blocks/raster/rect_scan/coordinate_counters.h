#pragma once
// CoordinateCounters: the coordinate counters ЛЧх and ЛЧу of the rectangle-scan rasteriser (seed
// 002, fig. 4; docs/rasterizers.md §2). Loaded from РГХп/ЛЧУп at each row start and stepped by
// the БКП increments (major +1, minor 0 or ±1); their outputs are the pixel coordinates and at
// the same time the address of the auxiliary memory.
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

class CoordinateCounters {
 public:
  struct Config {
    static Config from_toml(const ConfigReader& r);
  };
  explicit CoordinateCounters(bool x_major = true) : x_major_(x_major) {}
  void load(int32_t major, int32_t minor) {
    major_ = major;
    minor_ = minor;
    ++loads_;
  }
  void step(int minor_increment) {
    ++major_;
    minor_ += minor_increment;
    ++steps_;
  }
  int32_t major() const { return major_; }
  int32_t minor() const { return minor_; }
  int32_t x() const { return x_major_ ? major_ : minor_; }  // ЛЧх
  int32_t y() const { return x_major_ ? minor_ : major_; }  // ЛЧу
  uint64_t steps() const { return steps_; }
  uint64_t loads() const { return loads_; }

  // Item: one step (two counter increments).
  OpCounts ops_per_item() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.rect_scan.coordinate_counters"; }
  std::string arithmetic() const { return "two 32-bit integer counters"; }

 private:
  bool x_major_ = true;
  int32_t major_ = 0, minor_ = 0;
  uint64_t steps_ = 0, loads_ = 0;
};

}  // namespace texsim
