#include "pipeline/run_report.h"

#include <cstdio>
#include <sstream>

#include <toml++/toml.h>

#include "pipeline/atomic_file.h"

namespace texsim {

namespace {

toml::table ops_table(const OpCounts& ops) {
  toml::table t;
  for (int k = 0; k < kOpKinds; ++k) {
    t.insert(kOpKindNames[k], static_cast<int64_t>(ops.get(static_cast<OpKind>(k))));
  }
  return t;
}

std::string fmt(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}


}  // namespace

void write_run_reports(const std::string& dir, const RunInfo& info, const TextureUnit& unit,
                       const AccuracyMetrics& acc) {
  const auto blocks = unit.blocks();
  const double frags = static_cast<double>(unit.fragments());
  const auto i64 = [](uint64_t v) { return static_cast<int64_t>(v); };

  toml::table j;
  j.insert("scene", info.scene);
  j.insert("trace", info.trace);
  j.insert("mode", unit.timing() ? "timing" : "functional");
  j.insert("fragments", i64(unit.fragments()));
  j.insert("cycles", i64(unit.cycles()));
  j.insert("cycles_per_fragment", frags > 0 ? static_cast<double>(unit.cycles()) / frags : 0.0);
  toml::table jb;
  for (const auto& b : blocks) {
    toml::table e;
    e.insert("ops", ops_table(b.ops));
    e.insert("ops_per_fragment", frags > 0 ? static_cast<double>(b.ops.total()) / frags : 0.0);
    e.insert("latency", static_cast<int64_t>(b.timing.latency));
    e.insert("ii", static_cast<int64_t>(b.timing.ii));
    e.insert("area", b.timing.area);
    e.insert("arithmetic", b.arithmetic);
    toml::array mats;
    for (const auto& m : b.materials) mats.push_back(m);
    e.insert("materials", mats);
    jb.insert(b.name, e);
  }
  j.insert("blocks", jb);
  if (const ClockedPipeline* p = unit.pipeline()) {
    toml::table js;
    for (int s = 0; s < p->stage_count(); ++s) {
      const StageStats& st = p->stats(s);
      toml::table e;
      e.insert("latency", static_cast<int64_t>(p->config(s).timing.latency));
      e.insert("busy", i64(st.busy));
      e.insert("utilisation", p->utilisation(s));
      toml::table stalls;
      stalls.insert("starved", i64(st.stall_starved));
      stalls.insert("blocked", i64(st.stall_blocked));
      stalls.insert("full", i64(st.stall_full));
      stalls.insert("multi_cycle", i64(st.stall_extra));
      e.insert("stalls", stalls);
      js.insert(p->config(s).name, e);
    }
    j.insert("stages", js);
  }
  const auto& cs = unit.cache().stats();
  toml::table jc;
  jc.insert("hits", i64(cs.hits));
  jc.insert("misses", i64(cs.misses));
  jc.insert("accesses", i64(cs.accesses));
  jc.insert("hit_rate", cs.accesses ? static_cast<double>(cs.hits) / static_cast<double>(cs.accesses) : 0.0);
  jc.insert("texel_reads", i64(cs.texel_reads));
  jc.insert("fill_bytes", i64(cs.fill_bytes));
  jc.insert("size_bytes", static_cast<int64_t>(unit.cache().config().size_bytes));
  jc.insert("ways", static_cast<int64_t>(unit.cache().config().ways));
  jc.insert("line_bytes", static_cast<int64_t>(unit.cache().config().line_bytes));
  j.insert("cache", jc);
  toml::table jd;
  jd.insert("requests", i64(unit.dram().stats().requests));
  jd.insert("bytes", i64(unit.dram().stats().bytes));
  jd.insert("busy_cycles", i64(unit.dram().stats().busy_cycles));
  j.insert("dram", jd);
  toml::array jf;
  for (const auto& f : unit.frames()) {
    toml::table e;
    e.insert("frame", static_cast<int64_t>(f.frame));
    e.insert("fragments", i64(f.fragments));
    e.insert("cycles_end", i64(f.cycles));
    jf.push_back(e);
  }
  j.insert("frames", jf);
  toml::table ja;
  ja.insert("psnr_db", acc.psnr_db);
  ja.insert("nmse", acc.nmse);
  ja.insert("max_abs", acc.max_abs);
  ja.insert("mean_abs", acc.mean_abs);
  ja.insert("mse", acc.mse);
  ja.insert("pixels", i64(acc.pixels));
  ja.insert("reference", info.reference);
  j.insert("accuracy", ja);
  std::ostringstream js;
  js << toml::json_formatter{j} << "\n";
  write_file_atomic(dir + "/report.json", js.str());

  std::ostringstream md;
  md << "# texsim run report\n\n";
  md << "| | |\n|---|---|\n";
  md << "| scene | `" << info.scene << "` |\n";
  if (!info.trace.empty()) md << "| trace | `" << info.trace << "` |\n";
  md << "| mode | " << (unit.timing() ? "timing" : "functional") << " |\n";
  md << "| image | " << info.width << " × " << info.height << " |\n";
  md << "| fragments | " << unit.fragments() << " |\n";
  md << "| cycles | " << unit.cycles() << " (" << fmt(frags > 0 ? static_cast<double>(unit.cycles()) / frags : 0)
     << " per fragment) |\n\n";
  md << "## Accuracy against the ground truth\n\n" << info.reference << "\n\n";
  md << "| PSNR (dB) | NMSE | max abs error | mean abs error | pixels |\n|---|---|---|---|---|\n";
  md << "| " << fmt(acc.psnr_db) << " | " << fmt(acc.nmse) << " | " << fmt(acc.max_abs) << " | "
     << fmt(acc.mean_abs) << " | " << acc.pixels << " |\n\n";
  md << "## Blocks (instantiated for this scene's materials)\n\n";
  md << "| block | materials | arithmetic | latency | area |";
  for (auto k : kOpKindNames) md << " " << k << " |";
  md << " ops/fragment |\n|---|---|---|---|---|";
  for (int k = 0; k < kOpKinds; ++k) md << "---|";
  md << "---|\n";
  for (const auto& b : blocks) {
    std::string mats;
    for (const auto& m : b.materials) mats += (mats.empty() ? "" : ", ") + m;
    md << "| " << b.name << " | " << mats << " | " << b.arithmetic << " | " << b.timing.latency << " | "
       << fmt(b.timing.area) << " |";
    for (int k = 0; k < kOpKinds; ++k) md << " " << b.ops.get(static_cast<OpKind>(k)) << " |";
    md << " " << fmt(frags > 0 ? static_cast<double>(b.ops.total()) / frags : 0) << " |\n";
  }
  if (const ClockedPipeline* p = unit.pipeline()) {
    md << "\n## Pipeline stages\n\n| stage | latency | utilisation | starved | blocked | in-flight full | multi-cycle |\n"
          "|---|---|---|---|---|---|---|\n";
    for (int s = 0; s < p->stage_count(); ++s) {
      const StageStats& st = p->stats(s);
      md << "| " << p->config(s).name << " | " << p->config(s).timing.latency << " | "
         << fmt(100.0 * p->utilisation(s), 3) << "% | " << st.stall_starved << " | " << st.stall_blocked
         << " | " << st.stall_full << " | " << st.stall_extra << " |\n";
    }
  }
  md << "\n## Texture cache and DRAM\n\n| hits | misses | hit rate | texels read | fill bytes | DRAM requests |\n"
        "|---|---|---|---|---|---|\n";
  md << "| " << cs.hits << " | " << cs.misses << " | "
     << fmt(cs.accesses ? 100.0 * static_cast<double>(cs.hits) / static_cast<double>(cs.accesses) : 0, 4) << "% | "
     << cs.texel_reads << " | " << cs.fill_bytes << " | " << unit.dram().stats().requests << " |\n";
  md << "\nCache: " << unit.cache().config().size_bytes << " B, " << unit.cache().config().ways << "-way, "
     << unit.cache().config().line_bytes << " B lines, LRU.\n";
  md << "\n## Images\n\n`image.png` (filtered result), `reference.png` (ground truth), `error.png` "
        "(max-channel absolute error; white = the largest error in this run).\n";
  write_file_atomic(dir + "/report.md", md.str());
}

}  // namespace texsim
