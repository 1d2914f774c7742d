#pragma once
// RectScanRasterizer: the rectangle-scan constant-depth rasteriser of seed 002 (fig. 3–4) as a
// structural model (docs/rasterizers.md §2). The triangle is virtually inscribed in a rectangle
// whose every row is the same digital line along which the depth is constant (slope k of the
// constant-depth lines, quantised by ЛІ), shifted one pixel along the minor axis per row: so a
// pixel (major, minor) belongs to the row minor - d(major - major0) and to no other, and there
// are neither holes nor duplicates between neighbouring rows. Elements, each a block with its
// own state and counters: LineStepper (ЛІ + БКП), RowStartCounter (РГХп + ЛЧУп),
// CoordinateCounters (ЛЧх, ЛЧу: also the memory address), OutlineMemory + OutlineComparator (the
// auxiliary memory, РГп and БП), TexturingControl (БКТ).
//
// Operating sequence: preparation (edge set-up, the outline drawn in the auxiliary memory,
// registers loaded); then per row: ЛЧх/ЛЧу load from РГХп/ЛЧУп, each step ЛІ/БКП move the
// counters, the memory word at their address is compared with РГп, БКТ decides; БКТ ends the row
// after the exit edge and the triangle after the last row. Background pixels are skipped at the
// fast clock; textured pixels run at the memory clock; one reciprocal per textured row feeds the
// constant-depth coordinate block (UvConstantDepth), so divisions = q rows.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/raster_types.h"
#include "blocks/raster/rect_scan/line_stepper.h"
#include "blocks/raster/rect_scan/seed_outline.h"
#include "blocks/raster/rect_scan/texturing_control.h"

namespace texsim {

class ConfigReader;

struct RectScanStats {
  uint64_t rows_scanned = 0;     // rows of the rectangle entered
  uint64_t rows_textured = 0;    // q: rows with a textured pixel (one reciprocal each)
  uint64_t pixels_visited = 0;   // pixels the counters stepped through
  uint64_t pixels_textured = 0;  // pixels sent to texturing
  uint64_t background_pixels = 0;
  uint64_t comparator_hits = 0, crossings = 0, vertex_hits = 0;
  uint64_t steps = 0, minor_steps = 0;  // ЛІ/БКП: major steps, carries into the minor axis
  uint64_t memory_reads = 0;            // auxiliary-memory reads (one per step)
  uint64_t outline_marks = 0, memory_words = 0;  // preparation: pixels drawn, memory size
  uint64_t fast_cycles = 0;    // background pixels and row starts, at the fast clock
  uint64_t memory_cycles = 0;  // textured pixels, at the memory clock
  uint64_t prep_cycles = 0;    // outline drawing (memory writes), at the memory clock
  double time_ns = 0;
  // coverage = "outline_parity": where the parity rule departs from what the seed means (the
  // inside, which БКТ's per-edge flags still compute beside it as the oracle, and the outline).
  ParityHazards hazards;
};

// A run of textured pixels: major0 .. major0+n-1 of row t, at minor = t + d(major - start).
// h: the row's exact line minor = k'·major + h in pixel-index coordinates (k' = line.slope()).
struct RectScanRun {
  int32_t t = 0, major0 = 0, n = 0;
  double h = 0;
};

// The rectangle in the row frame: columns [major0, major1], rows [t_lo, t_hi], the auxiliary
// memory's minor range [mem_lo, mem_hi] and the box's (scissor's) minor range [box_lo, box_hi].
struct RectScanFrame {
  int32_t major0 = 0, major1 = -1;
  int32_t t_lo = 0, t_hi = -1;
  int32_t mem_lo = 0, mem_hi = -1;
  int32_t box_lo = 0, box_hi = -1;
};

// One visited pixel as the datapath sees it (the RTL's transaction): its screen position, the
// row's first pixel, БКТ's decision and end of row, and БП's hit planes (0 on a row's first
// pixel, which takes its sides from the edge values instead).
struct RectScanEvent {
  int32_t x = 0, y = 0;
  bool row_start = false, texture = false, end_of_row = false;
  uint8_t hits = 0;
};
using RectScanEventSink = std::function<void(const RectScanEvent&)>;

struct RectScanResult {
  RasterReject reject = RasterReject::None;
  RowLine line{};
  RectScanFrame frame;
  int32_t major_start = 0;  // the rectangle's side where rows start (РГХп)
  std::vector<RectScanRun> runs;
  std::vector<std::pair<int32_t, int32_t>> pixels;  // textured (x, y) in visiting order
  RectScanStats stats;
};

class RectScanRasterizer {
 public:
  struct Config {
    int subpixel_bits = 8;          // vertex snapping, as EdgeRasterizer
    int slope_bits = 12;            // LineStepper: ΔX = 2^slope_bits
    double fast_clock_mhz = 1000;   // background pixels
    double memory_clock_mhz = 250;  // texturing and outline drawing
    RectScanCoverage coverage = RectScanCoverage::TopLeft;
    static Config from_toml(const ConfigReader& r);
  };
  RectScanRasterizer() = default;
  explicit RectScanRasterizer(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // The row line of a plane whose map has denominator q = G·x + H·y + I.
  RowLine line_for_denominator(double g, double h) const;
  RowLine line_for_slope(bool x_major, double k) const;
  // `events`, if given, receives every visited pixel in order.
  RectScanResult rasterize(const ScreenVertex v[3], const RowLine& line, const Scissor& sc,
                           const RectScanEventSink* events = nullptr) const;

  // Item: one visited pixel (a step of ЛІ/БКП and the counters, a memory read and compare, a
  // БКТ decision).
  OpCounts ops_per_item() const;
  OpCounts row_ops() const;  // counter loads, ЛЧУп step, БКТ row start
  OpCounts triangle_setup_ops() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.rect_scan"; }
  std::string arithmetic() const;

 private:
  Config cfg_{};
};

}  // namespace texsim
