#include "pipeline/report/run_report.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "blocks/base/atomic_file.h"

namespace texsim {

namespace {

std::string fmt(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

// One material's method and what it cost: its blocks' operations and texels over its fragments.
struct MaterialRow {
  std::string name;
  uint64_t fragments = 0;
  std::vector<std::string> blocks;
  OpCounts ops;
  uint64_t texels = 0;
  AccuracyMetrics acc;
  double per_fragment(double v) const {
    return fragments > 0 ? v / static_cast<double>(fragments) : 0.0;
  }
};

std::vector<MaterialRow> material_rows(const RunInfo& info, const TextureUnit& unit) {
  std::vector<MaterialRow> rows;
  for (int m = 0; m < unit.material_count(); ++m) {
    MaterialRow r;
    r.name = unit.material(m).name;
    r.fragments = unit.material_fragments(m);
    for (const BlockUse& b : unit.material_blocks(m)) {
      r.blocks.push_back(b.name);
      r.ops += b.ops;
      r.texels += b.texels;
    }
    if (static_cast<size_t>(m) < info.material_accuracy.size())
      r.acc = info.material_accuracy[static_cast<size_t>(m)];
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

void write_run_reports(const std::string& dir, const RunInfo& info, const TextureUnit& unit,
                       const AccuracyMetrics& acc) {
  const auto blocks = unit.blocks();
  const double frags = static_cast<double>(unit.fragments());

  using Json = nlohmann::ordered_json;
  Json j;
  j["scene"] = info.scene;
  j["trace"] = info.trace;
  j["mode"] = unit.timing() ? "timing" : "functional";
  j["fragments"] = unit.fragments();
  j["cycles"] = unit.cycles();
  j["cycles_per_fragment"] = frags > 0 ? static_cast<double>(unit.cycles()) / frags : 0.0;
  j["image"] = {{"width", info.width}, {"height", info.height}};
  j["textures"] = info.textures;
  for (const auto& b : blocks) {
    Json e;
    for (int k = 0; k < kOpKinds; ++k)
      e["ops"][std::string(kOpKindNames[k])] = b.ops.get(static_cast<OpKind>(k));
    e["ops_per_fragment"] = frags > 0 ? static_cast<double>(b.ops.total()) / frags : 0.0;
    e["latency"] = b.timing.latency;
    e["ii"] = b.timing.ii;
    e["area"] = b.timing.area;
    e["arithmetic"] = b.arithmetic;
    e["materials"] = b.materials;
    e["texels"] = b.texels;
    e["texels_per_fragment"] = frags > 0 ? static_cast<double>(b.texels) / frags : 0.0;
    j["blocks"][b.name] = e;
  }
  if (const ClockedPipeline* p = unit.pipeline()) {
    for (int s = 0; s < p->stage_count(); ++s) {
      const StageStats& st = p->stats(s);
      j["stages"][p->config(s).name] = {{"latency", p->config(s).timing.latency},
                                        {"busy", st.busy},
                                        {"utilisation", p->utilisation(s)},
                                        {"stalls",
                                         {{"starved", st.stall_starved},
                                          {"blocked", st.stall_blocked},
                                          {"latency_full", st.stall_full},
                                          {"multi_cycle", st.stall_extra}}}};
    }
  }
  const auto& cs = unit.cache().stats();
  j["cache"] = {
      {"hits", cs.hits},
      {"misses", cs.misses},
      {"accesses", cs.accesses},
      {"hit_rate",
       cs.accesses ? static_cast<double>(cs.hits) / static_cast<double>(cs.accesses) : 0.0},
      {"texel_reads", cs.texel_reads},
      {"fill_bytes", cs.fill_bytes},
      {"size_bytes", unit.cache().config().size_bytes},
      {"ways", unit.cache().config().ways},
      {"line_bytes", unit.cache().config().line_bytes}};
  j["dram"] = {{"requests", unit.dram().stats().requests},
               {"bytes", unit.dram().stats().bytes},
               {"busy_cycles", unit.dram().stats().busy_cycles}};
  j["frames"] = Json::array();
  for (const auto& f : unit.frames()) {
    j["frames"].push_back(
        {{"frame", f.frame}, {"fragments", f.fragments}, {"cycles_end", f.cycles}});
  }
  j["accuracy"] = {{"psnr_db", acc.psnr_db},     {"nmse", acc.nmse}, {"max_abs", acc.max_abs},
                   {"mean_abs", acc.mean_abs},   {"mse", acc.mse},   {"pixels", acc.pixels},
                   {"reference", info.reference}};
  // Accuracy next to cost, material by material (each material is one method variant).
  const std::vector<MaterialRow> rows = material_rows(info, unit);
  for (const MaterialRow& r : rows) {
    Json e;
    e["fragments"] = r.fragments;
    e["blocks"] = r.blocks;
    for (int k = 0; k < kOpKinds; ++k)
      e["ops"][std::string(kOpKindNames[k])] = r.ops.get(static_cast<OpKind>(k));
    e["ops_per_fragment"] = r.per_fragment(static_cast<double>(r.ops.total()));
    e["texels_per_fragment"] = r.per_fragment(static_cast<double>(r.texels));
    e["accuracy"] = {{"psnr_db", r.acc.psnr_db},
                     {"nmse", r.acc.nmse},
                     {"max_abs", r.acc.max_abs},
                     {"mean_abs", r.acc.mean_abs},
                     {"pixels", r.acc.pixels}};
    j["materials"][r.name] = e;
  }
  if (unit.front_stages() > 0) {
    const FrontEndStats& fe = unit.front_end_stats();
    j["front_end"] = {
        {"generated", fe.generated}, {"occluded", fe.occluded}, {"rejected", fe.rejected}};
  }
  write_file_atomic(dir + "/report.json", j.dump(2) + "\n");

  std::ostringstream md;
  md << "# texsim run report\n\n";
  md << "| | |\n|---|---|\n";
  md << "| scene | `" << info.scene << "` |\n";
  if (!info.trace.empty()) md << "| trace | `" << info.trace << "` |\n";
  md << "| mode | " << (unit.timing() ? "timing" : "functional") << " |\n";
  md << "| image | " << info.width << " × " << info.height << " |\n";
  md << "| fragments | " << unit.fragments() << " |\n";
  md << "| cycles | " << unit.cycles() << " ("
     << fmt(frags > 0 ? static_cast<double>(unit.cycles()) / frags : 0) << " per fragment) |\n\n";
  md << "## Accuracy against the ground truth\n\n" << info.reference << "\n\n";
  md << "| PSNR (dB) | NMSE | max abs error | mean abs error | pixels |\n|---|---|---|---|---|\n";
  md << "| " << fmt(acc.psnr_db) << " | " << fmt(acc.nmse) << " | " << fmt(acc.max_abs) << " | "
     << fmt(acc.mean_abs) << " | " << acc.pixels << " |\n\n";
  md << "## Materials: accuracy next to cost\n\n"
        "| material | blocks | fragments | PSNR (dB) | NMSE | max abs error | ops/fragment | "
        "texels/fragment |\n"
        "|---|---|---|---|---|---|---|---|\n";
  for (const MaterialRow& r : rows) {
    std::string names;
    for (const auto& b : r.blocks) names += (names.empty() ? "" : ", ") + b;
    md << "| " << r.name << " | " << names << " | " << r.fragments << " | " << fmt(r.acc.psnr_db)
       << " | " << fmt(r.acc.nmse) << " | " << fmt(r.acc.max_abs) << " | "
       << fmt(r.per_fragment(static_cast<double>(r.ops.total()))) << " | "
       << fmt(r.per_fragment(static_cast<double>(r.texels))) << " |\n";
  }
  if (unit.front_stages() > 0) {
    const FrontEndStats& fe = unit.front_end_stats();
    md << "\nCoordinate front end: " << fe.generated << " pixels computed, " << fe.occluded
       << " left after it (occluded or on a shared triangle edge), " << fe.rejected
       << " rejected (coordinates the format cannot hold; drawn as background).\n";
  }
  md << "\n## Blocks (instantiated for this scene's materials)\n\n";
  md << "| block | materials | arithmetic | latency | area |";
  for (auto k : kOpKindNames) md << " " << k << " |";
  md << " ops/fragment | texels |\n|---|---|---|---|---|";
  for (int k = 0; k < kOpKinds; ++k) md << "---|";
  md << "---|---|\n";
  for (const auto& b : blocks) {
    std::string mats;
    for (const auto& m : b.materials) mats += (mats.empty() ? "" : ", ") + m;
    md << "| " << b.name << " | " << mats << " | " << b.arithmetic << " | " << b.timing.latency
       << " | " << fmt(b.timing.area) << " |";
    for (int k = 0; k < kOpKinds; ++k) md << " " << b.ops.get(static_cast<OpKind>(k)) << " |";
    md << " " << fmt(frags > 0 ? static_cast<double>(b.ops.total()) / frags : 0) << " | "
       << b.texels << " |\n";
  }
  if (const ClockedPipeline* p = unit.pipeline()) {
    md << "\n## Pipeline stages\n\n| stage | latency | utilisation | starved | blocked | in-flight "
          "full | multi-cycle |\n"
          "|---|---|---|---|---|---|---|\n";
    for (int s = 0; s < p->stage_count(); ++s) {
      const StageStats& st = p->stats(s);
      md << "| " << p->config(s).name << " | " << p->config(s).timing.latency << " | "
         << fmt(100.0 * p->utilisation(s), 3) << "% | " << st.stall_starved << " | "
         << st.stall_blocked << " | " << st.stall_full << " | " << st.stall_extra << " |\n";
    }
  }
  md << "\n## Texture cache and DRAM\n\n| hits | misses | hit rate | texels read | fill bytes | "
        "DRAM requests |\n"
        "|---|---|---|---|---|---|\n";
  md << "| " << cs.hits << " | " << cs.misses << " | "
     << fmt(cs.accesses ? 100.0 * static_cast<double>(cs.hits) / static_cast<double>(cs.accesses)
                        : 0,
            4)
     << "% | " << cs.texel_reads << " | " << cs.fill_bytes << " | " << unit.dram().stats().requests
     << " |\n";
  md << "\nCache: " << unit.cache().config().size_bytes << " B, " << unit.cache().config().ways
     << "-way, " << unit.cache().config().line_bytes << " B lines, LRU.\n";
  md << "\n## Images\n\n`image.png` (filtered result), `reference.png` (ground truth), `error.png` "
        "(max-channel absolute error; white = the largest error in this run).\n";
  write_file_atomic(dir + "/report.md", md.str());
}

}  // namespace texsim
