#pragma once
// RowStartCounter: the row-start register РГХп and the row-start counter ЛЧУп of the
// rectangle-scan rasteriser (seed 002, fig. 4; docs/rasterizers.md §2). РГХп holds the major
// coordinate of the rectangle's side where every row starts; ЛЧУп holds the minor coordinate of
// the current row's start and moves one level per row (the seed's y axis points up and
// decrements; ours points down the screen, so it increments).
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

class RowStartCounter {
 public:
  struct Config {
    static Config from_toml(const ConfigReader& r);
  };
  void load(int32_t major0, int32_t minor0) {
    major0_ = major0;
    minor_ = minor0;
  }
  void next_row() {
    ++minor_;
    ++rows_;
  }
  int32_t major0() const { return major0_; }  // РГХп
  int32_t minor() const { return minor_; }    // ЛЧУп
  uint64_t rows() const { return rows_; }

  // Item: one row (one increment of ЛЧУп).
  OpCounts ops_per_item() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.rect_scan.row_start_counter"; }
  std::string arithmetic() const { return "32-bit integer register and counter"; }

 private:
  int32_t major0_ = 0, minor_ = 0;
  uint64_t rows_ = 0;
};

}  // namespace texsim
