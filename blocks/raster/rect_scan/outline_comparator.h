#pragma once
// The auxiliary memory of the rectangle-scan rasteriser with the triangle's outline drawn in it,
// the foreground-colour register РГп and the comparator БП of memory data against РГп (seed 002,
// fig. 4; docs/rasterizers.md §2).
//
// What is drawn, and why it differs from the seed: the seed draws the triangle in one
// foreground colour and fills between crossings by the parity rule. A sloped 8-connected row can
// cross an 8-connected outline without sharing a pixel (opposite diagonals), one crossing can
// give a run of several hits, and a row touching a vertex sees an even count. Here each edge has
// its own bit plane (three foreground "colours"), and a pixel is marked in plane e where the
// row, stepping from the previous pixel of the same digital row, crosses the line of edge e
// (the side of the pixel centre changes under the top-left rule). The marks are drawn in the
// frame of the scan rows, so no crossing can fall between two pixels, and every hit is exactly
// one crossing of one edge.
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/rect_scan/line_stepper.h"

namespace texsim {

class ConfigReader;

// The auxiliary memory: one 3-bit word per pixel of a window [major0, major1] × [minor0, minor1]
// (major/minor as the row line says); reads outside the window give 0 (background).
class OutlineMemory {
 public:
  OutlineMemory() = default;
  OutlineMemory(const RowLine& line, int32_t major0, int32_t major1, int32_t minor0,
                int32_t minor1);
  // Draws the crossings of the three edge lines of `st` along rows of `line` starting at the
  // window's major0 column. Returns the number of marked pixels (memory writes).
  uint64_t draw(const EdgeRasterizer::Setup& st);
  uint8_t read(int32_t major, int32_t minor) {
    ++reads_;
    if (major < major0_ || major > major1_ || minor < minor0_ || minor > minor1_) return 0;
    return words_[index(major, minor)];
  }
  // A read that is not counted (the parity rule's oracle, beside the datapath).
  uint8_t peek(int32_t major, int32_t minor) const {
    if (major < major0_ || major > major1_ || minor < minor0_ || minor > minor1_) return 0;
    return words_[index(major, minor)];
  }
  uint64_t reads() const { return reads_; }
  uint64_t words() const { return words_.size(); }

 private:
  size_t index(int32_t major, int32_t minor) const {
    return static_cast<size_t>(minor - minor0_) * static_cast<size_t>(major1_ - major0_ + 1) +
           static_cast<size_t>(major - major0_);
  }
  RowLine line_{};
  int32_t major0_ = 0, major1_ = -1, minor0_ = 0, minor1_ = -1;
  std::vector<uint8_t> words_;
  uint64_t reads_ = 0;
};

class OutlineComparator {
 public:
  struct Config {
    static Config from_toml(const ConfigReader& r);
  };
  // РГп: the planes the triangle was drawn in.
  void set_foreground(uint8_t planes) { foreground_ = planes; }
  // БП: the planes of the memory word that match РГп (one bit per edge crossed here).
  uint8_t compare(uint8_t word) {
    ++compares_;
    const auto hit = static_cast<uint8_t>(word & foreground_);
    if (hit) ++hits_;
    return hit;
  }
  // The hit planes of `word` without counting a compare.
  uint8_t planes(uint8_t word) const { return static_cast<uint8_t>(word & foreground_); }
  uint64_t compares() const { return compares_; }
  uint64_t hits() const { return hits_; }

  // Item: one visited pixel (one memory read, one compare).
  OpCounts ops_per_item() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.rect_scan.outline_comparator"; }
  std::string arithmetic() const { return "3-bit memory words (one plane per edge), bitwise AND"; }

 private:
  uint8_t foreground_ = 7;
  uint64_t compares_ = 0, hits_ = 0;
};

}  // namespace texsim
