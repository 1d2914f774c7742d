// Every figure report.json holds is checked here against its definition, recomputed in the test
// from the primary counts of the same report (or from the run's own images): rates, per-fragment
// figures, sums over blocks, materials and frames, bytes from lines, times from cycles at the
// clock, PSNR from the MSE, the ledger's deltas. A report key the test does not know fails the
// test, so a new figure cannot go unchecked (add it to kKnownKeys and check its definition;
// docs/reports.md "Figures and their checks" lists where each one is checked). The runs are
// small scenes run in-process (no binary spawned) so the whole file takes a few seconds.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "pipeline/app/run.h"
#include "pipeline/app/sweep.h"
#include "testbench/lib/temp_dir.h"

namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

const std::string kScenes = std::string(TEXSIM_SOURCE_DIR) + "/scenes/";

// Every key report.json may hold: named entries (blocks, stages, materials, raster, ledger, the
// object-space op groups) are `*`, operator kinds `<op>`, array elements `[]`.
const std::set<std::string> kKnownKeys = {
    "scene", "trace", "mode", "fragments", "cycles", "cycles_per_fragment", "image", "image.width",
    "image.height", "image.frame", "textures",
    // blocks
    "blocks", "blocks.*", "blocks.*.ops", "blocks.*.ops.<op>", "blocks.*.ops_per_fragment",
    "blocks.*.latency", "blocks.*.ii", "blocks.*.area", "blocks.*.arithmetic", "blocks.*.materials",
    "blocks.*.texels", "blocks.*.texels_per_fragment", "blocks.*.border_taps",
    // stages
    "stages", "stages.*", "stages.*.latency", "stages.*.busy", "stages.*.utilisation",
    "stages.*.stalls", "stages.*.stalls.starved", "stages.*.stalls.blocked",
    "stages.*.stalls.latency_full", "stages.*.stalls.multi_cycle",
    // memory
    "cache", "cache.hits", "cache.misses", "cache.accesses", "cache.hit_rate", "cache.texel_reads",
    "cache.fill_bytes", "cache.size_bytes", "cache.ways", "cache.line_bytes", "dram",
    "dram.requests", "dram.bytes", "dram.busy_cycles", "dram.model", "dram.channels", "dram.banks",
    "dram.row_hits", "dram.row_empty", "dram.row_conflicts", "dram.row_hit_rate",
    "dram.activations", "dram.bank_wait_cycles", "dram.channel_busy_cycles", "l2", "l2.accesses",
    "l2.hits", "l2.misses", "l2.hit_rate", "l2.mshr_merges", "l2.mshr_stalls",
    "l2.mshr_stall_cycles", "l2.bank_conflicts", "l2.bank_conflict_cycles", "l2.prefetches_issued",
    "l2.prefetches_useful", "l2.fill_bytes", "l2.size_bytes", "l2.ways", "l2.line_bytes",
    "l2.slices",
    // several units, quads, energy
    "units", "units[].unit", "units[].fragments", "units[].cycles", "units[].l1",
    "units[].l1.accesses", "units[].l1.hits", "units[].l1.misses", "units[].l1.hit_rate",
    "scheduler", "scheduler.forced_commits", "scheduler.late_items", "scheduler.local_commits",
    "quads", "quads.derivatives", "quads.merge", "quads.merged_lookups", "quads.quads",
    "quads.helper_lanes", "quads.own_x", "quads.own_y", "energy", "energy.total_pj",
    "energy.per_fragment_pj", "energy.ops_pj", "energy.l1_pj", "energy.l2_pj", "energy.dram_pj",
    "energy.blocks_pj", "energy.blocks_pj.*",
    // block-compressed textures
    "decompress", "decompress.placement", "decompress.blocks_decoded",
    "decompress.blocks_by_format", "decompress.blocks_by_format.*", "decompress.decoded_lines",
    "decompress.compressed_reads", "srgb_decode", "srgb_decode.placement", "srgb_decode.fragments",
    "srgb_decode.texels", "srgb_decode.decodes",
    // frames and accuracy
    "frames", "frames[].frame", "frames[].fragments", "frames[].cycles_end", "frames[].time_us",
    "frames[].accuracy", "frames[].accuracy.psnr_db", "frames[].accuracy.nmse",
    "frames[].accuracy.max_abs", "frames[].accuracy.mean_abs", "frames[].accuracy.pixels",
    "accuracy", "accuracy.psnr_db", "accuracy.nmse", "accuracy.max_abs", "accuracy.mean_abs",
    "accuracy.mse", "accuracy.pixels", "accuracy.reference", "accuracy.pixel",
    // materials
    "materials", "materials.*", "materials.*.fragments", "materials.*.blocks", "materials.*.ops",
    "materials.*.ops.<op>", "materials.*.ops_per_fragment", "materials.*.texels_per_fragment",
    "materials.*.arithmetic", "board", "board.link", "board.blocks", "board.fragments",
    "board.streams", "board.lerps", "materials.*.operations", "materials.*.operations.*",
    "materials.*.operations.*.fragments", "materials.*.operations.*.taps_per_fragment",
    "materials.*.operations.*.ops_per_fragment",
    "materials.*.operations.*.issue_cycles_per_fragment", "materials.*.relief",
    "materials.*.relief.steps", "materials.*.relief.fetches",
    "materials.*.relief.steps_per_fragment", "materials.*.relief.fetches_per_fragment",
    "materials.*.accuracy", "materials.*.accuracy.psnr_db", "materials.*.accuracy.nmse",
    "materials.*.accuracy.max_abs", "materials.*.accuracy.mean_abs", "materials.*.accuracy.pixels",
    // object space (per material and the frame)
    "materials.*.object_space", "materials.*.object_space.max_step_px",
    "materials.*.object_space.band_ratio", "materials.*.object_space.lanes",
    "materials.*.object_space.primitives", "materials.*.object_space.culled",
    "materials.*.object_space.clipped_away", "materials.*.object_space.edge_on",
    "materials.*.object_space.degenerate", "materials.*.object_space.bands",
    "materials.*.object_space.lod_mean", "materials.*.object_space.samples",
    "materials.*.object_space.grid_samples", "materials.*.object_space.edge_samples",
    "materials.*.object_space.pixels_shown", "materials.*.object_space.samples_per_pixel",
    "materials.*.object_space.cycles", "materials.*.object_space.cycles.total",
    "materials.*.object_space.cycles.texture", "materials.*.object_space.cycles.raster",
    "materials.*.object_space.cycles.projection", "materials.*.object_space.cycles.splat",
    "materials.*.object_space.cycles.setup", "materials.*.object_space.cycles.resolve",
    "materials.*.object_space.ops", "materials.*.object_space.ops.*",
    "materials.*.object_space.ops.*.<op>", "materials.*.object_space.texels",
    "materials.*.object_space.cache", "materials.*.object_space.cache.hits",
    "materials.*.object_space.cache.misses", "materials.*.object_space.cache.accesses",
    "materials.*.object_space.cache.fill_bytes", "materials.*.object_space.dram_bytes",
    "materials.*.object_space.splat_buffer",
    "materials.*.object_space.splat_buffer.splat_read_bytes",
    "materials.*.object_space.splat_buffer.splat_written_bytes",
    "materials.*.object_space.splat_buffer.resolve_read_bytes",
    "materials.*.object_space.splat_buffer.resolve_written_bytes",
    "materials.*.object_space.splat_buffer.bytes", "materials.*.object_space.splat_buffer.targets",
    "materials.*.object_space.splat_buffer.offscreen",
    "materials.*.object_space.splat_buffer.depth_resets",
    "materials.*.object_space.splat_buffer.depth_dropped", "materials.*.object_space.holes",
    "materials.*.object_space.holes.covered", "materials.*.object_space.holes.holes",
    "materials.*.object_space.holes.shown", "object_space", "object_space.materials",
    "object_space.cycles", "object_space.screen_space_cycles", "object_space.frame_cycles",
    "object_space.visibility",
    // front end, geometry, rasterisation
    "front_end", "front_end.generated", "front_end.occluded", "front_end.rejected", "geometry",
    "geometry.block", "geometry.vertices", "geometry.primitives", "geometry.culled_back",
    "geometry.degenerate", "geometry.behind_eye", "geometry.near_clipped",
    "geometry.cull_disagreements", "geometry.cycles", "geometry.time_ns", "geometry.ops",
    "geometry.ops.<op>", "raster", "raster.*", "raster.*.block", "raster.*.primitives",
    "raster.*.triangles", "raster.*.rejected", "raster.*.rows", "raster.*.pixels_visited",
    "raster.*.pixels_covered", "raster.*.quads", "raster.*.helper_lanes", "raster.*.time_ns",
    "raster.*.ops", "raster.*.ops.<op>", "raster.*.divisions", "raster.*.divisions_per_triangle",
    "raster.*.fast_cycles", "raster.*.memory_cycles", "raster.*.cycles", "raster.*.coords",
    "raster.*.coord_pixels", "raster.*.coord_rejected", "raster.*.coord_ops",
    "raster.*.coord_ops.<op>", "raster.*.parity_hazards", "raster.*.parity_hazards.extra_pixels",
    "raster.*.parity_hazards.missed_pixels", "raster.*.parity_hazards.vertex_rows",
    "raster.*.parity_hazards.touching_rows", "raster.*.parity_hazards.run_rows",
    "raster.*.parity_hazards.missed_crossing_rows",
    // physical
    "area_total", "physical", "physical.clock_mhz", "physical.time_us",
    "physical.fragments_per_second",
    // ledger
    "ledger", "ledger.*", "ledger.*.exact", "ledger.*.materials", "ledger.*.ops", "ledger.*.area",
    "ledger.*.alone", "ledger.*.alone.psnr_db", "ledger.*.alone.nmse", "ledger.*.alone.dpsnr_db",
    "ledger.*.alone.dnmse", "ledger.*.alone.pixels_changed", "ledger.*.alone.pixels_changed_pct",
    "ledger.*.alone.dcycles", "ledger.*.all_but", "ledger.*.all_but.psnr_db",
    "ledger.*.all_but.nmse", "ledger.*.all_but.dpsnr_db", "ledger.*.all_but.dnmse",
    "ledger.*.all_but.pixels_changed", "ledger.*.all_but.pixels_changed_pct",
    "ledger.*.all_but.dcycles", "ledger_setup", "ledger_setup.hardware",
    "ledger_setup.hardware.psnr_db", "ledger_setup.hardware.nmse", "ledger_setup.hardware.cycles",
    "ledger_setup.all_exact", "ledger_setup.all_exact.psnr_db", "ledger_setup.all_exact.nmse",
    "ledger_setup.all_exact.cycles", "ledger_setup.pixels", "ledger_setup.change_threshold",
    "ledger_setup.maps",
    // error map
    "error_map", "error_map.scale", "error_map.auto", "error_map.bar_rows", "error_map.ticks",
    // provenance
    "provenance", "provenance.texsim_version", "provenance.command", "provenance.inputs",
    "provenance.inputs[].role", "provenance.inputs[].path", "provenance.inputs[].sha1",
    "provenance.inputs[].bytes", "provenance.pipeline", "provenance.pipeline.fifo_depth",
    "provenance.pipeline.layout", "provenance.pipeline.cache",
    "provenance.pipeline.cache.size_bytes", "provenance.pipeline.cache.ways",
    "provenance.pipeline.cache.line_bytes", "provenance.pipeline.cache.hit_latency",
    "provenance.pipeline.cache.texels_per_cycle", "provenance.pipeline.cache.miss_queue",
    "provenance.pipeline.dram", "provenance.pipeline.dram.latency",
    "provenance.pipeline.dram.bytes_per_cycle", "provenance.pipeline.dram.model",
    "provenance.pipeline.dram.channels", "provenance.pipeline.dram.banks",
    "provenance.pipeline.dram.row_bytes", "provenance.pipeline.dram.interleave_bytes",
    "provenance.pipeline.dram.mapping", "provenance.pipeline.dram.page_policy",
    "provenance.pipeline.dram.tCL", "provenance.pipeline.dram.tRCD", "provenance.pipeline.dram.tRP",
    "provenance.pipeline.dram.tRAS", "provenance.pipeline.dram.burst_length",
    "provenance.pipeline.dram.bus_bytes", "provenance.pipeline.dram.beats_per_cycle",
    "provenance.pipeline.units", "provenance.pipeline.unit_tile", "provenance.pipeline.derivatives",
    "provenance.pipeline.quad_merge", "provenance.pipeline.l2", "provenance.pipeline.l2.size_bytes",
    "provenance.pipeline.l2.ways", "provenance.pipeline.l2.line_bytes",
    "provenance.pipeline.l2.slices", "provenance.pipeline.l2.ports",
    "provenance.pipeline.l2.hit_latency", "provenance.pipeline.l2.mshrs",
    "provenance.pipeline.l2.prefetch", "provenance.tech.energy", "provenance.tech.energy.op",
    "provenance.tech.energy.op.<op>", "provenance.tech.energy.sram",
    "provenance.tech.energy.sram[].capacity_bytes", "provenance.tech.energy.sram[].pj",
    "provenance.tech.energy.sram_access_bytes", "provenance.tech.energy.dram_byte_pj",
    "provenance.tech.energy.dram_activation_pj", "provenance.pipeline.blend",
    "provenance.pipeline.blend.taps_per_cycle", "provenance.tech", "provenance.tech.clock_mhz",
    "provenance.tech.latency", "provenance.tech.latency.<op>", "provenance.tech.area",
    "provenance.tech.area.<op>",
    // workload characterisation
    "workload", "workload.layout", "workload.line_bytes", "workload.lod_lo", "workload.lod_step",
    "workload.aniso_bins", "workload.reuse_line_bytes", "workload.reuse_max_lines",
    "workload.total", "workload.frames", "workload.total.frame", "workload.frames[].frame",
    "workload.total.fragments", "workload.frames[].fragments", "workload.total.quads",
    "workload.frames[].quads", "workload.total.textures", "workload.frames[].textures",
    "workload.total.texels_level0", "workload.frames[].texels_level0", "workload.total.texels_lod",
    "workload.frames[].texels_lod", "workload.total.texels_per_fragment",
    "workload.frames[].texels_per_fragment", "workload.total.footprint_texels_per_fragment",
    "workload.frames[].footprint_texels_per_fragment", "workload.total.lines",
    "workload.frames[].lines", "workload.total.working_set_bytes",
    "workload.frames[].working_set_bytes", "workload.total.lod_under",
    "workload.frames[].lod_under", "workload.total.lod", "workload.frames[].lod",
    "workload.total.lod_over", "workload.frames[].lod_over", "workload.total.aniso",
    "workload.frames[].aniso", "workload.total.magnified", "workload.frames[].magnified",
    "workload.total.minified", "workload.frames[].minified", "workload.total.magnified_share",
    "workload.frames[].magnified_share", "workload.total.line_uses", "workload.frames[].line_uses",
    "workload.total.first_uses", "workload.frames[].first_uses", "workload.total.untracked_uses",
    "workload.frames[].untracked_uses", "workload.total.reuse", "workload.frames[].reuse"};

bool is_op_kind(const std::string& k) {
  return std::any_of(texsim::kOpKindNames.begin(), texsim::kOpKindNames.end(),
                     [&](std::string_view n) { return n == k; });
}

void key_patterns(const Json& j, const std::string& path, std::set<std::string>& out) {
  static const std::set<std::string> named = {"blocks",           "stages",
                                              "materials",        "raster",
                                              "ledger",           "materials.*.object_space.ops",
                                              "energy.blocks_pj", "decompress.blocks_by_format"};
  if (j.is_array()) {
    for (const Json& e : j) key_patterns(e, path + "[]", out);
    return;
  }
  if (!j.is_object()) return;
  const std::string last =
      path.substr(path.rfind('.') == std::string::npos ? 0 : path.rfind('.') + 1);
  for (const auto& [k, v] : j.items()) {
    std::string seg = k;
    if (named.count(path)) seg = "*";
    if (is_op_kind(k) &&
        (last == "ops" || last == "coord_ops" || last == "latency" || last == "area" ||
         last == "op" || path == "materials.*.object_space.ops.*"))
      seg = "<op>";
    std::string sub = path;
    if (!sub.empty()) sub += ".";
    sub += seg;
    out.insert(sub);
    key_patterns(v, sub, out);
  }
}

void expect_known_keys(const Json& r) {
  std::set<std::string> keys;
  key_patterns(r, "", keys);
  for (const std::string& k : keys)
    EXPECT_TRUE(kKnownKeys.count(k)) << "report.json key '" << k
                                     << "' is not checked by test_report_figures: add it to "
                                        "kKnownKeys with a check of its definition";
}

// Relative comparison (the report's doubles round-trip exactly; the test's own arithmetic may
// differ in the last bits from the writer's order of operations).
::testing::AssertionResult same(const char* ea, const char* eb, double a, double b) {
  const double tol = 1e-9 * std::max({1.0, std::abs(a), std::abs(b)});
  if (std::abs(a - b) <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << ea << " = " << std::setprecision(17) << a << ", expected " << eb << " = " << b;
}
#define EXPECT_SAME(a, b) EXPECT_PRED_FORMAT2(same, a, b)

double d(const Json& v) { return v.get<double>(); }
uint64_t u(const Json& v) { return v.get<uint64_t>(); }
double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

uint64_t ops_total(const Json& ops) {
  EXPECT_EQ(ops.size(), texsim::kOpKindNames.size()) << ops.dump();
  uint64_t s = 0;
  for (const auto& [k, v] : ops.items()) s += u(v);
  return s;
}

// --- the checks, one family of figures each ---------------------------------------------------

void check_summary(const Json& r, int width, int height) {
  const double frags = d(r["fragments"]), cycles = d(r["cycles"]);
  EXPECT_SAME(d(r["cycles_per_fragment"]), ratio(cycles, frags));
  EXPECT_EQ(r["image"]["width"].get<int>(), width);
  EXPECT_EQ(r["image"]["height"].get<int>(), height);
  EXPECT_EQ(r["image"].contains("frame"), r["frames"].size() > 1);
  const bool timing = r["mode"] == "timing";
  EXPECT_TRUE(timing || r["mode"] == "functional");
  EXPECT_EQ(timing, r.contains("physical"));
  if (!timing) {
    EXPECT_EQ(u(r["cycles"]), 0u);
    EXPECT_FALSE(r.contains("stages"));
    for (const char* k : {"hits", "misses", "accesses", "texel_reads", "fill_bytes"})
      EXPECT_EQ(u(r["cache"][k]), 0u) << k;
  }
  double area = 0;
  for (const auto& [name, b] : r["blocks"].items()) area += d(b["area"]);
  EXPECT_SAME(d(r["area_total"]), area);
  EXPECT_FALSE(r["textures"].empty());
}

void check_blocks(const Json& r) {
  const double frags = d(r["fragments"]);
  uint64_t filter_texels = 0;
  for (const auto& [name, b] : r["blocks"].items()) {
    EXPECT_SAME(d(b["ops_per_fragment"]), ratio(static_cast<double>(ops_total(b["ops"])), frags))
        << name;
    EXPECT_SAME(d(b["texels_per_fragment"]), ratio(d(b["texels"]), frags)) << name;
    EXPECT_GE(b["latency"].get<int64_t>(), 0) << name;
    EXPECT_GE(b["ii"].get<int64_t>(), 1) << name;
    EXPECT_GE(d(b["area"]), 0.0) << name;
    EXPECT_FALSE(b["materials"].empty()) << name;
    for (const Json& m : b["materials"]) EXPECT_TRUE(r["materials"].contains(m)) << name << m;
    if (name != "cache") filter_texels += u(b["texels"]);
    // Border taps: present only where some tap read the border colour (not counted in texels).
    if (b.contains("border_taps")) {
      EXPECT_GT(u(b["border_taps"]), 0u) << name;
      EXPECT_EQ(name.rfind("filter.", 0), 0u) << name;
    }
  }
  // The cache serves every filter texel, one `mem` op each.
  ASSERT_TRUE(r["blocks"].contains("cache"));
  EXPECT_EQ(u(r["blocks"]["cache"]["texels"]), filter_texels);
  EXPECT_EQ(u(r["blocks"]["cache"]["ops"]["mem"]), filter_texels);
}

// Materials drawn screen space share the unit's blocks: their fragments, operations and texels
// add up to the unit's.
void check_materials(const Json& r) {
  uint64_t frags = 0;
  std::map<std::string, uint64_t> ops;
  double texels = 0;
  for (const auto& [name, m] : r["materials"].items()) {
    const double f = d(m["fragments"]);
    EXPECT_SAME(d(m["ops_per_fragment"]), ratio(static_cast<double>(ops_total(m["ops"])), f))
        << name;
    if (m.contains("relief")) {
      const Json& rl = m["relief"];
      EXPECT_SAME(d(rl["steps_per_fragment"]), ratio(d(rl["steps"]), f)) << name;
      EXPECT_SAME(d(rl["fetches_per_fragment"]), ratio(d(rl["fetches"]), f)) << name;
      EXPECT_GT(u(rl["steps"]), 0u) << name;
    }
    if (m.contains("object_space")) continue;  // check_object_space
    for (const Json& b : m["blocks"]) EXPECT_TRUE(r["blocks"].contains(b)) << name << b;
    frags += u(m["fragments"]);
    for (const auto& [k, v] : m["ops"].items()) ops[k] += u(v);
    texels += d(m["texels_per_fragment"]) * f;
  }
  EXPECT_EQ(frags, u(r["fragments"]));
  std::map<std::string, uint64_t> block_ops;
  uint64_t block_texels = 0;
  for (const auto& [name, b] : r["blocks"].items()) {
    // The materials' blocks exclude the fetch path's: the cache and the texel decoders serve
    // every material's fetches (a decoded line or block serves whichever material reads it).
    if (name == "cache" || name.rfind("decode.", 0) == 0) continue;
    for (const auto& [k, v] : b["ops"].items()) block_ops[k] += u(v);
    block_texels += u(b["texels"]);
  }
  EXPECT_EQ(ops, block_ops);
  EXPECT_NEAR(texels, static_cast<double>(block_texels), 1e-6 * std::max(1.0, texels));
}

void check_stages(const Json& r) {
  if (!r.contains("stages")) return;
  const double cycles = d(r["cycles"]);
  const Json& setup = r["provenance"]["pipeline"];
  const double units = setup.contains("units") ? d(setup["units"]) : 1.0;
  for (const auto& [name, s] : r["stages"].items()) {
    const double busy = d(s["busy"]);
    const Json& st = s["stalls"];
    // utilisation = busy ÷ (cycles × lanes × units), busy and stalls summed over the units; no
    // scene of this test gives a stage more than the default one lane (the report does not
    // list lanes).
    ASSERT_GT(d(s["utilisation"]), 0.0) << name;
    const double lanes = busy / (cycles * d(s["utilisation"]) * units);
    EXPECT_SAME(lanes, 1.0) << name;
    EXPECT_LE(d(s["utilisation"]), 1.0) << name;
    EXPECT_LE(u(st["multi_cycle"]), u(s["busy"])) << name;
    EXPECT_LE(busy + d(st["starved"]) + d(st["blocked"]) + d(st["latency_full"]),
              cycles * lanes * units)
        << name;
    EXPECT_GE(s["latency"].get<int64_t>(), 0) << name;
  }
}

void check_memory(const Json& r) {
  const Json& c = r["cache"];
  const Json& cfg = r["provenance"]["pipeline"];
  const uint64_t hits = u(c["hits"]), misses = u(c["misses"]);
  EXPECT_EQ(u(c["accesses"]), hits + misses);
  EXPECT_SAME(d(c["hit_rate"]), hits + misses > 0
                                    ? static_cast<double>(hits) / static_cast<double>(hits + misses)
                                    : 0.0);
  EXPECT_EQ(u(c["fill_bytes"]), misses * u(c["line_bytes"]));
  for (const char* k : {"size_bytes", "ways", "line_bytes"}) EXPECT_EQ(c[k], cfg["cache"][k]) << k;
  const Json& dr = r["dram"];
  if (!r.contains("l2") && !dr.contains("model")) {  // the flat DRAM right behind the L1s
    EXPECT_EQ(u(dr["requests"]), misses);
    EXPECT_EQ(u(dr["bytes"]), u(c["fill_bytes"]));
    const uint64_t bpc = u(cfg["dram"]["bytes_per_cycle"]);
    EXPECT_EQ(u(dr["busy_cycles"]), misses * ((u(c["line_bytes"]) + bpc - 1) / bpc));
  }
  if (r["mode"] == "timing") {
    EXPECT_EQ(u(c["texel_reads"]), u(r["blocks"]["cache"]["texels"]));
    EXPECT_GT(hits + misses, 0u);
  }
}

// The levels behind the L1s: what each passes on, and its rates.
void check_hierarchy(const Json& r) {
  const Json& c = r["cache"];
  const Json& dr = r["dram"];
  uint64_t dram_lines = u(c["misses"]), dram_line_bytes = u(c["line_bytes"]);
  if (r.contains("l2")) {
    const Json& l = r["l2"];
    EXPECT_EQ(u(l["accesses"]), u(c["misses"]));  // every L1 miss asks the L2
    EXPECT_EQ(u(l["accesses"]), u(l["hits"]) + u(l["misses"]) + u(l["mshr_merges"]));
    EXPECT_SAME(d(l["hit_rate"]), ratio(d(l["hits"]), d(l["accesses"])));
    EXPECT_LE(u(l["prefetches_useful"]), u(l["prefetches_issued"]));
    dram_lines = u(l["misses"]) + u(l["prefetches_issued"]);
    dram_line_bytes = u(l["line_bytes"]);
    EXPECT_EQ(u(l["fill_bytes"]), dram_lines * dram_line_bytes);
    for (const char* k : {"size_bytes", "ways", "line_bytes", "slices"})
      EXPECT_EQ(l[k], r["provenance"]["pipeline"]["l2"][k]) << k;
  }
  EXPECT_EQ(u(dr["requests"]), dram_lines);
  EXPECT_EQ(u(dr["bytes"]), dram_lines * dram_line_bytes);
  if (dr.contains("model")) {
    const uint64_t req = u(dr["requests"]);
    EXPECT_EQ(req, u(dr["row_hits"]) + u(dr["row_empty"]) + u(dr["row_conflicts"]));
    EXPECT_EQ(u(dr["activations"]), u(dr["row_empty"]) + u(dr["row_conflicts"]));
    EXPECT_SAME(d(dr["row_hit_rate"]), ratio(d(dr["row_hits"]), static_cast<double>(req)));
    uint64_t busiest = 0;
    for (const Json& b : dr["channel_busy_cycles"]) busiest = std::max(busiest, u(b));
    EXPECT_EQ(dr["channel_busy_cycles"].size(), u(dr["channels"]));
    EXPECT_EQ(u(dr["busy_cycles"]), busiest);
    EXPECT_LE(busiest, u(r["cycles"]));
  }
}

// Several units: their shares add up to the run's figures, and the order was exact.
void check_units(const Json& r) {
  if (!r.contains("units")) return;
  uint64_t frags = 0, acc = 0, hits = 0, misses = 0, last = 0;
  for (const Json& e : r["units"]) {
    frags += u(e["fragments"]);
    const Json& l = e["l1"];
    EXPECT_EQ(u(l["accesses"]), u(l["hits"]) + u(l["misses"]));
    EXPECT_SAME(d(l["hit_rate"]), ratio(d(l["hits"]), d(l["accesses"])));
    acc += u(l["accesses"]);
    hits += u(l["hits"]);
    misses += u(l["misses"]);
    last = std::max(last, u(e["cycles"]));
  }
  EXPECT_EQ(frags, u(r["fragments"]));
  EXPECT_EQ(acc, u(r["cache"]["accesses"]));
  EXPECT_EQ(hits, u(r["cache"]["hits"]));
  EXPECT_EQ(misses, u(r["cache"]["misses"]));
  EXPECT_EQ(last, u(r["cycles"]));
  EXPECT_EQ(r["units"].size(), u(r["provenance"]["pipeline"]["units"]));
  EXPECT_EQ(u(r["scheduler"]["late_items"]), 0u);
  // Local commits are fragments whose look-ups all hit: never more than the fragments, and a
  // fragment with a miss is not one of them.
  const uint64_t local = u(r["scheduler"]["local_commits"]);
  EXPECT_LE(local, frags);
  if (misses > 0) {
    EXPECT_LT(local, frags);
  }
}

void check_quads(const Json& r) {
  if (!r.contains("quads")) return;
  const Json& q = r["quads"];
  if (!q.contains("quads")) return;
  // Every fragment of the unit came through a quad (no object-space materials here).
  EXPECT_EQ(u(q["helper_lanes"]), 4 * u(q["quads"]) - u(r["fragments"]));
  EXPECT_LE(u(q["own_x"]), u(r["fragments"]));
  EXPECT_LE(u(q["own_y"]), u(r["fragments"]));
}

// An SRAM access's energy from the provenance's classes: linear in log2(capacity) between
// classes, constant outside them, linear in the access width.
double sram_pj(const Json& e, double capacity, double bytes) {
  const Json& cls = e["sram"];
  const double width = bytes / d(e["sram_access_bytes"]);
  if (capacity <= d(cls.front()["capacity_bytes"])) return d(cls.front()["pj"]) * width;
  if (capacity >= d(cls.back()["capacity_bytes"])) return d(cls.back()["pj"]) * width;
  size_t i = 1;
  while (d(cls[i]["capacity_bytes"]) < capacity) ++i;
  const double a = std::log2(d(cls[i - 1]["capacity_bytes"]));
  const double b = std::log2(d(cls[i]["capacity_bytes"]));
  const double t = (std::log2(capacity) - a) / (b - a);
  return (d(cls[i - 1]["pj"]) + t * (d(cls[i]["pj"]) - d(cls[i - 1]["pj"]))) * width;
}

void check_energy(const Json& r) {
  if (r["mode"] != "timing") {
    EXPECT_FALSE(r.contains("energy"));
    return;
  }
  const Json& en = r["energy"];
  const Json& table = r["provenance"]["tech"]["energy"];
  double ops = 0;
  for (const auto& [name, b] : r["blocks"].items()) {
    double pj = 0;
    for (const auto& [k, n] : b["ops"].items()) pj += d(n) * d(table["op"][k]);
    EXPECT_SAME(d(en["blocks_pj"][name]), pj) << name;
    ops += pj;
  }
  EXPECT_SAME(d(en["ops_pj"]), ops);
  const Json& c = r["cache"];
  EXPECT_SAME(d(en["l1_pj"]),
              d(c["texel_reads"]) * sram_pj(table, d(c["size_bytes"]), 4) +
                  d(c["misses"]) * sram_pj(table, d(c["size_bytes"]), d(c["line_bytes"])));
  double l2 = 0;
  if (r.contains("l2")) {
    const Json& l = r["l2"];
    l2 = d(l["accesses"]) * sram_pj(table, d(l["size_bytes"]), d(c["line_bytes"])) +
         (d(l["misses"]) + d(l["prefetches_issued"])) *
             sram_pj(table, d(l["size_bytes"]), d(l["line_bytes"]));
  }
  EXPECT_SAME(d(en["l2_pj"]), l2);
  const double act = r["dram"].contains("activations") ? d(r["dram"]["activations"]) : 0.0;
  EXPECT_SAME(d(en["dram_pj"]), d(r["dram"]["bytes"]) * d(table["dram_byte_pj"]) +
                                    act * d(table["dram_activation_pj"]));
  const double total = d(en["ops_pj"]) + d(en["l1_pj"]) + d(en["l2_pj"]) + d(en["dram_pj"]);
  EXPECT_SAME(d(en["total_pj"]), total);
  EXPECT_SAME(d(en["per_fragment_pj"]), ratio(total, d(r["fragments"])));
}

double mse_of(const Json& a) {
  const double p = d(a["psnr_db"]);
  return p >= 999 ? 0.0 : std::pow(10.0, -p / 10.0);
}

// The accuracy figures of several parts (frames, materials) pool into the whole's.
void check_pooled(const Json& whole, const std::vector<const Json*>& parts, const char* what) {
  uint64_t px = 0;
  double se = 0, sabs = 0, mx = 0;
  for (const Json* a : parts) {
    const auto n = u((*a)["pixels"]);
    px += n;
    se += mse_of(*a) * static_cast<double>(n);
    sabs += d((*a)["mean_abs"]) * static_cast<double>(n);
    mx = std::max(mx, d((*a)["max_abs"]));
  }
  EXPECT_EQ(px, u(whole["pixels"])) << what;
  const double n = static_cast<double>(px);
  EXPECT_NEAR(se / n, d(whole["mse"]), 1e-9 * std::max(1e-12, d(whole["mse"])) + 1e-15) << what;
  EXPECT_SAME(sabs / n, d(whole["mean_abs"])) << what;
  EXPECT_SAME(mx, d(whole["max_abs"])) << what;
}

void check_accuracy(const Json& r) {
  const Json& a = r["accuracy"];
  if (a["psnr_db"].is_null()) return;  // no ground truth (check_no_truth)
  const double mse = d(a["mse"]);
  EXPECT_SAME(d(a["psnr_db"]), mse > 0 ? 10 * std::log10(1 / mse) : 999.0);
  EXPECT_TRUE(a["pixel"] == "box" || a["pixel"] == "gaussian");
  EXPECT_FALSE(a["reference"].get<std::string>().empty());
  std::vector<const Json*> frames, mats;
  for (const Json& f : r["frames"])
    if (f.contains("accuracy")) frames.push_back(&f["accuracy"]);
  for (const auto& [name, m] : r["materials"].items()) mats.push_back(&m["accuracy"]);
  EXPECT_EQ(frames.size(), r["frames"].size());
  check_pooled(a, frames, "frames");
  check_pooled(a, mats, "materials");  // a material's figures pool over every frame too
  // Each part's PSNR from its own error: a part with no pixels has none.
  for (const Json* p : mats) {
    if (u((*p)["pixels"]) == 0) {
      EXPECT_SAME(d((*p)["max_abs"]), 0.0);
    }
  }
}

void check_frames(const Json& r) {
  uint64_t frags = 0, prev = 0;
  const bool timing = r.contains("physical");
  for (const Json& f : r["frames"]) {
    frags += u(f["fragments"]);
    const uint64_t end = u(f["cycles_end"]);
    EXPECT_GE(end, prev);
    if (timing) {
      EXPECT_SAME(d(f["time_us"]),
                  static_cast<double>(end - prev) / d(r["provenance"]["tech"]["clock_mhz"]));
    } else {
      EXPECT_FALSE(f.contains("time_us"));
    }
    prev = end;
  }
  EXPECT_EQ(frags, u(r["fragments"]));
  EXPECT_EQ(prev, u(r["cycles"]));
  if (r["image"].contains("frame")) {
    bool found = false;
    for (const Json& f : r["frames"]) found = found || f["frame"] == r["image"]["frame"];
    EXPECT_TRUE(found);
  }
}

void check_physical(const Json& r) {
  if (!r.contains("physical")) return;
  const Json& p = r["physical"];
  const double mhz = d(r["provenance"]["tech"]["clock_mhz"]);
  EXPECT_SAME(d(p["clock_mhz"]), mhz);
  EXPECT_SAME(d(p["time_us"]), d(r["cycles"]) / mhz);
  EXPECT_SAME(d(p["fragments_per_second"]), ratio(d(r["fragments"]), d(r["cycles"]) / (mhz * 1e6)));
}

void check_error_map(const Json& r) {
  if (!r.contains("error_map")) return;
  const Json& e = r["error_map"];
  const double scale = d(e["scale"]);
  ASSERT_EQ(e["ticks"].size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_SAME(d(e["ticks"][i]), scale * i / 4.0);
  // The ramp's rows, then the labels' (7·s + 4 rows, s = max(1, height / 240)).
  const int h = r["image"]["height"].get<int>();
  EXPECT_EQ(e["bar_rows"].get<int>(), std::max(8, h / 12) + 7 * std::max(1, h / 240) + 4);
  if (e["auto"].get<bool>()) {
    // The largest error of the imaged frame.
    const Json* acc = &r["accuracy"];
    for (const Json& f : r["frames"])
      if (r["image"].contains("frame") && f["frame"] == r["image"]["frame"]) acc = &f["accuracy"];
    EXPECT_SAME(scale, d((*acc)["max_abs"]));
  }
}

void check_front_end(const Json& r) {
  if (!r.contains("front_end")) return;
  const Json& f = r["front_end"];
  // Every pixel the coordinate units computed either went on to the unit as a fragment of a
  // material with a coordinate unit, or was hidden, or was rejected.
  uint64_t frags = 0;
  for (const auto& [name, m] : r["materials"].items()) {
    bool coords = false;
    for (const Json& b : m["blocks"])
      coords = coords || b.get<std::string>().rfind("coords.", 0) == 0;
    if (coords) frags += u(m["fragments"]);
  }
  EXPECT_GT(frags, 0u);
  EXPECT_EQ(u(f["generated"]), u(f["occluded"]) + u(f["rejected"]) + frags);
}

void check_geometry(const Json& r) {
  const double mhz = d(r["provenance"]["tech"]["clock_mhz"]);
  if (r.contains("geometry")) {
    const Json& g = r["geometry"];
    EXPECT_EQ(g["block"], "geometry.vertex_transform");
    EXPECT_EQ(u(g["cycles"]), u(g["vertices"]));  // one vertex a cycle, one lane by default
    EXPECT_SAME(d(g["time_ns"]), d(g["cycles"]) * 1000.0 / mhz);
    EXPECT_LE(u(g["culled_back"]) + u(g["degenerate"]) + u(g["behind_eye"]), u(g["primitives"]));
    EXPECT_GT(ops_total(g["ops"]), 0u);
  }
  if (!r.contains("raster")) return;
  for (const auto& [name, c] : r["raster"].items()) {
    EXPECT_TRUE(r["materials"].contains(name)) << name;
    EXPECT_LE(u(c["pixels_covered"]), u(c["pixels_visited"])) << name;
    EXPECT_LE(u(c["rejected"]), u(c["primitives"])) << name;
    // Quads after the depth test: each holds 1..4 of the material's kept pixels, which are its
    // fragments unless the object-space pipeline draws it.
    EXPECT_LE(u(c["helper_lanes"]), 3 * u(c["quads"])) << name;
    EXPECT_LE(u(c["quads"]), u(c["pixels_covered"])) << name;
    const Json& m = r["materials"][name];
    if (!m.contains("object_space")) {
      EXPECT_EQ(4 * u(c["quads"]) - u(c["helper_lanes"]), u(m["fragments"])) << name;
    }
    if (c["block"] == "raster.rect_scan") {
      EXPECT_SAME(d(c["divisions_per_triangle"]), ratio(d(c["divisions"]), d(c["triangles"])))
          << name;
      EXPECT_FALSE(c.contains("cycles")) << name;
      // The constant-depth block's reciprocals are the rows' divisions; it covers every pixel
      // it did not reject.
      if (c["coords"] == "constant_depth") {
        EXPECT_EQ(u(c["coord_ops"]["rcp"]), u(c["divisions"])) << name;
        EXPECT_EQ(u(c["coord_pixels"]) + u(c["coord_rejected"]), u(c["pixels_covered"])) << name;
      } else {
        EXPECT_EQ(c["coords"], "exact") << name;
        EXPECT_EQ(u(c["coord_pixels"]), 0u) << name;
      }
    } else {
      EXPECT_EQ(c["block"], "raster.edge") << name;
      EXPECT_EQ(u(c["cycles"]), u(c["pixels_visited"])) << name;  // one pixel a cycle
      EXPECT_SAME(d(c["time_ns"]), d(c["cycles"]) * 1000.0 / mhz) << name;
    }
  }
}

void check_object_space(const Json& r) {
  if (!r.contains("object_space")) return;
  const Json& top = r["object_space"];
  uint64_t cycles = 0;
  const uint64_t line = u(r["cache"]["line_bytes"]);
  for (const Json& name : top["materials"]) {
    const Json& m = r["materials"][name.get<std::string>()];
    ASSERT_TRUE(m.contains("object_space")) << name;
    const Json& os = m["object_space"];
    cycles += u(os["cycles"]["total"]);
    // The streaming stages overlap (the slowest sets the pace); set-up and resolve do not.
    const Json& oc = os["cycles"];
    EXPECT_EQ(u(oc["total"]),
              std::max({u(oc["texture"]), u(oc["raster"]), u(oc["projection"]), u(oc["splat"])}) +
                  u(oc["setup"]) + u(oc["resolve"]))
        << name;
    EXPECT_EQ(u(m["fragments"]), u(os["pixels_shown"])) << name;
    EXPECT_SAME(d(os["samples_per_pixel"]), ratio(d(os["samples"]), d(os["pixels_shown"]))) << name;
    EXPECT_EQ(u(os["samples"]), u(os["grid_samples"]) + u(os["edge_samples"])) << name;
    std::map<std::string, uint64_t> sum;
    for (const auto& [blk, ops] : os["ops"].items())
      for (const auto& [k, v] : ops.items()) sum[k] += u(v);
    std::map<std::string, uint64_t> mat;
    for (const auto& [k, v] : m["ops"].items()) mat[k] = u(v);
    EXPECT_EQ(mat, sum) << name;
    EXPECT_SAME(d(m["texels_per_fragment"]), ratio(d(os["texels"]), d(m["fragments"]))) << name;
    const Json& c = os["cache"];
    EXPECT_EQ(u(c["accesses"]), u(c["hits"]) + u(c["misses"])) << name;
    EXPECT_EQ(u(c["fill_bytes"]), u(c["misses"]) * line) << name;
    EXPECT_EQ(u(os["dram_bytes"]), u(c["fill_bytes"])) << name;
    const Json& sb = os["splat_buffer"];
    EXPECT_EQ(u(sb["bytes"]), u(sb["splat_read_bytes"]) + u(sb["splat_written_bytes"]) +
                                  u(sb["resolve_read_bytes"]) + u(sb["resolve_written_bytes"]))
        << name;
    EXPECT_LE(u(os["holes"]["holes"]), u(os["holes"]["covered"])) << name;
    EXPECT_GT(d(os["lod_mean"]), -20.0) << name;
    EXPECT_GT(u(os["bands"]), 0u) << name;
    const std::vector<std::string> ends = {"geometry.polygon_rotation", "raster.object_space"};
    EXPECT_EQ(m["blocks"][0], ends[0]) << name;
    EXPECT_EQ(m["blocks"][1], ends[1]) << name;
    EXPECT_EQ(m["blocks"].back(), "raster.splat_resolve") << name;
  }
  EXPECT_EQ(u(top["cycles"]), cycles);
  EXPECT_EQ(u(top["frame_cycles"]), cycles + u(top["screen_space_cycles"]));
  EXPECT_GE(u(top["screen_space_cycles"]), u(r["cycles"]));
}

// The ledger's block costs are the report's own blocks'; its deltas are differences of the
// accuracy figures it lists.
void check_ledger(const Json& r) {
  if (!r.contains("ledger")) return;
  const Json& s = r["ledger_setup"];
  EXPECT_SAME(d(s["hardware"]["psnr_db"]), d(r["accuracy"]["psnr_db"]));
  EXPECT_SAME(d(s["hardware"]["nmse"]), d(r["accuracy"]["nmse"]));
  EXPECT_EQ(u(s["hardware"]["cycles"]), u(r["cycles"]));
  EXPECT_EQ(u(s["pixels"]), u(r["accuracy"]["pixels"]));
  EXPECT_SAME(d(s["change_threshold"]), 0.5 / 255);
  const std::map<std::string, std::string> prefix = {
      {"coords", "coords."},   {"derivs", "derivs."}, {"lod", "lod"},
      {"subtexel", "filter."}, {"vd", "filter."},     {"filter_arith", "filter."},
      {"texels", "cache"}};
  for (const auto& [name, row] : r["ledger"].items()) {
    if (name == "raster_coords") {
      // The rasteriser's constant-depth block: its ops are the raster section's coord_ops.
      uint64_t ops = 0;
      for (const Json& m : row["materials"])
        ops += ops_total(r["raster"][m.get<std::string>()]["coord_ops"]);
      EXPECT_EQ(u(row["ops"]), ops) << name;
      EXPECT_GT(ops, 0u) << name;
      continue;
    }
    ASSERT_TRUE(prefix.count(name)) << name;
    uint64_t ops = 0;
    double area = 0;
    for (const auto& [bn, b] : r["blocks"].items()) {
      if (bn.rfind(prefix.at(name), 0) != 0) continue;
      bool ours = false;
      for (const Json& m : b["materials"])
        for (const Json& rm : row["materials"]) ours = ours || m == rm;
      if (!ours) continue;
      ops += ops_total(b["ops"]);
      area += d(b["area"]);
    }
    EXPECT_EQ(u(row["ops"]), ops) << name;
    EXPECT_SAME(d(row["area"]), area) << name;
    const Json& al = row["alone"];
    EXPECT_SAME(d(al["dpsnr_db"]), d(al["psnr_db"]) - d(r["accuracy"]["psnr_db"])) << name;
    EXPECT_SAME(d(al["dnmse"]), d(r["accuracy"]["nmse"]) - d(al["nmse"])) << name;
    EXPECT_SAME(d(al["pixels_changed_pct"]), 100.0 * ratio(d(al["pixels_changed"]), d(s["pixels"])))
        << name;
    const Json& ab = row["all_but"];
    EXPECT_SAME(d(ab["psnr_db"]), d(s["all_exact"]["psnr_db"])) << name;
    EXPECT_SAME(d(ab["nmse"]), d(s["all_exact"]["nmse"])) << name;
    // The all-but run's pixels are the hardware run's (same geometry).
    EXPECT_SAME(d(ab["pixels_changed_pct"]), 100.0 * ratio(d(ab["pixels_changed"]), d(s["pixels"])))
        << name;
  }
}

void check_provenance(const Json& r) {
  const Json& p = r["provenance"];
  EXPECT_FALSE(p["texsim_version"].get<std::string>().empty());
  for (const Json& in : p["inputs"]) {
    if (!in.contains("sha1")) continue;
    EXPECT_EQ(in["sha1"].get<std::string>().size(), 40u);
    EXPECT_EQ(u(in["bytes"]), fs::file_size(in["path"].get<std::string>())) << in["path"];
  }
  EXPECT_GT(d(p["tech"]["clock_mhz"]), 0.0);
  EXPECT_EQ(p["tech"]["latency"].size(), texsim::kOpKindNames.size());
  EXPECT_EQ(p["tech"]["area"].size(), texsim::kOpKindNames.size());
}

uint64_t sum(const Json& a) {
  uint64_t s = 0;
  for (const Json& v : a) s += u(v);
  return s;
}

// One frame's (or the total's) characterisation: histograms hold every fragment, working sets
// shrink as lines grow, a fragment brings at most four texels and as many line uses.
void check_workload_frame(const Json& w, const Json& setup) {
  const uint64_t frags = u(w["fragments"]);
  EXPECT_GT(frags, 0u);
  EXPECT_LE(u(w["quads"]), frags);
  EXPECT_GE(4 * u(w["quads"]), frags);
  EXPECT_GE(u(w["textures"]), 1u);
  EXPECT_EQ(u(w["lod_under"]) + sum(w["lod"]) + u(w["lod_over"]), frags);
  EXPECT_EQ(w["lod"].size(), 32u);
  EXPECT_EQ(sum(w["aniso"]), frags);
  EXPECT_EQ(w["aniso"].size(), setup["aniso_bins"].size());
  EXPECT_EQ(u(w["magnified"]) + u(w["minified"]), frags);
  EXPECT_SAME(d(w["magnified_share"]), ratio(d(w["magnified"]), static_cast<double>(frags)));
  EXPECT_GE(u(w["texels_level0"]), 1u);
  EXPECT_LE(u(w["texels_level0"]), 4 * frags);
  EXPECT_GE(u(w["texels_lod"]), 1u);
  EXPECT_LE(u(w["texels_lod"]), 4 * frags);
  EXPECT_SAME(d(w["texels_per_fragment"]), ratio(d(w["texels_lod"]), static_cast<double>(frags)));
  EXPECT_GE(d(w["footprint_texels_per_fragment"]), 0.0);
  const Json& lines = w["lines"];
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_GE(u(lines[0]), u(lines[1]));
  EXPECT_GE(u(lines[1]), u(lines[2]));
  EXPECT_GE(u(lines[2]), 1u);
  EXPECT_LE(u(lines[0]), u(w["texels_lod"]));  // every line holds a texel read
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(u(w["working_set_bytes"][k]), u(lines[k]) * u(setup["line_bytes"][k])) << k;
    // A line is at most twice the one of half its size (and holds at most all of them).
    if (k > 0) {
      EXPECT_LE(u(lines[k - 1]), 2 * u(lines[k])) << k;
    }
  }
  // Reuse on 64-byte lines: every use is a first use, a reuse of some distance or untracked.
  EXPECT_EQ(u(setup["reuse_line_bytes"]), 64u);
  if (u(w["untracked_uses"]) == 0) {
    EXPECT_EQ(u(w["first_uses"]), u(lines[1]));
  } else {
    EXPECT_LT(u(w["first_uses"]), u(lines[1]));
  }
  EXPECT_EQ(sum(w["reuse"]), u(w["line_uses"]) - u(w["first_uses"]) - u(w["untracked_uses"]));
  EXPECT_GE(u(w["line_uses"]), frags);
  EXPECT_LE(u(w["line_uses"]), 4 * frags);
}

// Frames of the characterisation are the run's frames; the total sums them.
void check_workload(const Json& r) {
  ASSERT_TRUE(r.contains("workload"));
  const Json& w = r["workload"];
  EXPECT_EQ(w["layout"], r["provenance"]["pipeline"]["layout"]);
  EXPECT_EQ(w["line_bytes"], Json::parse("[32, 64, 128]"));
  EXPECT_SAME(d(w["lod_lo"]), -4.0);
  EXPECT_SAME(d(w["lod_step"]), 0.5);
  EXPECT_EQ(u(w["reuse_max_lines"]), 1u << 20);
  ASSERT_EQ(w["frames"].size(), r["frames"].size());
  Json total = w["frames"][0];
  for (size_t i = 0; i < w["frames"].size(); ++i) {
    const Json& f = w["frames"][i];
    check_workload_frame(f, w);
    EXPECT_EQ(f["frame"], r["frames"][i]["frame"]);
    EXPECT_EQ(u(f["fragments"]), u(r["frames"][i]["fragments"]));
    if (i == 0) continue;
    for (const char* k :
         {"fragments", "quads", "textures", "texels_level0", "texels_lod", "lod_under", "lod_over",
          "magnified", "minified", "line_uses", "first_uses", "untracked_uses"})
      total[k] = u(total[k]) + u(f[k]);
    for (const char* k : {"lines", "working_set_bytes", "lod", "aniso", "reuse"})
      for (size_t j = 0; j < f[k].size(); ++j) total[k][j] = u(total[k][j]) + u(f[k][j]);
  }
  const Json& t = w["total"];
  check_workload_frame(t, w);
  EXPECT_EQ(u(t["fragments"]), u(r["fragments"]));
  for (const char* k : {"fragments", "quads", "textures", "texels_level0", "texels_lod", "lines",
                        "working_set_bytes", "lod_under", "lod", "lod_over", "aniso", "magnified",
                        "minified", "line_uses", "first_uses", "untracked_uses", "reuse"})
    EXPECT_EQ(t[k], total[k]) << k;
}

// Compressed textures: the decoder's activations, per format and in all, and the decompressor
// level's counters only where it exists (before the L1 or after the L2).
void check_decompress(const Json& r) {
  if (!r.contains("decompress")) return;
  const Json& e = r["decompress"];
  const std::string at = e["placement"].get<std::string>();
  EXPECT_TRUE(at == "before_l1" || at == "after_l1" || at == "after_l2") << at;
  uint64_t sum = 0;
  for (const auto& [f, n] : e["blocks_by_format"].items()) {
    sum += u(n);
    EXPECT_TRUE(r["blocks"].contains("decode." + f)) << f;  // each format's decoder has a row
  }
  EXPECT_EQ(u(e["blocks_decoded"]), sum);
  // The decompressor level sits in front of DRAM (before_l1) or of the L2 (after_l2).
  EXPECT_EQ(e.contains("decoded_lines"), at != "after_l1");
  EXPECT_EQ(e.contains("compressed_reads"), at != "after_l1");
  // Every compressed line read brings at least one block to decode.
  if (at != "after_l1") {
    EXPECT_LE(u(e["compressed_reads"]), u(e["blocks_decoded"]));
  }
}

void check_report(const Json& r, int width, int height) {
  expect_known_keys(r);
  check_summary(r, width, height);
  check_blocks(r);
  check_materials(r);
  check_stages(r);
  check_memory(r);
  check_hierarchy(r);
  check_units(r);
  check_quads(r);
  check_energy(r);
  check_frames(r);
  check_accuracy(r);
  check_physical(r);
  check_error_map(r);
  check_front_end(r);
  check_geometry(r);
  check_object_space(r);
  check_ledger(r);
  check_provenance(r);
  check_workload(r);
  check_decompress(r);
}

// The accuracy figures against the run's own float images: over covered pixels, per channel.
void check_against_images(const Json& r, const texsim::RunCapture& c) {
  ASSERT_TRUE(c.image && c.reference);
  const texsim::ImageRgb& img = *c.image;
  const texsim::ImageRgb& ref = *c.reference;
  ASSERT_EQ(img.rgb.size(), ref.rgb.size());
  struct Sums {
    uint64_t px = 0;
    double se = 0, sref = 0, sabs = 0, mx = 0;
  };
  std::map<int, Sums> by_label;
  Sums all;
  for (size_t i = 0; i < img.covered.size(); ++i) {
    if (!img.covered[i]) continue;
    Sums& l = by_label[img.label[i]];
    for (Sums* s : {&all, &l}) {
      ++s->px;
      for (size_t k = 0; k < 3; ++k) {
        const double e = static_cast<double>(img.rgb[3 * i + k]) - ref.rgb[3 * i + k];
        s->se += e * e;
        s->sref += static_cast<double>(ref.rgb[3 * i + k]) * ref.rgb[3 * i + k];
        s->sabs += std::abs(e);
        s->mx = std::max(s->mx, std::abs(e));
      }
    }
  }
  auto expect = [](const Json& a, const Sums& s, const std::string& what) {
    ASSERT_EQ(u(a["pixels"]), s.px) << what;
    if (s.px == 0) return;
    const double n = 3.0 * static_cast<double>(s.px), mse = s.se / n;
    if (a.contains("mse")) {
      EXPECT_NEAR(d(a["mse"]), mse, 1e-7 * mse) << what;
    }
    EXPECT_NEAR(d(a["psnr_db"]), 10 * std::log10(1 / mse), 1e-6) << what;
    EXPECT_NEAR(d(a["nmse"]), s.se / s.sref, 1e-7 * s.se / s.sref) << what;
    EXPECT_NEAR(d(a["mean_abs"]), s.sabs / n, 1e-7 * s.sabs / n) << what;
    EXPECT_NEAR(d(a["max_abs"]), s.mx, 1e-7) << what;
  };
  if (r["frames"].size() == 1) expect(r["accuracy"], all, "accuracy");
  for (const Json& f : r["frames"])
    if (!r["image"].contains("frame") || f["frame"] == r["image"]["frame"])
      expect(f["accuracy"], all, "frame " + f["frame"].dump());
  // Materials pool over every frame; the images are one frame's. Labels of the object-space
  // pass differ.
  if (r["frames"].size() > 1 || r.contains("object_space")) return;
  for (size_t m = 0; m < c.material_names.size(); ++m) {
    const Json& a = r["materials"][c.material_names[m]]["accuracy"];
    expect(a, by_label[static_cast<int>(m)], "material " + c.material_names[m]);
  }
}

// --- report.md prints the same figures as report.json ------------------------------------------

std::string g4(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

void expect_in(const std::string& md, const std::string& text) {
  EXPECT_NE(md.find(text), std::string::npos) << "report.md lacks '" << text << "'";
}

// report.md computes some figures on its own (the hit rate, per-fragment figures): each must be
// report.json's, printed to 4 significant digits.
void check_markdown(const Json& r, const std::string& md) {
  for (const Json& f : r["workload"]["frames"]) {
    expect_in(md, "| " + f["frame"].dump() + " | " + f["fragments"].dump() + " | " +
                      f["quads"].dump() + " | " + f["textures"].dump() + " | " +
                      f["texels_level0"].dump() + " | " + f["texels_lod"].dump() + " | " +
                      g4(d(f["texels_per_fragment"])) + " | " + f["lines"][0].dump() + " | ");
    break;  // the first frame's row
  }
  expect_in(md, "| cycles | " + r["cycles"].dump() + " (" + g4(d(r["cycles_per_fragment"])) +
                    " per fragment) |");
  expect_in(md, "| area (sum of blocks) | " + g4(d(r["area_total"])) + " |");
  if (r.contains("physical")) {
    const Json& p = r["physical"];
    expect_in(md, "| time at " + g4(d(p["clock_mhz"])) + " MHz | " + g4(d(p["time_us"])) + " µs (" +
                      g4(d(p["fragments_per_second"]) / 1e6) + " M fragments/s) |");
  }
  const Json& c = r["cache"];
  expect_in(md, "| " + c["hits"].dump() + " | " + c["misses"].dump() + " | " +
                    g4(100 * d(c["hit_rate"])) + "% | " + c["texel_reads"].dump() + " | " +
                    c["fill_bytes"].dump() + " | " + r["dram"]["requests"].dump() + " |");
  const Json& a = r["accuracy"];
  if (!a["psnr_db"].is_null()) {
    expect_in(md, "| " + g4(d(a["psnr_db"])) + " | " + g4(d(a["nmse"])) + " | " +
                      g4(d(a["max_abs"])) + " | " + g4(d(a["mean_abs"])) + " | " +
                      a["pixels"].dump() + " |");
  }
  for (const auto& [name, m] : r["materials"].items()) {
    expect_in(md, " | " + m["fragments"].dump() + " | ");
    expect_in(md, " | " + g4(d(m["ops_per_fragment"])) + " | " + g4(d(m["texels_per_fragment"])) +
                      " |\n");
  }
  for (const auto& [name, b] : r["blocks"].items())
    expect_in(md, " | " + g4(d(b["ops_per_fragment"])) + " | " + b["texels"].dump() + " |\n");
  if (r.contains("stages")) {
    for (const auto& [name, st] : r["stages"].items())
      expect_in(md, "| " + name + " | " + st["latency"].dump() + " | " +
                        g4(100 * d(st["utilisation"]), 3) + "% | ");
  }
}

class ReportFigures : public ::testing::Test {
 protected:
  // Runs in-process with `opt` into a fresh directory; returns the report (and the images in
  // `capture_`).
  Json run(texsim::RunOptions opt, const std::vector<std::string>& sets = {}) {
    opt.out = dir_.file("run" + std::to_string(runs_++));
    opt.threads = 1;
    for (const std::string& s : sets) opt.overrides.push_back(s);
    capture_ = texsim::RunCapture{};
    capture_.write_outputs = true;
    opt.capture = &capture_;
    std::ostringstream log;
    texsim::run_simulation(opt, log);
    std::ifstream in(opt.out + "/report.json"), md(opt.out + "/report.md");
    Json r = Json::parse(in);
    std::stringstream text;
    text << md.rdbuf();
    check_markdown(r, text.str());
    return r;
  }
  Json run_scene(const std::string& scene, std::vector<std::string> sets = {},
                 bool functional = false) {
    texsim::RunOptions opt;
    opt.scene = scene;
    opt.functional = functional;
    sets.insert(sets.begin(), {"output.width=" + std::to_string(kW),
                               "output.height=" + std::to_string(kH), "reference.samples=2"});
    return run(opt, sets);
  }
  static constexpr int kW = 64, kH = 48;
  texsim::TempDir dir_{"texsim_report_figures"};
  texsim::RunCapture capture_;
  int runs_ = 0;
};

TEST_F(ReportFigures, DefaultSceneTiming) {
  const Json r = run_scene("");
  check_report(r, kW, kH);
  check_against_images(r, capture_);
  EXPECT_TRUE(r.contains("stages"));
}

// Several units, quads, an L2 over banked DRAM and an energy table of the scene's own.
TEST_F(ReportFigures, MemoryHierarchy) {
  const Json r = run_scene(
      "", {"pipeline.units=4", "pipeline.unit_tile=8", "pipeline.quad_merge=true",
           "pipeline.derivatives=coarse", "raster.order=tiled", "pipeline.l2.size_bytes=65536",
           "pipeline.l2.prefetch=next_line", "pipeline.dram.model=banked",
           "pipeline.dram.preset=lpddr4", "tech.energy.dram_byte_pj=100"});
  check_report(r, kW, kH);
  check_against_images(r, capture_);
  for (const char* k : {"units", "l2", "quads", "energy", "scheduler"})
    EXPECT_TRUE(r.contains(k)) << k;
  EXPECT_EQ(r["dram"]["model"], "banked");
  EXPECT_SAME(d(r["provenance"]["tech"]["energy"]["dram_byte_pj"]), 100.0);
}

TEST_F(ReportFigures, DefaultSceneFunctional) {
  const Json r = run_scene("", {}, true);
  check_report(r, kW, kH);
  check_against_images(r, capture_);
}

TEST_F(ReportFigures, ReliefAndLighting) {
  const Json r = run_scene(kScenes + "relief_wall.toml");
  check_report(r, kW, kH);
  check_against_images(r, capture_);
  bool relief = false;
  for (const auto& [n, m] : r["materials"].items()) relief = relief || m.contains("relief");
  EXPECT_TRUE(relief);
}

TEST_F(ReportFigures, CoordinateFrontEnd) {
  const Json r = run_scene(kScenes + "coords.toml");
  check_report(r, kW, kH);
  check_against_images(r, capture_);
  EXPECT_TRUE(r.contains("front_end"));
}

TEST_F(ReportFigures, RectScanRasterAndGeometry) {
  const Json r = run_scene(kScenes + "flight.toml");
  check_report(r, kW, kH);
  check_against_images(r, capture_);
  EXPECT_TRUE(r.contains("geometry"));
  bool rect = false;
  for (const auto& [n, c] : r["raster"].items()) rect = rect || c["block"] == "raster.rect_scan";
  EXPECT_TRUE(rect);
}

// A tiled raster order reorders the fragments: the same fragments, quads and image; only the
// figures of the order (cache, cycles) may move.
TEST_F(ReportFigures, TiledRasterOrder) {
  const Json rows = run_scene("");
  const Json r = run_scene("", {"raster.order=tiled", "raster.tile=8", "raster.tile_order=hilbert",
                                "raster.quad_order=morton"});
  check_report(r, kW, kH);
  check_against_images(r, capture_);
  EXPECT_EQ(u(r["fragments"]), u(rows["fragments"]));
  EXPECT_NEAR(d(r["accuracy"]["psnr_db"]), d(rows["accuracy"]["psnr_db"]), 1e-9);
  for (const auto& [name, c] : rows["raster"].items()) {
    EXPECT_EQ(u(r["raster"][name]["quads"]), u(c["quads"])) << name;
    EXPECT_EQ(u(r["raster"][name]["helper_lanes"]), u(c["helper_lanes"])) << name;
    EXPECT_GT(u(c["quads"]), 0u) << name;
  }
}

TEST_F(ReportFigures, ObjectSpace) {
  const Json r = run_scene(kScenes + "object_space.toml");
  check_report(r, kW, kH);
  check_against_images(r, capture_);
  EXPECT_TRUE(r.contains("object_space"));
}

// The object-space pipeline's DRAM bytes come from whichever DRAM model the scene sets (the
// banked one's counters, not the flat one's, which stay zero).
TEST_F(ReportFigures, ObjectSpaceOnBankedDram) {
  const Json r = run_scene(kScenes + "object_space.toml", {"pipeline.dram.model=banked"});
  check_report(r, kW, kH);
  bool checked = false;
  for (const auto& [name, m] : r["materials"].items()) {
    if (!m.contains("object_space")) continue;
    EXPECT_GT(u(m["object_space"]["dram_bytes"]), 0u) << name;
    checked = true;
  }
  EXPECT_TRUE(checked);
}

TEST_F(ReportFigures, ErrorLedger) {
  texsim::RunOptions opt;
  opt.ledger = true;
  const Json r = run(opt, {"output.width=48", "output.height=32", "reference.samples=1"});
  check_report(r, 48, 32);
  EXPECT_FALSE(r["ledger"].empty());
}

// Two frames of a trace: per-frame figures pool into the run's; the images show frame 1.
TEST_F(ReportFigures, FramesOfATrace) {
  std::string csv =
      "# texture 0 checker \"procedural:checker?size=64&cells=8\" 64 64\n"
      "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,lod_bias\n";
  for (int f = 0; f < 2; ++f)
    for (int y = 0; y < 20 - 8 * f; ++y)
      for (int x = 0; x < 30; ++x)
        csv += std::to_string(f) + ",0," + std::to_string(x) + "," + std::to_string(y) + ",0," +
               std::to_string(0.013 * x * (f + 1)) + "," + std::to_string(0.017 * y) +
               ",0.013,0,0,0.017,0\n";
  std::ofstream(dir_.file("t.csv")) << csv;
  texsim::RunOptions opt;
  opt.trace = dir_.file("t.csv");
  opt.frame = 1;
  const Json r = run(opt);
  ASSERT_EQ(r["frames"].size(), 2u);
  check_report(r, r["image"]["width"].get<int>(), r["image"]["height"].get<int>());
  check_against_images(r, capture_);
  EXPECT_EQ(r["image"]["frame"], 1);
}

// A block-compressed texture with the decoder at each of its places (after the L2 over an L2).
TEST_F(ReportFigures, CompressedTexture) {
  for (const char* at : {"before_l1", "after_l1", "after_l2"}) {
    const Json r = run_scene(
        kScenes + "cube.toml",
        {"textures.crate.compress={ format = \"bc1_rgb\", encoder = \"squish\", quality = "
         "\"range\" }",
         std::string("pipeline.decompress=") + at, "pipeline.l2.size_bytes=65536"});
    check_report(r, r["image"]["width"].get<int>(), r["image"]["height"].get<int>());
    ASSERT_TRUE(r.contains("decompress")) << at;
    EXPECT_EQ(r["decompress"]["placement"], at);
    EXPECT_GT(u(r["decompress"]["blocks_decoded"]), 0u) << at;
  }
}

// Border addressing: the filter rows count the border taps, which fetch nothing: the texels
// the cache serves are the taps less the border taps, and the blend makes no read for them.
TEST_F(ReportFigures, BorderTaps) {
  const Json r = run_scene(kScenes + "border.toml");
  check_report(r, kW, kH);
  uint64_t border = 0, taps_read = 0;
  for (const auto& [name, b] : r["blocks"].items()) {
    if (b.contains("border_taps")) border += u(b["border_taps"]);
    if (name.rfind("filter.", 0) == 0) taps_read += u(b["texels"]);
  }
  EXPECT_GT(border, 0u);
  EXPECT_EQ(u(r["cache"]["texel_reads"]), taps_read);  // the L1 saw no border tap
  EXPECT_EQ(u(r["blocks"]["blend"]["ops"]["mem"]), taps_read);
  EXPECT_EQ(u(r["blocks"]["blend"]["ops"]["mul"]), 4 * (taps_read + border));
  // Without border addressing the same panels read a texel for every tap.
  const Json c =
      run_scene(kScenes + "border.toml", {"materials.border_white.filter.address=\"clamp\"",
                                          "materials.border_custom.filter.address_u=\"clamp\""});
  for (const auto& [name, b] : c["blocks"].items()) EXPECT_FALSE(b.contains("border_taps")) << name;
  EXPECT_EQ(u(c["blocks"]["blend"]["ops"]["mem"]) * 4, u(c["blocks"]["blend"]["ops"]["mul"]));
}

// Without a ground truth every accuracy figure is null and there is no error map.
TEST_F(ReportFigures, NoGroundTruth) {
  texsim::RunOptions opt;
  opt.reference = "none";
  const Json r = run(opt, {"output.width=48", "output.height=32"});
  check_report(r, 48, 32);
  EXPECT_FALSE(r.contains("error_map"));
  auto nulls = [](const Json& a) {
    for (const char* k : {"psnr_db", "nmse", "max_abs", "mean_abs"})
      EXPECT_TRUE(a[k].is_null()) << k;
  };
  nulls(r["accuracy"]);
  EXPECT_TRUE(r["accuracy"]["mse"].is_null());
  for (const Json& f : r["frames"]) nulls(f["accuracy"]);
  for (const auto& [n, m] : r["materials"].items()) nulls(m["accuracy"]);
}

TEST(ReportKeys, AnUnknownKeyFails) {
  Json r = {{"fragments", 1}, {"cache", {{"hit_rate", 0.5}, {"new_figure", 1}}}};
  std::set<std::string> keys;
  key_patterns(r, "", keys);
  std::vector<std::string> unknown;
  for (const std::string& k : keys)
    if (!kKnownKeys.count(k)) unknown.push_back(k);
  EXPECT_EQ(unknown, std::vector<std::string>{"cache.new_figure"});
}

// --- texsim merge: every column is the report's (or the job's) value --------------------------

// One column: its name, and where its value comes from (JSON pointer into job.json or
// report.json), as docs/sweeps.md defines them.
struct MergeColumn {
  std::string name, file, pointer;
};
const std::vector<MergeColumn> kMergeColumns = {
    {"job", "job", "/job"},
    {"scene", "job", "/scene"},
    {"trace", "job", "/trace"},
    {"overrides", "job", "/overrides"},
    {"fragments", "report", "/fragments"},
    {"cycles", "report", "/cycles"},
    {"cycles_per_fragment", "report", "/cycles_per_fragment"},
    {"psnr_db", "report", "/accuracy/psnr_db"},
    {"nmse", "report", "/accuracy/nmse"},
    {"max_abs", "report", "/accuracy/max_abs"},
    {"area_total", "report", "/area_total"},
    {"time_us", "report", "/physical/time_us"},
    {"cache_hit_rate", "report", "/cache/hit_rate"},
};

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out(1);
  for (char ch : s) {
    if (ch == sep) {
      out.emplace_back();
    } else {
      out.back() += ch;
    }
  }
  return out;
}

// A cell against the value it stands for: numbers compared as numbers, arrays as "a; b".
void expect_cell(const std::string& cell, const Json& v, const std::string& what) {
  if (v.is_number()) {
    ASSERT_FALSE(cell.empty()) << what;
    EXPECT_SAME(std::stod(cell), d(v)) << what;
  } else if (v.is_string()) {
    EXPECT_EQ(cell, v.get<std::string>()) << what;
  } else if (v.is_array()) {
    std::string s;
    for (const Json& e : v) s += (s.empty() ? "" : "; ") + e.get<std::string>();
    EXPECT_EQ(cell, s) << what;
  }
}

// The SQLite results ledger merge writes: its columns are the known ones, each figure column
// the report's value stored as a number, the others the job's and the provenance's.
void check_results_ledger(const texsim::TempDir& dir) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(dir.file("m/ledger.sqlite").c_str(), &db), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT * FROM runs ORDER BY job", -1, &st, nullptr), SQLITE_OK)
      << sqlite3_errmsg(db);
  std::vector<std::string> names;
  names.reserve(static_cast<size_t>(sqlite3_column_count(st)));
  for (int i = 0; i < sqlite3_column_count(st); ++i) names.emplace_back(sqlite3_column_name(st, i));
  const std::vector<std::string> known = {
      "report_sha1",  "texsim_version", "command",   "job",        "scene",
      "trace",        "overrides",      "fragments", "cycles",     "cycles_per_fragment",
      "psnr_db",      "nmse",           "max_abs",   "area_total", "time_us",
      "configuration"};
  ASSERT_EQ(names, known) << "a new ledger column must be checked here";
  const std::map<std::string, std::string> figures = {
      {"fragments", "/fragments"},
      {"cycles", "/cycles"},
      {"cycles_per_fragment", "/cycles_per_fragment"},
      {"psnr_db", "/accuracy/psnr_db"},
      {"nmse", "/accuracy/nmse"},
      {"max_abs", "/accuracy/max_abs"},
      {"area_total", "/area_total"},
      {"time_us", "/physical/time_us"}};
  int rows = 0;
  while (sqlite3_step(st) == SQLITE_ROW) {
    auto text = [&](int i) {
      return std::string(reinterpret_cast<const char*>(sqlite3_column_text(st, i)));
    };
    char name[40];
    std::snprintf(name, sizeof name, "sw/job-%05d/", sqlite3_column_int(st, 3));
    std::ifstream rf(dir.file(std::string(name) + "report.json")),
        jf(dir.file(std::string(name) + "job.json"));
    const Json r = Json::parse(rf), job = Json::parse(jf);
    for (int i = 0; i < static_cast<int>(names.size()); ++i) {
      const auto f = figures.find(names[i]);
      if (f == figures.end()) continue;
      const int type = sqlite3_column_type(st, i);
      EXPECT_TRUE(type == SQLITE_INTEGER || type == SQLITE_FLOAT) << names[i];
      EXPECT_SAME(sqlite3_column_double(st, i), d(r.at(Json::json_pointer(f->second)))) << names[i];
    }
    EXPECT_EQ(text(0).size(), 40u);
    EXPECT_EQ(text(1), r["provenance"]["texsim_version"].get<std::string>());
    EXPECT_EQ(text(2), r["provenance"]["command"].get<std::string>());
    EXPECT_EQ(sqlite3_column_int(st, 3), job["job"].get<int>());
    EXPECT_EQ(text(4), job["scene"].get<std::string>());
    EXPECT_EQ(text(5), job["trace"].get<std::string>());
    EXPECT_EQ(Json::parse(text(6)), job["overrides"]);
    const Json config = Json::parse(text(15));
    EXPECT_EQ(config["pipeline"], r["provenance"]["pipeline"]);
    EXPECT_EQ(config["tech"], r["provenance"]["tech"]);
    ++rows;
  }
  sqlite3_finalize(st);
  sqlite3_close(db);
  EXPECT_EQ(rows, 2);
}

TEST_F(ReportFigures, MergeColumnsAreTheReportsValues) {
  const std::string sweep = dir_.file("s.toml");
  std::ofstream(sweep) << "[sweep]\nscenes = [\"default\"]\nout = \"sw\"\n"
                          "[grid]\n\"output.width\" = [40, 56]\n\"output.height\" = [30]\n"
                          "\"reference.samples\" = [1]\n";
  texsim::SweepOptions so;
  so.jobs = 1;
  std::ostringstream log;
  ASSERT_EQ(texsim::run_sweep(sweep, so, log), 0) << log.str();
  ASSERT_EQ(texsim::merge_sweeps({dir_.file("sw")}, dir_.file("m"), log), 2) << log.str();
  std::ifstream csv_in(dir_.file("m/merged.csv")), md_in(dir_.file("m/merged.md"));
  std::string line;
  std::getline(csv_in, line);
  std::vector<std::string> want;
  want.reserve(kMergeColumns.size());
  for (const MergeColumn& c : kMergeColumns) want.push_back(c.name);
  ASSERT_EQ(split(line, ','), want) << "a new merge column must be checked here";
  std::vector<std::string> md_lines;
  while (std::getline(md_in, line))
    if (line.rfind("| ", 0) == 0) md_lines.push_back(line);
  ASSERT_EQ(md_lines.size(), 3u);  // header and two jobs
  for (int job = 0; job < 2; ++job) {
    char name[32];
    std::snprintf(name, sizeof name, "sw/job-%05d/", job);
    std::ifstream jf(dir_.file(std::string(name) + "job.json")),
        rf(dir_.file(std::string(name) + "report.json"));
    const Json files[2] = {Json::parse(jf), Json::parse(rf)};
    check_report(files[1], job == 0 ? 40 : 56, 30);
    ASSERT_TRUE(std::getline(csv_in, line));
    const std::vector<std::string> cells = split(line, ',');
    // The Markdown row: "| a | b | … |".
    std::vector<std::string> md = split(md_lines[1 + job].substr(2), '|');
    md.pop_back();
    ASSERT_EQ(cells.size(), kMergeColumns.size()) << line;
    ASSERT_EQ(md.size(), kMergeColumns.size()) << md_lines[1 + job];
    for (size_t i = 0; i < kMergeColumns.size(); ++i) {
      const MergeColumn& c = kMergeColumns[i];
      const Json& v = files[c.file == "job" ? 0 : 1].at(Json::json_pointer(c.pointer));
      std::string cell = cells[i];
      if (cell.size() >= 2 && cell.front() == '"') cell = cell.substr(1, cell.size() - 2);
      expect_cell(cell, v, "merged.csv " + c.name);
      std::string m = md[i];
      m.erase(0, std::min(m.size(), m.find_first_not_of(' ')));
      m.erase(m.find_last_not_of(' ') + 1);
      expect_cell(m, v, "merged.md " + c.name);
    }
  }
  check_results_ledger(dir_);
}

}  // namespace
