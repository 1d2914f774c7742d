#pragma once
// `texsim study formats`: texel storage formats and block compression on shipped scenes, with
// the ground truth. Each row is one run: a scene and a list of `--set` overrides on top of a
// fixed base (one unit, 16 KB 4-way L1 of 64-byte lines, tiled4x4 texels, row raster order,
// flat DRAM). Sweeps: every texture of the scene in one variant (rgba8, rgb565, rgba4444,
// srgb8_a8 decoded before or after the filter, rgba16f, BC1 and BC3 from squish and nvtt, BC7
// and ETC2 RGB8 from texsim's encoders, ASTC 4x4
// … 12x12 from astcenc); the decoder's place (before the L1, after the L1, after an L2 of 256 KB)
// for BC1 and ASTC 6x6. Per row: PSNR against the truth (the texture as loaded), bytes per fragment
// into the L1, into the L2 and from DRAM, cycles, energy, the decoder's area and energy
// (docs/studies/study-formats.md).
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace texsim {

struct StudyFormatsOptions {
  // Scene files; empty: photo and cube (--quick: photo only).
  std::vector<std::string> scenes;
  bool quick = false;  // a few rows on photo at 96x64 (a CI check, about a second)
  // The scenes' output size for the study (0: 240x160; --quick: 96x64).
  int width = 0, height = 0;
  int threads = 0;  // runs in parallel (0: one per core); the outputs do not depend on it
};

struct FormatsStudyRow {
  // The plan.
  std::string scene;  // short name: "photo", "cube", ...
  std::string scene_path;
  std::string sweep;    // "variants" or "placement"
  std::string variant;  // "rgba8", "srgb8_a8 after_filter", "bc1_rgb squish range", ...
  std::string format;   // storage or compressed format name
  bool compressed = false;
  std::string placement;                   // [pipeline] decompress ("" for uncompressed rows)
  std::map<std::string, std::string> set;  // every override of the run (base and row)
  // The run's figures (report.json).
  uint64_t fragments = 0, cycles = 0;
  double psnr_db = 0;
  uint64_t l1_accesses = 0, l1_hits = 0, l1_fill_bytes = 0;
  double l1_hit_rate = 0;
  bool has_l2 = false;
  uint64_t l2_accesses = 0, l2_fill_bytes = 0;
  double l2_hit_rate = 0;
  uint64_t dram_bytes = 0;
  double energy_pj = 0;  // per fragment, every block and memory level
  // The decoder (blocks.decode.<format>), compressed rows only.
  uint64_t blocks_decoded = 0;
  double decoder_ops_per_block = 0;
  int decoder_latency = 0, decoder_ii = 0;
  double decoder_area = 0;
  double decoder_pj = 0;  // per fragment
  // The sRGB decoder (blocks.srgb_decode), srgb8_a8 rows only: its placement ("before_filter",
  // "after_filter"), decodes (texels or fragments) and operations over the run, area, energy.
  std::string srgb_placement;
  uint64_t srgb_decodes = 0, srgb_ops = 0;
  double srgb_area = 0;
  double srgb_pj = 0;  // per fragment

  std::vector<std::string> overrides() const;  // KEY=VALUE, in key order
  double per_fragment(double v) const { return fragments ? v / static_cast<double>(fragments) : 0; }
};

// The rows to run, in table order (no figures yet).
std::vector<FormatsStudyRow> formats_study_plan(const StudyFormatsOptions& opt);

// Runs every row (on the study pool), writes formats.csv, formats.md and the plots into
// out_dir; returns 0. With `rows` set, the measured rows are copied there.
int run_study_formats(const std::string& out_dir, std::ostream& log, const StudyFormatsOptions& opt,
                      std::vector<FormatsStudyRow>* rows = nullptr);

}  // namespace texsim
