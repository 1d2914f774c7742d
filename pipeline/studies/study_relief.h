#pragma once
// `texsim study relief`: the relief methods of the texture unit (docs/derivations/relief.md)
// at grazing views — offset parallax, steep/relief parallax at several layer counts, sphere
// tracing with the classic and the refined distance maps at several iteration caps — as
// iterations, fetches and cycles per fragment against the error of the found surface point
// (texels) and of the colour read there, both against a high-iteration reference; and the
// visibility-aware anisotropic filter against plain EWA as extra reads and cycles, with the
// colour difference against a fine-trace reference. Maps: the relief wall's asteroid height
// map (glmark2-data, box-filtered to the study's size) and a procedural map with sharp height
// changes.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace texsim {

struct ReliefStudyOptions {
  int32_t size = 64;               // height-map texels per side
  int32_t fragments = 400;         // fragments per map and view elevation
  int32_t filter_fragments = 150;  // footprints per map and elevation (filter part)
  bool use_files = true;  // false: procedural maps only (no glmark2-data; used by the tests)
  std::vector<double> elevations_deg{15, 30, 50};  // view above the surface
};

struct ReliefStudyRow {
  std::string map, method;
  double elevation_deg = 0;
  uint32_t fragments = 0;
  double iterations = 0, fetches = 0, cycles = 0;  // means per fragment
  double err_texels = 0;                           // mean distance to the reference point
  double far_fraction = 0;                         // fragments > 1 texel from it
  double colour_err = 0;  // mean |colour - reference colour| per channel (RGB in [0, 1])
  double capped = 0;      // fragments that hit the iteration cap
  double missed = 0;      // sphere tracing: rays that left the volume
};

struct ReliefFilterRow {
  std::string map;
  double elevation_deg = 0;
  uint32_t footprints = 0;
  double texels = 0;                       // footprint texels per lookup (plain EWA reads)
  double reads_rule = 0, reads_exact = 0;  // reads per lookup with visibility (colour + trace)
  double cycles_plain = 0, cycles_rule = 0, cycles_exact = 0;
  double err_plain = 0, err_rule = 0, err_exact = 0;  // mean colour error vs the reference
  double hidden = 0;                                  // fraction of texels hidden (reference)
};

// The footprint after the shift (docs/derivations/relief-footprint.md): the derivatives LOD
// gets — unshifted, analytic or quad differences — against the reference's, which are the
// centred differences of the reference surface point across one pixel.
struct ReliefFootprintRow {
  std::string map, method, footprint;
  double elevation_deg = 0;
  uint32_t fragments = 0;
  double lod_err = 0;    // mean |LOD − reference LOD|, levels (LOD: log2 of the longer axis)
  double lod_far = 0;    // share of fragments more than half a level off
  double axis_err = 0;   // mean |J·d − J_ref·d| / |J_ref·d| over the two pixel axes
  double ops = 0;        // operations per fragment of the derivatives (not the lanes' shifts)
  uint32_t latency = 0;  // cycles the derivatives add to the relief stage
};

struct ReliefStudy {
  std::vector<ReliefStudyRow> rows;
  std::vector<ReliefFilterRow> filter;
  std::vector<ReliefFootprintRow> footprint;
  std::vector<std::string> notes;  // maps and textures used or missing
};

ReliefStudy measure_relief_study(const ReliefStudyOptions& opt);
int run_study_relief(const std::string& out_dir, std::ostream& log);
// The same with other options (a short run for tests).
int run_study_relief(const std::string& out_dir, std::ostream& log, const ReliefStudyOptions& opt);

}  // namespace texsim
