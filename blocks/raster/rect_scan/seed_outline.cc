#include "blocks/raster/rect_scan/seed_outline.h"

#include <algorithm>
#include <cstdlib>

namespace texsim {

namespace {

// A snapped coordinate (units of 2^-bits pixel) rounded to the nearest pixel, ties up.
int32_t to_pixel(int64_t v, int bits) {
  if (bits == 0) return static_cast<int32_t>(v);
  return static_cast<int32_t>((v + (int64_t{1} << (bits - 1))) >> bits);
}

}  // namespace

uint64_t SeedOutlineMemory::draw(const EdgeRasterizer::Setup& st, const RowLine& line,
                                 int32_t major0) {
  int64_t row[3];
  for (int e = 0; e < 3; ++e) {
    vx_[e] = to_pixel(st.vx[e], st.bits);
    vy_[e] = to_pixel(st.vy[e], st.bits);
    const int32_t major = line.x_major ? vx_[e] : vy_[e], minor = line.x_major ? vy_[e] : vx_[e];
    row[e] = minor - line.offset(int64_t{major} - major0);  // the digital row through it
  }
  const int64_t first = std::min({row[0], row[1], row[2]});
  const int64_t last = std::max({row[0], row[1], row[2]});
  for (int e = 0; e < 3; ++e) end_[e] = row[e] == first || row[e] == last;
  // The window: the vertices' pixels within the scanned box (grown by one pixel), so that a
  // triangle far larger than the scissor needs no memory beyond it.
  x0_ = std::max(std::min({vx_[0], vx_[1], vx_[2]}), st.x0 - 1);
  x1_ = std::min(std::max({vx_[0], vx_[1], vx_[2]}), st.x1 + 1);
  y0_ = std::max(std::min({vy_[0], vy_[1], vy_[2]}), st.y0 - 1);
  y1_ = std::min(std::max({vy_[0], vy_[1], vy_[2]}), st.y1 + 1);
  if (x1_ < x0_ || y1_ < y0_) {
    words_.clear();
    x1_ = x0_ - 1;
    return 0;
  }
  words_.assign(static_cast<size_t>(x1_ - x0_ + 1) * static_cast<size_t>(y1_ - y0_ + 1), 0);
  uint64_t writes = 0;
  // Edge e from vertex e+1 to vertex e+2 (EdgeRasterizer's numbering), 8-connected Bresenham.
  for (int e = 0; e < 3; ++e) {
    int32_t x = vx_[(e + 1) % 3], y = vy_[(e + 1) % 3];
    const int32_t xe = vx_[(e + 2) % 3], ye = vy_[(e + 2) % 3];
    const int64_t dx = std::abs(int64_t{xe} - x), dy = -std::abs(int64_t{ye} - y);
    const int32_t sx = x < xe ? 1 : -1, sy = y < ye ? 1 : -1;
    int64_t err = dx + dy;
    for (;;) {
      if (x >= x0_ && x <= x1_ && y >= y0_ && y <= y1_) {
        words_[index(x, y)] |= static_cast<uint8_t>(1u << e);
        ++writes;
      }
      if (x == xe && y == ye) break;
      const int64_t e2 = 2 * err;
      if (e2 >= dy) {
        err += dy;
        x += sx;
      }
      if (e2 <= dx) {
        err += dx;
        y += sy;
      }
    }
  }
  return writes;
}

ParityHazards& ParityHazards::operator+=(const ParityHazards& o) {
  extra_pixels += o.extra_pixels;
  missed_pixels += o.missed_pixels;
  vertex_rows += o.vertex_rows;
  touching_rows += o.touching_rows;
  run_rows += o.run_rows;
  missed_crossing_rows += o.missed_crossing_rows;
  return *this;
}

void ParityControl::start_row() {
  odd_ = in_run_ = textured_ = end_of_row_ = false;
  run_vertex_ = run_any_vertex_ = false;
  run_edges_ = 0;
  run_len_ = 0;
  saw_vertex_ = saw_touching_ = saw_long_ = false;
}

void ParityControl::close_run() {
  // One crossing per run; a vertex's run counts two (the seed: a row touching a vertex only
  // has an even count).
  if (!run_vertex_) {
    odd_ = !odd_;
    ++crossings_;
  }
  saw_vertex_ = saw_vertex_ || run_any_vertex_;
  const bool two_edges = (run_edges_ & (run_edges_ - 1)) != 0;
  saw_touching_ = saw_touching_ || (two_edges && !run_any_vertex_);
  saw_long_ = saw_long_ || run_len_ >= 2;
  in_run_ = false;
  run_vertex_ = run_any_vertex_ = false;
  run_edges_ = 0;
  run_len_ = 0;
}

bool ParityControl::on_pixel(uint8_t word, bool end_vertex, bool vertex) {
  if (word != 0) {  // БП: the word equals РГп (one colour)
    in_run_ = true;
    run_vertex_ = run_vertex_ || end_vertex;
    run_any_vertex_ = run_any_vertex_ || vertex;
    run_edges_ = static_cast<uint8_t>(run_edges_ | word);
    ++run_len_;
    textured_ = true;
    return true;  // the outline is drawn
  }
  if (in_run_) {
    close_run();
    end_of_row_ = textured_ && !odd_;
  }
  textured_ = textured_ || odd_;
  return odd_;
}

OpCounts ParityControl::ops_per_item() const {
  OpCounts o;
  o.cmp = 3;  // hit, run end, vertex compare
  return o;
}

}  // namespace texsim
