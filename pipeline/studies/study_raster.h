#pragma once
// `texsim study raster`: what the rectangle-scan rasteriser's digital rows cost in accuracy and
// what they save (issue "Geometry and rasterisation", docs/rasterizers.md §5). On a 512 × 512
// view of a textured plane at tilts from screen-parallel to grazing and two azimuths, the
// screen (two triangles) is drawn by (a) the edge-function rasteriser feeding exact Heckbert
// coordinates (one division per pixel: the reference) and (b) the rectangle scan whose rows
// are digital lines of constant depth driving the constant-depth coordinate block (one
// reciprocal per row). Per configuration: pixels, divisions, cycles at each clock, and the
// coordinate error of (b) against (a) at the pixel centres, in texels and in pixels of
// minor-axis offset.
#include <ostream>
#include <string>
#include <vector>

namespace texsim {

struct RasterStudyRow {
  double tilt_deg = 0, azimuth_deg = 0;
  uint64_t pixels =
      0;  // = Heckbert divisions (one per pixel)              // covered pixels (the whole screen)
  uint64_t compared = 0;      // of them, in front of the horizon band (q >= 1/64)
  uint64_t edge_visited = 0;  // edge rasteriser: bounding-box pixels (one per cycle)
  uint64_t rows = 0;          // rectangle scan: textured rows = reciprocals
  uint64_t fast_cycles = 0, memory_cycles = 0;
  double edge_time_ns = 0, rect_time_ns = 0;
  double mean_err_texels = 0, max_err_texels = 0;  // digital rows against exact Heckbert
  // The same in pixels of minor-axis offset (error / the map's derivative across the rows).
  double mean_err_minor_px = 0, max_err_minor_px = 0;
};

std::vector<RasterStudyRow> measure_raster_study();
int run_study_raster(const std::string& out_dir, std::ostream& log);

}  // namespace texsim
