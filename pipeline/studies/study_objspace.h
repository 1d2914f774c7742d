#pragma once
// `texsim study objspace`: object-space texturing (rotate each polygon parallel to the screen,
// texture it with one LOD per polygon, project and splat: docs/derivations/object-space.md)
// against screen-space rasterisation with trilinear filtering and with the anisotropic filters
// (Vulkan probes, EWA, Feline), on the same scenes: cycles per frame, operations by kind,
// texels fetched, memory traffic, holes and image error against the ground truth. Sweeps:
// screen resolution (default scene: the oblique floor; the textured cube; the bunny mesh),
// polygon tilt 0°…85° (one square), polygon count (the same square cut into a grid of
// triangles), polygon area, grid step, and the depth bands against the thesis's one LOD per
// polygon. The thesis's claims are re-measured as cycles.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "pipeline/report/image_metrics.h"
#include "pipeline/studies/shipped_scenes.h"

namespace texsim {

struct ObjspaceStudyOptions {
  std::vector<int> widths = {160, 320, 640};  // resolution sweep (height = 3/4 width)
  std::vector<double> tilts = {0, 15, 30, 45, 60, 75, 85};
  int tilt_size = 256;                           // image of the tilt, count and area sweeps
  std::vector<int> grid_cells = {1, 4, 16, 64};  // count sweep: 2·n² triangles
  std::vector<double> areas = {0.5, 1, 2, 4};    // area sweep: the square's area (units²)
  // Density sweep (floor, 320 × 240): object space with a coarser grid step than the hole-free
  // 3/4 pixel, to show what the sample density costs and what leaving holes would save.
  std::vector<double> steps = {1.0, 1.5, 2.0, 3.0};
  // Band sweep (floor, bands_width × 3/4 of it): object space with these band ratios instead of the
  // default 2; 0 is the thesis's one LOD and one grid step per polygon.
  std::vector<double> band_ratios = {0.0};
  int bands_width = 320;  // its image width (height = 3/4 width)
  // Lane sweep (floor, lanes_width × 3/4 of it): object space with each block of the variant
  // (rotation, grid walk, projection, splat) `lanes` wide — the thesis's number of "GPU
  // cores"; the texture unit stays one (empty: no sweep).
  std::vector<int> lane_counts = {1, 2, 4, 8, 16};
  int lanes_width = 320;
  bool cube = true, mesh = true;                  // scenes/cube.toml, scenes/bunny.toml
  std::string scenes_dir = shipped_scenes_dir();  // the shipped scenes (shipped_scenes.h)
  int reference_supersamples = 4;                 // per axis, per pixel
  bool images = true;                             // side-by-side images of the scenes
};

struct ObjspaceRow {
  std::string sweep;   // "resolution", "tilt", "count", "area", "density", "bands", "lanes"
  std::string scene;   // "floor", "cube", "bunny", "square"
  std::string method;  // "object-space", "trilinear", "vulkan", "ewa", "feline"
  int width = 0, height = 0;
  double tilt_deg = -1, area = 0;  // -1: not a tilt sweep
  double step_px = 0.75;           // object space's grid step on the screen at most
  double band_ratio = 2.0;         // object space's far/near depth ratio per band (0: one band)
  uint64_t bands = 0;              // object space's depth bands (grid steps and LODs)
  int lanes = 1;                   // object space's lanes per block
  double block_area = 0;  // object space: its four blocks' area (adder equivalents), else 0
  // Object space: the texture unit's cycles, and the slowest of the lane-wide stages (grid
  // walk, projection, splat); the frame is the larger plus set-up and resolve.
  uint64_t texture_cycles = 0, lane_cycles = 0;
  uint64_t primitives = 0;
  uint64_t pixels = 0;  // covered pixels (screen-space coverage)
  uint64_t items = 0;   // fragments (screen space) or samples (object space)
  uint64_t cycles = 0;  // per frame
  OpCounts ops;
  uint64_t texels = 0, dram_bytes = 0, buffer_bytes = 0, holes = 0;
  AccuracyMetrics acc;
};

std::vector<ObjspaceRow> measure_objspace_study(const ObjspaceStudyOptions& opt,
                                                const std::string& image_dir, std::ostream& log);
int run_study_objspace(const std::string& out_dir, std::ostream& log);
int run_study_objspace(const std::string& out_dir, std::ostream& log,
                       const ObjspaceStudyOptions& opt);

}  // namespace texsim
