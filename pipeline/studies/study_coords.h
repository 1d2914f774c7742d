#pragma once
// `texsim study coords`: every texture-coordinate method and derivative/ellipse method in every
// number format over planes from screen-parallel to grazing: error in texels against the
// long double map, ops per pixel by kind, cycles per pixel from the clocked pipeline, and the
// seeds' claims re-measured (docs/studies/study-coords.md explains the set-up and the results).
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/geometry/projective_map.h"
#include "pipeline/texture/coord_method.h"

namespace texsim {

struct StudyCoordsOptions {
  int32_t width = 512, height = 512;  // viewport; camera focal 256 px (90° field of view)
  std::vector<double> tilts = {0, 30, 60, 75, 85, 89, 89.9};
  double azimuth_deg = 20;           // tilt axis direction: G and H both non-zero
  double plane_texels = 4096;        // the textured quad is plane_texels² texels
  int tiles = 16;                    // the quad is a mesh of tiles×tiles quads (2 triangles each)
  double z_near = 0.1, z_far = 150;  // clip distances (units of the view-axis distance)
  std::vector<std::string> coord_methods;  // empty = all
  std::vector<std::string> deriv_methods;  // empty = all
  std::vector<std::string> formats;        // empty = all
  // Cycles of the texel fetch + filter stage after the coordinate stage, per pixel (ii) and
  // latency; the first is used in the tables, all of them in the +26 % claim sweep.
  std::vector<uint32_t> filter_ii = {1, 4, 8};
  std::vector<int> lane_counts = {1, 2, 4, 8, 16};  // the lane sweep (empty: none)
  uint32_t filter_latency = 8;
  uint32_t max_aniso = 16;  // EWA stage: anisotropy clamp of the texel-count model
  int threads = 0;          // worker threads (0: one per core); results do not depend on it
};

// A study plane: the quad clipped to [z_near, z_far], fan-triangulated and rasterized.
struct StudyPlane {
  double tilt = 0;
  ProjectiveMap map;
  std::vector<CoordTriangle> tris;
  uint64_t pixels = 0;
  uint64_t rows = 0;  // horizontal raster rows summed over triangles (the seed's q)
};
StudyPlane make_study_plane(const StudyCoordsOptions& o, double tilt);

// EWA texels scanned for a footprint (mip level at the minor axis, anisotropy clamp).
uint32_t ewa_texels(const DerivsL& d, uint32_t max_aniso);

struct CoordStudyRow {
  double tilt = 0;
  std::string method, format;
  uint64_t pixels = 0, rejected = 0;
  double max_err = 0, mean_err = 0;  // texels, max of |Δu|, |Δv| per pixel
  // The same in pixels: the error divided by the pixel's footprint size (texels per pixel,
  // max of |∂(u,v)/∂x| and |∂(u,v)/∂y|): how far the sample moves on the screen.
  double max_err_px = 0, mean_err_px = 0;
  OpCounts ops;  // total over the plane (set-ups included)
  uint64_t rows = 0, triangles = 0, divisions = 0;
  // Cycles per pixel in [coords -> filter], for each filter ii of the options.
  std::vector<double> cpp_spatial, cpp_shared;
};

struct DerivStudyRow {
  double tilt = 0;
  std::string method, ellipse, format;
  uint64_t pixels = 0, rejected = 0;
  double max_rel_true = 0, mean_rel_true = 0;        // vs the analytic derivative
  double max_rel_own = 0;                            // vs the exact value of the method's formula
  double max_rel_ellipse = 0, mean_rel_ellipse = 0;  // normalised A/F, B/F, C/F vs exact
  uint64_t ellipse_rejected = 0;
  OpCounts ops;  // derivative + ellipse blocks, total over the plane
  // Cycles per pixel of [incremental coords -> derivs -> ellipse -> EWA filter]:
  double cpp_spatial = 0, cpp_shared = 0;
  double cpp_fused = 0;  // the whole front end on one shared ALU set (a shader-like core)
};

// The thesis varied the number of parallel lanes ("GPU cores"): the k-lane and direct-n
// incremental forms at each lane count, on the reference tilt's plane.
struct LaneSweepRow {
  std::string method;
  int lanes = 1;
  double cpp_unit_spatial = 0, cpp_unit_shared = 0;  // the coordinate stage alone
  double cpp_spatial = 0;                            // [coords -> filter of II 1]
  double area = 0;                                   // adder equivalents, spatial datapath
  double max_err_float = 0;                          // texels, float
};

struct StudyCoordsResult {
  std::vector<StudyPlane> planes;  // rows/triangles only (maps and counts)
  std::vector<LaneSweepRow> lanes;
  std::vector<CoordStudyRow> coords;
  std::vector<DerivStudyRow> derivs;
};

StudyCoordsResult measure_study_coords(const StudyCoordsOptions& o, std::ostream* log);
// Markdown report (tables and the claims) and CSV of a result.
std::string study_coords_markdown(const StudyCoordsOptions& o, const StudyCoordsResult& r);
std::string study_coords_csv(const StudyCoordsOptions& o, const StudyCoordsResult& r);

// Writes coords.csv, coords.md and coords.png into out_dir (atomically). Returns 0.
int run_study_coords(const std::string& out_dir, std::ostream& log, int threads = 0);

}  // namespace texsim
