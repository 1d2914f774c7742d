#include "pipeline/report/run_report.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "blocks/base/atomic_file.h"
#include "blocks/base/sample_op.h"
#include "pipeline/report/number_text.h"
#include "pipeline/report/workload_report.h"

namespace texsim {

namespace {

// One material's method and what it cost: its blocks' operations and texels over its fragments.
struct MaterialRow {
  std::string name;
  uint64_t fragments = 0;
  std::vector<std::string> blocks;
  OpCounts ops;
  uint64_t texels = 0;
  TextureUnit::OpTallies op_tallies{};  // explicit operations (Fragment::op)
  // "fixed" or "float" (filter.arithmetic); empty when no material of the run is fixed.
  std::string arithmetic;
  bool relief = false;  // relief loop steps and height reads (materials with relief only)
  uint64_t relief_steps = 0, relief_fetches = 0;
  AccuracyMetrics acc;
  double per_fragment(double v) const {
    return fragments > 0 ? v / static_cast<double>(fragments) : 0.0;
  }
};

std::vector<MaterialRow> material_rows(const RunInfo& info, const UnitArray& unit) {
  std::vector<MaterialRow> rows;
  bool any_fixed = false;
  for (int m = 0; m < unit.material_count(); ++m)
    any_fixed = any_fixed || unit.material(m).filter.fixed_arithmetic;
  for (int m = 0; m < unit.material_count(); ++m) {
    MaterialRow r;
    r.name = unit.material(m).name;
    if (any_fixed) r.arithmetic = unit.material(m).filter.fixed_arithmetic ? "fixed" : "float";
    r.fragments = unit.material_fragments(m);
    r.op_tallies = unit.material_op_tallies(m);
    for (const BlockUse& b : unit.material_blocks(m)) {
      r.blocks.push_back(b.name);
      r.ops += b.ops;
      r.texels += b.texels;
    }
    r.relief = unit.material_has_relief(m);
    r.relief_steps = unit.material_relief_steps(m);
    r.relief_fetches = unit.material_relief_fetches(m);
    if (const ObjectSpaceMaterialInfo* os = info.object_space.find(r.name)) {
      // Drawn by the object-space pipeline: its blocks, its pixels, its operations and texels.
      r.fragments = os->pixels_shown;
      r.blocks = os->blocks();
      r.ops = os->result.total_ops();
      r.texels = os->result.texels;
    }
    if (static_cast<size_t>(m) < info.material_accuracy.size())
      r.acc = info.material_accuracy[static_cast<size_t>(m)];
    rows.push_back(r);
  }
  return rows;
}

using Json = nlohmann::ordered_json;

double per_fragment(double v, double frags) { return frags > 0 ? v / frags : 0.0; }

Json block_json(const BlockUse& b, double frags) {
  Json e;
  e["ops"] = ops_json(b.ops);
  e["ops_per_fragment"] = per_fragment(static_cast<double>(b.ops.total()), frags);
  e["latency"] = b.timing.latency;
  e["ii"] = b.timing.ii;
  e["area"] = b.timing.area;
  e["arithmetic"] = b.arithmetic;
  e["materials"] = b.materials;
  e["texels"] = b.texels;
  e["texels_per_fragment"] = per_fragment(static_cast<double>(b.texels), frags);
  if (b.border_taps > 0) e["border_taps"] = b.border_taps;  // only where border mode met a tap
  return e;
}

void add_stages_json(Json& j, const UnitArray& unit) {
  const ClockedPipeline& p = *unit.unit(0).pipeline();
  for (int s = 0; s < p.stage_count(); ++s) {
    const StageStats st = unit.stage_totals(s);
    j["stages"][p.config(s).name] = {{"latency", p.config(s).timing.latency},
                                     {"busy", st.busy},
                                     {"utilisation", unit.utilisation(s)},
                                     {"stalls",
                                      {{"starved", st.stall_starved},
                                       {"blocked", st.stall_blocked},
                                       {"latency_full", st.stall_full},
                                       {"multi_cycle", st.stall_extra}}}};
  }
}

// Compressed textures: where they are decoded and the decoders' work.
void add_decompress_json(Json& j, const UnitArray& unit) {
  if (!unit.textures().any_compressed()) return;
  static constexpr const char* kPlacement[] = {"before_l1", "after_l1", "after_l2"};
  PerCompressedFormat n{};
  for (int u = 0; u < unit.units(); ++u) {
    const PerCompressedFormat d = unit.unit(u).decoded_blocks();
    for (size_t f = 0; f < n.size(); ++f) n[f] += d[f];
  }
  Json formats = Json::object();
  uint64_t total = 0;
  for (size_t f = 0; f < n.size(); ++f) {
    if (n[f] == 0) continue;
    formats[std::string(to_string(static_cast<CompressedFormat>(f)))] = n[f];
    total += n[f];
  }
  Json& e = j["decompress"];
  e["placement"] = kPlacement[static_cast<int>(unit.setup().decompress)];
  e["blocks_decoded"] = total;
  e["blocks_by_format"] = formats;
  if (const BlockDecompressor* d = unit.memory().decompressor()) {
    e["decoded_lines"] = d->stats().lines;
    e["compressed_reads"] = d->stats().compressed_reads;
  }
}

// sRGB textures: where they are decoded to linear and the decoder's work (one decode per
// texel before the filter, per fragment after it).
void add_srgb_json(Json& j, const UnitArray& unit) {
  if (!unit.textures().any_srgb()) return;
  uint64_t fragments = 0, texels = 0;
  for (int u = 0; u < unit.units(); ++u) {
    fragments += unit.unit(u).srgb_fragments();
    texels += unit.unit(u).srgb_texels();
  }
  const SrgbDecode where = unit.setup().srgb_decode;
  j["srgb_decode"] = {{"placement", to_string(where)},
                      {"fragments", fragments},
                      {"texels", texels},
                      {"decodes", where == SrgbDecode::BeforeFilter ? texels : fragments}};
}

// The texture cache's counters and geometry, then DRAM's.
void add_memory_json(Json& j, const UnitArray& unit) {
  const TextureCache::Stats cs = unit.l1_totals();
  j["cache"] = {
      {"hits", cs.hits},
      {"misses", cs.misses},
      {"accesses", cs.accesses},
      {"hit_rate",
       cs.accesses ? static_cast<double>(cs.hits) / static_cast<double>(cs.accesses) : 0.0},
      {"texel_reads", cs.texel_reads},
      {"fill_bytes", cs.fill_bytes},
      {"size_bytes", unit.l1_config().size_bytes},
      {"ways", unit.l1_config().ways},
      {"line_bytes", unit.l1_config().line_bytes}};
  const MemorySystem& mem = unit.memory();
  const DramModel::Stats d = mem.dram_totals();
  j["dram"] = {{"requests", d.requests}, {"bytes", d.bytes}, {"busy_cycles", d.busy_cycles}};
  if (const BankedDram* b = mem.banked()) {
    const BankedDram::Stats& s = b->stats();
    Json& e = j["dram"];
    e["model"] = "banked";
    e["channels"] = b->config().channels;
    e["banks"] = b->config().banks;
    e["row_hits"] = s.row_hits;
    e["row_empty"] = s.row_empty;
    e["row_conflicts"] = s.row_conflicts;
    e["row_hit_rate"] =
        s.requests ? static_cast<double>(s.row_hits) / static_cast<double>(s.requests) : 0.0;
    e["activations"] = s.activations;
    e["bank_wait_cycles"] = s.bank_wait_cycles;
    e["channel_busy_cycles"] = s.bus_busy_cycles;
  }
  if (const L2Cache* l2 = mem.l2()) {
    const L2Cache::Stats& s = l2->stats();
    j["l2"] = {{"accesses", s.accesses},
               {"hits", s.hits},
               {"misses", s.misses},
               {"hit_rate",
                s.accesses ? static_cast<double>(s.hits) / static_cast<double>(s.accesses) : 0.0},
               {"mshr_merges", s.mshr_merges},
               {"mshr_stalls", s.mshr_stalls},
               {"mshr_stall_cycles", s.mshr_stall_cycles},
               {"bank_conflicts", s.bank_conflicts},
               {"bank_conflict_cycles", s.bank_conflict_cycles},
               {"prefetches_issued", s.prefetches_issued},
               {"prefetches_useful", s.prefetches_useful},
               {"fill_bytes", s.fill_bytes},
               {"size_bytes", l2->config().size_bytes},
               {"ways", l2->config().ways},
               {"line_bytes", l2->config().line_bytes},
               {"slices", l2->config().slices}};
  }
  add_decompress_json(j, unit);
  add_srgb_json(j, unit);
  if (!unit.several()) return;
  // Several units: each unit's share, and how exactly the scheduler kept cycle order.
  Json units = Json::array();
  for (int u = 0; u < unit.units(); ++u) {
    const TextureUnit& t = unit.unit(u);
    const TextureCache::Stats& c = t.cache().stats();
    units.push_back(
        {{"unit", u},
         {"fragments", t.fragments()},
         {"cycles", t.cycles()},
         {"l1",
          {{"accesses", c.accesses},
           {"hits", c.hits},
           {"misses", c.misses},
           {"hit_rate",
            c.accesses ? static_cast<double>(c.hits) / static_cast<double>(c.accesses) : 0.0}}}});
  }
  j["units"] = units;
  j["scheduler"] = {{"forced_commits", unit.forced_commits()},
                    {"late_items", unit.late_items()},
                    {"local_commits", unit.local_commits()}};
}

Json accuracy_json(const AccuracyMetrics& a) {
  return {{"psnr_db", a.psnr_db},
          {"nmse", a.nmse},
          {"max_abs", a.max_abs},
          {"mean_abs", a.mean_abs},
          {"pixels", a.pixels}};
}

Json material_json(const MaterialRow& r) {
  Json e;
  e["fragments"] = r.fragments;
  e["blocks"] = r.blocks;
  e["ops"] = ops_json(r.ops);
  e["ops_per_fragment"] = r.per_fragment(static_cast<double>(r.ops.total()));
  e["texels_per_fragment"] = r.per_fragment(static_cast<double>(r.texels));
  if (!r.arithmetic.empty()) e["arithmetic"] = r.arithmetic;
  if (r.relief) {
    e["relief"] = {{"steps", r.relief_steps},
                   {"fetches", r.relief_fetches},
                   {"steps_per_fragment", r.per_fragment(static_cast<double>(r.relief_steps))},
                   {"fetches_per_fragment", r.per_fragment(static_cast<double>(r.relief_fetches))}};
  }
  // Per operation, when some fragment asked for an explicit one: its fragments, and what each
  // of them cost (taps, operations, address-slot issue cycles). "sample" is the rest, the
  // implicit-LOD samples, with the fragment count only (the material's rows hold their costs).
  uint64_t explicit_fragments = 0;
  for (const auto& t : r.op_tallies) explicit_fragments += t.fragments;
  if (explicit_fragments > 0) {
    Json ops;
    ops["sample"] = {{"fragments", r.fragments - explicit_fragments}};
    for (int k = 1; k < kSampleOps; ++k) {
      const TextureUnit::OpTally& t = r.op_tallies[static_cast<size_t>(k)];
      if (t.fragments == 0) continue;
      const double n = static_cast<double>(t.fragments);
      ops[std::string(kSampleOpNames[k])] = {
          {"fragments", t.fragments},
          {"taps_per_fragment", static_cast<double>(t.taps) / n},
          {"ops_per_fragment", static_cast<double>(t.ops.total()) / n},
          {"issue_cycles_per_fragment", static_cast<double>(t.issue_cycles) / n}};
    }
    e["operations"] = ops;
  }
  e["accuracy"] = accuracy_json(r.acc);
  return e;
}

// Cycles and areas in physical terms at the clock of the tech table.
struct Physical {
  double clock_mhz = 0;
  double seconds = 0;               // the run's cycles at the clock
  double fragments_per_second = 0;  // 0 in functional mode (no clock)
  double area_total = 0;            // sum of the listed blocks' areas
};

Physical physical(const RunInfo& info, const UnitArray& unit) {
  Physical ph;
  ph.clock_mhz = info.provenance.tech.clock_mhz;
  ph.seconds = static_cast<double>(unit.cycles()) / (ph.clock_mhz * 1e6);
  if (ph.seconds > 0) ph.fragments_per_second = static_cast<double>(unit.fragments()) / ph.seconds;
  for (const auto& b : unit.blocks()) ph.area_total += b.timing.area;
  return ph;
}

void add_physical_json(Json& j, const RunInfo& info, const UnitArray& unit) {
  const Physical ph = physical(info, unit);
  j["area_total"] = ph.area_total;
  if (!unit.timing()) return;
  j["physical"] = {{"clock_mhz", ph.clock_mhz},
                   {"time_us", ph.seconds * 1e6},
                   {"fragments_per_second", ph.fragments_per_second}};
  uint64_t start = 0;
  for (auto& f : j["frames"]) {
    const auto end = f["cycles_end"].get<uint64_t>();
    f["time_us"] = static_cast<double>(end - start) / ph.clock_mhz;
    start = end;
  }
}

void add_energy_json(Json& j, const EnergyBreakdown& e, double frags) {
  Json blocks;
  for (const auto& [name, pj] : e.blocks) blocks[name] = pj;
  j["energy"] = {{"total_pj", e.total_pj()}, {"per_fragment_pj", per_fragment(e.total_pj(), frags)},
                 {"ops_pj", e.ops_pj},       {"l1_pj", e.l1_pj},
                 {"l2_pj", e.l2_pj},         {"dram_pj", e.dram_pj},
                 {"blocks_pj", blocks}};
}

// Without a ground truth every accuracy figure is null (the keys stay, so readers of the
// report find them) and there is no error map.
void drop_accuracy_figures(Json& j) {
  auto drop = [](Json& a) {
    for (const char* k : {"psnr_db", "nmse", "max_abs", "mean_abs", "mse"})
      if (a.contains(k)) a[k] = nullptr;
  };
  drop(j["accuracy"]);
  for (Json& f : j["frames"])
    if (f.contains("accuracy")) drop(f["accuracy"]);
  if (j.contains("materials"))
    for (auto& [name, m] : j["materials"].items()) drop(m["accuracy"]);
  j.erase("error_map");
}

// report.json; docs/reports.md lists every key.
Json report_json(const RunInfo& info, const UnitArray& unit, const AccuracyMetrics& acc,
                 const std::vector<MaterialRow>& rows) {
  const double frags = static_cast<double>(unit.fragments());
  Json j;
  j["scene"] = info.scene;
  j["trace"] = info.trace;
  j["mode"] = unit.timing() ? "timing" : "functional";
  j["fragments"] = unit.fragments();
  j["cycles"] = unit.cycles();
  j["cycles_per_fragment"] = per_fragment(static_cast<double>(unit.cycles()), frags);
  j["image"] = {{"width", info.width}, {"height", info.height}};
  if (info.frames.size() > 1) j["image"]["frame"] = info.image_frame;
  j["textures"] = info.textures;
  for (const auto& b : unit.blocks()) j["blocks"][b.name] = block_json(b, frags);
  if (unit.timing()) add_stages_json(j, unit);
  add_memory_json(j, unit);
  j["frames"] = Json::array();
  for (size_t i = 0; i < unit.frames().size(); ++i) {
    const FrameStats& f = unit.frames()[i];
    Json e = {{"frame", f.frame}, {"fragments", f.fragments}, {"cycles_end", f.cycles}};
    // Frames are contiguous, so the unit's and the images' frames are the same list.
    if (i < info.frames.size() && info.frames[i].frame == f.frame)
      e["accuracy"] = accuracy_json(info.frames[i].accuracy);
    j["frames"].push_back(e);
  }
  j["accuracy"] = {{"psnr_db", acc.psnr_db},
                   {"nmse", acc.nmse},
                   {"max_abs", acc.max_abs},
                   {"mean_abs", acc.mean_abs},
                   {"mse", acc.mse},
                   {"pixels", acc.pixels},
                   {"reference", info.reference},
                   {"pixel", info.reference_pixel}};
  // Accuracy next to cost, material by material (each material is one method variant).
  for (const MaterialRow& r : rows) j["materials"][r.name] = material_json(r);
  if (!info.board_link.empty()) {
    j["board"] = {{"link", info.board_link},
                  {"blocks", info.board_blocks},
                  {"fragments", info.board_fragments},
                  {"streams", info.board_streams},
                  {"lerps", info.board_lerps}};
  }
  if (unit.front_stages() > 0) {
    const FrontEndStats& fe = unit.front_end_stats();
    j["front_end"] = {
        {"generated", fe.generated}, {"occluded", fe.occluded}, {"rejected", fe.rejected}};
  }
  add_subsystems_json(j, info.subsystems);
  add_object_space_json(j, info.object_space);
  add_physical_json(j, info, unit);
  if (unit.timing()) add_energy_json(j, run_energy(unit, info.provenance.energy), frags);
  if (info.quads.active()) {
    static const char* const kModes[] = {"fragment", "coarse", "fine"};
    const QuadInfo& q = info.quads;
    Json& e = j["quads"];
    e = {{"derivatives", kModes[static_cast<int>(q.derivatives)]},
         {"merge", q.merge},
         {"merged_lookups", q.merged_lookups}};
    if (q.derivatives != QuadDerivatives::Own) {
      // The quads the derivatives came from, and the fragments that kept their own.
      e["quads"] = q.counts.quads;
      e["helper_lanes"] = q.counts.helper_lanes;
      e["own_x"] = q.counts.own_x;
      e["own_y"] = q.counts.own_y;
    }
  }
  if (!info.ledger.empty()) {
    j["ledger"] = ledger_json(info.ledger);
    j["ledger_setup"] = ledger_setup_json(info.ledger);
  }
  j["error_map"] = {{"scale", info.error_scale},
                    {"auto", info.error_scale_auto},
                    {"bar_rows", info.error_bar_rows},
                    {"ticks",
                     {0.0, 0.25 * info.error_scale, 0.5 * info.error_scale, 0.75 * info.error_scale,
                      info.error_scale}}};
  j["provenance"] = provenance_json(info.provenance);
  if (info.workload) add_workload_json(j, *info.workload);
  if (!info.has_truth) drop_accuracy_figures(j);
  return j;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

void md_summary(std::ostream& md, const RunInfo& info, const UnitArray& unit,
                const AccuracyMetrics& acc) {
  const double frags = static_cast<double>(unit.fragments());
  md << "# texsim run report\n\n";
  md << "| | |\n|---|---|\n";
  md << "| scene | `" << info.scene << "` |\n";
  if (!info.trace.empty()) md << "| trace | `" << info.trace << "` |\n";
  md << "| mode | " << (unit.timing() ? "timing" : "functional") << " |\n";
  md << "| image | " << info.width << " × " << info.height;
  if (info.frames.size() > 1)
    md << " (frame " << info.image_frame << " of " << info.frames.size() << " frames)";
  md << " |\n";
  md << "| fragments | " << unit.fragments() << " |\n";
  md << "| cycles | " << unit.cycles() << " ("
     << fmt(per_fragment(static_cast<double>(unit.cycles()), frags)) << " per fragment) |\n";
  const Physical ph = physical(info, unit);
  if (unit.timing()) {
    md << "| time at " << fmt(ph.clock_mhz) << " MHz | " << fmt(ph.seconds * 1e6) << " µs ("
       << fmt(ph.fragments_per_second / 1e6) << " M fragments/s) |\n";
  }
  md << "| area (sum of blocks) | " << fmt(ph.area_total) << " |\n\n";
  md << "## Accuracy against the ground truth\n\n" << info.reference << "\n\n";
  if (!info.has_truth) return;
  md << "| PSNR (dB) | NMSE | max abs error | mean abs error | pixels |\n|---|---|---|---|---|\n";
  md << "| " << fmt(acc.psnr_db) << " | " << fmt(acc.nmse) << " | " << fmt(acc.max_abs) << " | "
     << fmt(acc.mean_abs) << " | " << acc.pixels << " |\n\n";
  if (info.frames.size() <= 1) return;
  md << "Per frame:\n\n| frame | PSNR (dB) | NMSE | max abs error | pixels "
        "|\n|---|---|---|---|---|\n";
  for (const FrameAccuracy& f : info.frames) {
    md << "| " << f.frame << " | " << fmt(f.accuracy.psnr_db) << " | " << fmt(f.accuracy.nmse)
       << " | " << fmt(f.accuracy.max_abs) << " | " << f.accuracy.pixels << " |\n";
  }
  md << "\n";
}

void md_materials(std::ostream& md, const UnitArray& unit, const std::vector<MaterialRow>& rows,
                  bool has_truth) {
  md << "## Materials: accuracy next to cost\n\n"
        "| material | blocks | fragments | PSNR (dB) | NMSE | max abs error | ops/fragment | "
        "texels/fragment |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const MaterialRow& r : rows) {
    md << "| " << r.name << " | " << joined(r.blocks) << " | " << r.fragments << " | "
       << (has_truth ? fmt(r.acc.psnr_db) + " | " + fmt(r.acc.nmse) + " | " + fmt(r.acc.max_abs)
                     : std::string("— | — | —"))
       << " | " << fmt(r.per_fragment(static_cast<double>(r.ops.total()))) << " | "
       << fmt(r.per_fragment(static_cast<double>(r.texels))) << " |\n";
  }
  if (unit.front_stages() > 0) {
    const FrontEndStats& fe = unit.front_end_stats();
    md << "\nCoordinate front end: " << fe.generated << " pixels computed, " << fe.occluded
       << " left after it (occluded or on a shared triangle edge), " << fe.rejected
       << " rejected (coordinates the format cannot hold; drawn as background).\n";
  }
}

void md_blocks(std::ostream& md, const UnitArray& unit) {
  const double frags = static_cast<double>(unit.fragments());
  md << "\n## Blocks (instantiated for this scene's materials)\n\n";
  md << "| block | materials | arithmetic | latency | area |";
  for (auto k : kOpKindNames) md << " " << k << " |";
  md << " ops/fragment | texels |\n|---|---|---|---|---|";
  for (int k = 0; k < kOpKinds; ++k) md << "---|";
  md << "---|---|\n";
  for (const auto& b : unit.blocks()) {
    md << "| " << b.name << " | " << joined(b.materials) << " | " << b.arithmetic << " | "
       << b.timing.latency << " | " << fmt(b.timing.area) << " |";
    for (int k = 0; k < kOpKinds; ++k) md << " " << b.ops.get(static_cast<OpKind>(k)) << " |";
    md << " " << fmt(per_fragment(static_cast<double>(b.ops.total()), frags)) << " | " << b.texels
       << " |\n";
  }
}

void md_stages(std::ostream& md, const UnitArray& unit) {
  const ClockedPipeline& p = *unit.unit(0).pipeline();
  md << "\n## Pipeline stages";
  if (unit.several()) md << " (" << unit.units() << " units, summed)";
  md << "\n\n| stage | latency | utilisation | starved | blocked | in-flight "
        "full | multi-cycle |\n"
        "|---|---|---|---|---|---|---|\n";
  for (int s = 0; s < p.stage_count(); ++s) {
    const StageStats st = unit.stage_totals(s);
    md << "| " << p.config(s).name << " | " << p.config(s).timing.latency << " | "
       << fmt(100.0 * unit.utilisation(s), 3) << "% | " << st.stall_starved << " | "
       << st.stall_blocked << " | " << st.stall_full << " | " << st.stall_extra << " |\n";
  }
}

void md_memory(std::ostream& md, const UnitArray& unit) {
  const TextureCache::Stats cs = unit.l1_totals();
  md << "\n## Texture cache and DRAM\n\n| hits | misses | hit rate | texels read | fill bytes | "
        "DRAM requests |\n"
        "|---|---|---|---|---|---|\n";
  md << "| " << cs.hits << " | " << cs.misses << " | "
     << fmt(cs.accesses ? 100.0 * static_cast<double>(cs.hits) / static_cast<double>(cs.accesses)
                        : 0,
            4)
     << "% | " << cs.texel_reads << " | " << cs.fill_bytes << " | "
     << unit.memory().dram_totals().requests << " |\n";
  md << "\nCache: " << unit.l1_config().size_bytes << " B, " << unit.l1_config().ways << "-way, "
     << unit.l1_config().line_bytes << " B lines, LRU.\n";
  const auto pct = [](uint64_t a, uint64_t b) {
    return fmt(b ? 100.0 * static_cast<double>(a) / static_cast<double>(b) : 0, 4) + "%";
  };
  if (unit.several()) {
    md << "\n"
       << unit.units() << " texture units (one L1 each; screen tiles interleaved):\n\n"
       << "| unit | fragments | cycles | L1 hit rate |\n|---|---|---|---|\n";
    for (int u = 0; u < unit.units(); ++u) {
      const TextureUnit& t = unit.unit(u);
      md << "| " << u << " | " << t.fragments() << " | " << t.cycles() << " | "
         << pct(t.cache().stats().hits, t.cache().stats().accesses) << " |\n";
    }
  }
  if (const L2Cache* l2 = unit.memory().l2()) {
    const L2Cache::Stats& s = l2->stats();
    md << "\nShared L2: " << l2->config().size_bytes << " B, " << l2->config().slices << " slices, "
       << l2->config().line_bytes << " B lines: " << s.accesses << " accesses, hit rate "
       << pct(s.hits, s.accesses) << ", " << s.mshr_merges << " MSHR merges, " << s.bank_conflicts
       << " bank conflicts, " << s.mshr_stalls << " MSHR stalls.\n";
  }
  if (const BankedDram* b = unit.memory().banked()) {
    const BankedDram::Stats& s = b->stats();
    md << "\nDRAM: " << b->config().channels << " channels × " << b->config().banks
       << " banks: row hits " << pct(s.row_hits, s.requests) << ", " << s.row_conflicts
       << " row conflicts, " << s.activations << " activations.\n";
  }
}

void md_energy(std::ostream& md, const EnergyBreakdown& e, double frags) {
  md << "\n## Energy ([tech.energy])\n\n| total (nJ) | per fragment (pJ) | operations | L1 | L2 | "
        "DRAM |\n|---|---|---|---|---|---|\n";
  md << "| " << fmt(e.total_pj() / 1000) << " | " << fmt(per_fragment(e.total_pj(), frags)) << " | "
     << fmt(e.ops_pj / 1000) << " | " << fmt(e.l1_pj / 1000) << " | " << fmt(e.l2_pj / 1000)
     << " | " << fmt(e.dram_pj / 1000) << " |\n\n(operations, L1, L2 and DRAM in nJ)\n";
}

// report.md: the same run for a reader; docs/reports.md describes each section.
std::string report_markdown(const RunInfo& info, const UnitArray& unit, const AccuracyMetrics& acc,
                            const std::vector<MaterialRow>& rows) {
  std::ostringstream md;
  md_summary(md, info, unit, acc);
  md_materials(md, unit, rows, info.has_truth);
  subsystems_markdown(md, info.subsystems);
  object_space_markdown(md, info.object_space);
  md_blocks(md, unit);
  if (unit.timing()) md_stages(md, unit);
  md_memory(md, unit);
  if (unit.timing())
    md_energy(md, run_energy(unit, info.provenance.energy), static_cast<double>(unit.fragments()));
  if (!info.ledger.empty()) ledger_markdown(md, info.ledger);
  if (info.workload) workload_markdown(md, *info.workload);
  if (!info.has_truth) {
    md << "\n## Images\n\n`image.png` (filtered result); no ground truth, so no `reference.png` "
          "or `error.png`.\n";
    provenance_markdown(md, info.provenance);
    return md.str();
  }
  md << "\n## Images\n\n`image.png` (filtered result), `reference.png` (ground truth), `error.png` "
        "(max-channel absolute error, black 0 through red and yellow to white "
     << fmt(info.error_scale)
     << (info.error_scale_auto ? " = the largest error of the imaged frame" : " (--error-scale)")
     << "; below the image a colour bar of " << info.error_bar_rows
     << " rows from 0 at the left to " << fmt(info.error_scale)
     << " at the right, ticks at 0, ¼, ½, ¾ and 1 of the width, their values below in 8-bit "
        "levels, LSB = 1/255).\n";
  provenance_markdown(md, info.provenance);
  return md.str();
}

}  // namespace

void write_run_reports(const std::string& dir, const RunInfo& info, const UnitArray& unit,
                       const AccuracyMetrics& acc) {
  const std::vector<MaterialRow> rows = material_rows(info, unit);
  // Names come from input files and need not be UTF-8: invalid bytes become U+FFFD instead of
  // making the JSON writer throw after the images were written.
  const std::string json = report_json(info, unit, acc, rows)
                               .dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  write_file_atomic(dir + "/report.json", json + "\n");
  write_file_atomic(dir + "/report.md", report_markdown(info, unit, acc, rows));
}

}  // namespace texsim
