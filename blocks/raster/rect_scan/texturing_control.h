#pragma once
// TexturingControl: the texturing-control block БКТ of the rectangle-scan rasteriser (seed 002,
// fig. 4; docs/rasterizers.md §2). Loaded with the triangle's vertices (as the edge set-up of
// EdgeRasterizer) during preparation. Per row it takes the side of the row's first pixel for
// each edge; per pixel it toggles an edge's flag on each comparator hit of that edge's plane
// (the parity rule, kept per edge so that a run of hits, a missed diagonal or a lone vertex
// cannot upset it) and enables texturing while all three flags say inside. End of row: an edge
// along which every step of the row moves outward (or not at all) is outside: no later pixel of
// the row can be inside. End of triangle: the row index passes the last row the vertices reach.
#include <array>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/rect_scan/line_stepper.h"

namespace texsim {

class ConfigReader;

// Which pixels of a row are textured:
//  TopLeft: pixel centres inside with the top-left rule (the edge-function rasteriser's set):
//           triangles sharing an edge never share a pixel.
//  Outline: the seed's convention, the outline included: also the first pixel after each inside
//           run (where the row crosses out through the outline). Shared edges are drawn twice.
//  OutlineParity: the seed's datapath taken literally (seed_outline.h): one-colour 8-connected
//           outline and the parity rule; its pixels differ from Outline's at its hazards.
enum class RectScanCoverage { TopLeft, Outline, OutlineParity };

class TexturingControl {
 public:
  struct Config {
    static Config from_toml(const ConfigReader& r);
  };
  struct Decision {
    bool texture = false;
    bool end_of_row = false;
  };

  // Preparation: the triangle, the row line, the scissor's minor range, the convention.
  void load(const EdgeRasterizer::Setup& st, const RowLine& line, int32_t minor_lo,
            int32_t minor_hi, RectScanCoverage coverage);
  // Row start at (major0, minor0): the flags take the sides of that pixel.
  Decision start_row(int32_t major0, int32_t minor0);
  // A later pixel of the row with the comparator's hit planes.
  Decision on_pixel(uint8_t hits, int32_t major, int32_t minor);

  uint64_t crossings() const { return crossings_; }      // flag toggles
  uint64_t vertex_hits() const { return vertex_hits_; }  // visits of a vertex's pixel
  bool closing(int e) const { return closing_[e]; }

  // Item: one pixel (decision, end-of-row test, scissor test); per row: three edge values
  // stepped and three sides taken, the end-of-triangle compare.
  OpCounts ops_per_item() const;
  OpCounts row_ops() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.rect_scan.texturing_control"; }
  std::string arithmetic() const {
    return "int64 edge values at row starts (EdgeRasterizer set-up), 3 flags";
  }

 private:
  Decision decide(int32_t minor);
  const EdgeRasterizer::Setup* st_ = nullptr;
  RowLine line_{};
  int32_t minor_lo_ = 0, minor_hi_ = -1;
  RectScanCoverage coverage_ = RectScanCoverage::TopLeft;
  std::array<bool, 3> inside_{}, closing_{};
  std::array<int32_t, 3> vx_{}, vy_{};  // the vertices' pixels
  bool was_inside_ = false;
  uint64_t crossings_ = 0, vertex_hits_ = 0;
};

}  // namespace texsim
