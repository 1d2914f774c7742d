#pragma once
// The seed's literal outline memory and parity rule (seed 002, fig. 4; docs/rasterizers.md §2,
// coverage = "outline_parity"): before texturing, the triangle's three edges are drawn in the
// auxiliary memory in ONE foreground colour as 8-connected digital lines (Bresenham between
// the vertices' pixels); along each scan row БП compares each word with РГп, and БКТ textures
// the outline pixels and the pixels after an odd number of crossings (a run of consecutive hits
// is one crossing; a run through a vertex's pixel counts two, as the seed's vertex compare
// says). It ends the row when the parity closes again after texturing.
//
// The rule fails where the outline does not say how many times the row crossed: at vertices
// (a row through the side vertex's pixel may cross twice or not at all), along edges nearly
// parallel to the rows (a run of hits may be an entry and an exit), where two edges' outlines
// touch (one run for two crossings), and where a sloped row steps across an 8-connected edge
// between two of its pixels (no hit at all). Each edge's bit is kept beside the word only to
// classify those hazards; the datapath sees one colour.
#include <cstdint>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/rect_scan/line_stepper.h"

namespace texsim {

// One word per pixel of the vertices' pixel box (within the scanned box): bit e set where edge
// e's line passes.
class SeedOutlineMemory {
 public:
  SeedOutlineMemory() = default;
  // Draws the three edges of `st` (its snapped vertices rounded to pixels); the vertices on the
  // first and last row of `line`'s rows (starting at column major0) are the ones БКТ compares.
  // Returns the pixels written.
  uint64_t draw(const EdgeRasterizer::Setup& st, const RowLine& line, int32_t major0);
  uint8_t read(int32_t x, int32_t y) {
    ++reads_;
    if (words_.empty() || x < x0_ || x > x1_ || y < y0_ || y > y1_) return 0;
    return words_[index(x, y)];
  }
  uint8_t peek(int32_t x, int32_t y) const {  // a read that is not counted (the oracle's)
    if (words_.empty() || x < x0_ || x > x1_ || y < y0_ || y > y1_) return 0;
    return words_[index(x, y)];
  }
  bool is_vertex(int32_t x, int32_t y) const {
    for (int e = 0; e < 3; ++e) {
      if (x == vx_[e] && y == vy_[e]) return true;
    }
    return false;
  }
  // Whether (x, y) is the pixel of a vertex on the triangle's first or last row.
  bool is_end_vertex(int32_t x, int32_t y) const {
    for (int e = 0; e < 3; ++e) {
      if (end_[e] && x == vx_[e] && y == vy_[e]) return true;
    }
    return false;
  }
  uint64_t reads() const { return reads_; }
  uint64_t words() const { return words_.size(); }

 private:
  size_t index(int32_t x, int32_t y) const {
    return static_cast<size_t>(y - y0_) * static_cast<size_t>(x1_ - x0_ + 1) +
           static_cast<size_t>(x - x0_);
  }
  int32_t x0_ = 0, x1_ = -1, y0_ = 0, y1_ = -1;
  int32_t vx_[3] = {0, 0, 0}, vy_[3] = {0, 0, 0};
  bool end_[3] = {false, false, false};
  std::vector<uint8_t> words_;
  uint64_t reads_ = 0;
};

// Where the parity rule textured other pixels than the seed means (the triangle's inside with
// the top-left rule, and the outline pixels drawn), by row.
struct ParityHazards {
  uint64_t extra_pixels = 0;   // textured by parity, neither inside nor on the outline
  uint64_t missed_pixels = 0;  // inside or on the outline, not textured by parity
  // Rows with a difference, by the first cause found on the row (in this order): a run through
  // a vertex's pixel, a run of hits of two edges away from a vertex (touching edges), a run of 2 or
  // more hits of one edge (an edge along the row), otherwise a crossing with no hit.
  uint64_t vertex_rows = 0, touching_rows = 0, run_rows = 0, missed_crossing_rows = 0;
  ParityHazards& operator+=(const ParityHazards& o);
  uint64_t rows() const { return vertex_rows + touching_rows + run_rows + missed_crossing_rows; }
};

// БКТ with the parity rule over one colour, for one row at a time.
class ParityControl {
 public:
  // Row start: parity even, no run.
  void start_row();
  // The pixel's word (0: background), whether it is the pixel of the first or last row's
  // vertex (БКТ's compare) and of any vertex (for the hazard's cause only); returns whether it
  // is textured. end_of_row() tells after it whether the row is done.
  bool on_pixel(uint8_t word, bool end_vertex, bool vertex);
  bool end_of_row() const { return end_of_row_; }
  // Causes seen on this row so far (for ParityHazards).
  bool saw_vertex_run() const { return saw_vertex_; }
  bool saw_touching_run() const { return saw_touching_; }
  bool saw_long_run() const { return saw_long_; }
  uint64_t crossings() const { return crossings_; }

  // Item: one pixel (hit test, run end, parity toggle, texture enable).
  OpCounts ops_per_item() const;

 private:
  void close_run();
  bool odd_ = false, in_run_ = false, textured_ = false, end_of_row_ = false;
  bool run_vertex_ = false, run_any_vertex_ = false;
  uint8_t run_edges_ = 0;
  int run_len_ = 0;
  bool saw_vertex_ = false, saw_touching_ = false, saw_long_ = false;
  uint64_t crossings_ = 0;
};

}  // namespace texsim
