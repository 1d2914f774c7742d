#include "pipeline/app/study_formats.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "blocks/base/input_error.h"
#include "pipeline/app/run.h"
#include "pipeline/app/study_runs.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/report/number_text.h"
#include "pipeline/scene/scene.h"
#include "pipeline/studies/shipped_scenes.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

namespace {

using Set = StudySet;

// Every row starts from this (the memory study's base), so the scenes' own [pipeline] choices
// (photo's morton layout and 32 KB L1) do not mix into the comparison.
const Set& base_set() { return study_base_set(); }

constexpr uint32_t kL2Bytes = 262144;

// One way of storing every texture of a scene.
struct Variant {
  std::string format;   // storage format, or compressed format
  std::string encoder;  // empty: an uncompressed storage format
  std::string quality;
  std::string srgb_decode = "";  // [pipeline] srgb_decode when not the default
  bool compressed() const { return !encoder.empty(); }
  std::string label() const {
    if (!srgb_decode.empty()) return format + " " + srgb_decode;
    return compressed() ? format + " " + encoder + " " + quality : format;
  }
};

const std::vector<Variant>& all_variants() {
  static const std::vector<Variant> v = {{"rgba8", "", ""},
                                         {"rgb565", "", ""},
                                         {"rgba4444", "", ""},
                                         {"srgb8_a8", "", ""},
                                         {"srgb8_a8", "", "", "after_filter"},
                                         {"rgba16f", "", ""},
                                         {"bc1_rgb", "squish", "range"},
                                         {"bc1_rgb", "squish", "cluster"},
                                         {"bc1_rgb", "nvtt", "normal"},
                                         {"bc3", "squish", "cluster"},
                                         {"bc7", "texsim", "normal"},
                                         {"etc2_rgb8", "texsim", "normal"},
                                         {"astc_4x4", "astcenc", "fast"},
                                         {"astc_6x6", "astcenc", "fast"},
                                         {"astc_8x8", "astcenc", "fast"},
                                         {"astc_12x12", "astcenc", "fast"}};
  return v;
}

// The variants whose decoder placement is swept (and rgba8 beside them).
const std::vector<Variant>& placement_variants() {
  static const std::vector<Variant> v = {{"bc1_rgb", "squish", "cluster"},
                                         {"astc_6x6", "astcenc", "fast"}};
  return v;
}

// The overrides that store every texture of the scene as `v` (rgba8: as loaded).
Set variant_set(const Variant& v, const std::vector<std::string>& textures) {
  Set s;
  if (v.format == "rgba8") return s;
  if (!v.srgb_decode.empty()) s["pipeline.srgb_decode"] = v.srgb_decode;
  for (const std::string& t : textures) {
    if (v.compressed()) {
      s["textures." + t + ".compress"] = "{ format = \"" + v.format + "\", encoder = \"" +
                                         v.encoder + "\", quality = \"" + v.quality + "\" }";
    } else {
      s["textures." + t + ".format"] = v.format;
    }
  }
  return s;
}

struct SceneRef {
  std::string name, path;
  std::vector<std::string> textures;
};

std::vector<SceneRef> scenes_of(const StudyFormatsOptions& opt) {
  std::vector<std::string> paths = opt.scenes;
  if (paths.empty()) {
    paths = {shipped_scenes_dir() + "/photo.toml"};
    if (!opt.quick) paths.push_back(shipped_scenes_dir() + "/cube.toml");
  }
  std::vector<SceneRef> out;
  out.reserve(paths.size());
  for (const std::string& p : paths) {
    SceneRef r{std::filesystem::path(p).stem().string(), p, {}};
    for (const SceneTexture& t : load_scene(p).textures) r.textures.push_back(t.name);
    out.push_back(std::move(r));
  }
  return out;
}

FormatsStudyRow make_row(const SceneRef& sc, const std::string& sweep, const Variant& v,
                         const std::string& placement, const Set& size) {
  FormatsStudyRow r;
  r.scene = sc.name;
  r.scene_path = sc.path;
  r.sweep = sweep;
  r.variant = v.label();
  r.format = v.format;
  r.compressed = v.compressed();
  r.set = with(with(base_set(), size), variant_set(v, sc.textures));
  if (sweep == "placement") {
    r.set["pipeline.l2.size_bytes"] = std::to_string(kL2Bytes);
    r.set["pipeline.l2.slices"] = "1";
  }
  if (r.compressed) {
    r.placement = placement;
    r.set["pipeline.decompress"] = placement;
  }
  return r;
}

void plan_scene(const SceneRef& sc, const StudyFormatsOptions& opt,
                std::vector<FormatsStudyRow>& rows) {
  const int w = opt.width > 0 ? opt.width : opt.quick ? 96 : 240;
  const int h = opt.height > 0 ? opt.height : opt.quick ? 64 : 160;
  const Set size = {{"output.width", std::to_string(w)}, {"output.height", std::to_string(h)}};
  std::vector<Variant> variants = all_variants();
  if (opt.quick) {
    variants = {{"rgba8", "", ""},
                {"rgb565", "", ""},
                {"bc1_rgb", "squish", "range"},
                {"astc_6x6", "astcenc", "fast"}};
  }
  for (const Variant& v : variants) rows.push_back(make_row(sc, "variants", v, "after_l1", size));
  std::vector<Variant> placed = placement_variants();
  if (opt.quick) placed = {{"bc1_rgb", "squish", "range"}};
  rows.push_back(make_row(sc, "placement", {"rgba8", "", ""}, "", size));
  for (const Variant& v : placed) {
    for (const char* p : {"before_l1", "after_l1", "after_l2"})
      rows.push_back(make_row(sc, "placement", v, p, size));
  }
}

uint64_t u64(const nlohmann::json& j, const char* k) { return j.at(k).get<uint64_t>(); }

void read_figures(const nlohmann::json& j, FormatsStudyRow& r) {
  r.fragments = u64(j, "fragments");
  r.cycles = u64(j, "cycles");
  const auto& psnr = j.at("accuracy").at("psnr_db");
  r.psnr_db = psnr.is_number() ? psnr.get<double>() : 0;
  const auto& c = j.at("cache");
  r.l1_accesses = u64(c, "accesses");
  r.l1_hits = u64(c, "hits");
  r.l1_hit_rate = c.at("hit_rate").get<double>();
  r.l1_fill_bytes = u64(c, "fill_bytes");
  r.has_l2 = j.contains("l2");
  if (r.has_l2) {
    const auto& l2 = j.at("l2");
    r.l2_accesses = u64(l2, "accesses");
    r.l2_fill_bytes = u64(l2, "fill_bytes");
    r.l2_hit_rate = l2.at("hit_rate").get<double>();
  }
  r.dram_bytes = u64(j.at("dram"), "bytes");
  r.energy_pj = j.at("energy").at("per_fragment_pj").get<double>();
  if (j.contains("srgb_decode")) {
    const auto& b = j.at("blocks").at("srgb_decode");
    r.srgb_placement = j.at("srgb_decode").at("placement").get<std::string>();
    r.srgb_decodes = u64(j.at("srgb_decode"), "decodes");
    for (const auto& [kind, n] : b.at("ops").items()) r.srgb_ops += n.get<uint64_t>();
    r.srgb_area = b.at("area").get<double>();
    r.srgb_pj = r.per_fragment(j.at("energy").at("blocks_pj").at("srgb_decode").get<double>());
  }
  if (!r.compressed) return;
  const std::string block = "decode." + r.format;
  const auto& b = j.at("blocks").at(block);
  r.blocks_decoded = u64(j.at("decompress"), "blocks_decoded");
  uint64_t ops = 0;
  for (const auto& [kind, n] : b.at("ops").items()) ops += n.get<uint64_t>();
  r.decoder_ops_per_block =
      r.blocks_decoded ? static_cast<double>(ops) / static_cast<double>(r.blocks_decoded) : 0;
  r.decoder_latency = b.at("latency").get<int>();
  r.decoder_ii = b.at("ii").get<int>();
  r.decoder_area = b.at("area").get<double>();
  r.decoder_pj = r.per_fragment(j.at("energy").at("blocks_pj").at(block).get<double>());
}

// One row: a timed run with the ground truth into its own directory, its report read back and
// the directory removed.
void measure(FormatsStudyRow& r, const std::string& dir) {
  RunOptions o;
  o.scene = r.scene_path;
  o.workload = false;
  o.overrides = r.overrides();
  run_study_row(o, dir, " --no-workload", [&r](const nlohmann::json& j) { read_figures(j, r); });
}

std::string opt_num(bool present, double v, int digits) { return present ? fmt(v, digits) : ""; }

StudyTable table(const std::vector<FormatsStudyRow>& rows, bool csv) {
  std::vector<std::string> head = {"scene",
                                   "sweep",
                                   "variant",
                                   "decoder at",
                                   "behind L1",
                                   "fragments",
                                   "PSNR dB",
                                   "L1 hit rate",
                                   "L1 fill B/frag",
                                   "L2 hit rate",
                                   "L2 fill B/frag",
                                   "DRAM B/frag",
                                   "cycles/frag",
                                   "energy pJ/frag",
                                   "blocks decoded/frag",
                                   "decoder ops/block",
                                   "decoder latency/II",
                                   "decoder area",
                                   "decoder pJ/frag",
                                   "sRGB decodes/frag",
                                   "sRGB ops/frag",
                                   "sRGB area",
                                   "sRGB pJ/frag"};
  if (csv) head.push_back("overrides");
  StudyTable t(head, "lllllrrrrrrrrrrrrrrrrrrl");
  for (const FormatsStudyRow& r : rows) {
    auto pf = [&](uint64_t v) { return fmt(r.per_fragment(static_cast<double>(v)), 4); };
    const bool srgb = !r.srgb_placement.empty();
    std::vector<std::string> c = {
        r.scene,
        r.sweep,
        r.variant,
        r.placement,
        r.has_l2 ? "L2 " + std::to_string(kL2Bytes / 1024) + "K + flat DRAM" : "flat DRAM",
        std::to_string(r.fragments),
        fmt(r.psnr_db, 4),
        fmt(r.l1_hit_rate, 4),
        pf(r.l1_fill_bytes),
        opt_num(r.has_l2, r.l2_hit_rate, 4),
        r.has_l2 ? pf(r.l2_fill_bytes) : "",
        pf(r.dram_bytes),
        pf(r.cycles),
        fmt(r.energy_pj, 4),
        r.compressed ? pf(r.blocks_decoded) : "",
        opt_num(r.compressed, r.decoder_ops_per_block, 4),
        r.compressed ? std::to_string(r.decoder_latency) + "/" + std::to_string(r.decoder_ii) : "",
        opt_num(r.compressed, r.decoder_area, 5),
        opt_num(r.compressed, r.decoder_pj, 4),
        srgb ? pf(r.srgb_decodes) : "",
        srgb ? pf(r.srgb_ops) : "",
        opt_num(srgb, r.srgb_area, 5),
        opt_num(srgb, r.srgb_pj, 4)};
    if (csv) {
      std::string o;
      for (const std::string& s : r.overrides()) o += (o.empty() ? "" : " ") + s;
      c.push_back(o);
    }
    t.add(std::move(c));
  }
  return t;
}

std::vector<std::string> scene_names(const std::vector<FormatsStudyRow>& rows) {
  std::vector<std::string> names;
  for (const FormatsStudyRow& r : rows) {
    if (names.empty() || names.back() != r.scene) names.push_back(r.scene);
  }
  return names;
}

// PSNR against DRAM bytes per fragment, one series per scene, each point labelled with its
// variant: the upper left is the better end.
PlotSpec pareto_plot(const std::vector<FormatsStudyRow>& rows) {
  PlotSpec p;
  p.title = "PSNR vs DRAM bytes per fragment (16 KB 4-way L1, decoder after the L1)";
  p.xlabel = "DRAM bytes per fragment";
  p.ylabel = "PSNR against the texture as loaded (dB)";
  p.pareto = ParetoFront::higher_y_better;
  p.logx = true;
  for (const std::string& scene : scene_names(rows)) {
    std::vector<LabelledPoint> pts;
    for (const FormatsStudyRow& r : rows) {
      if (r.scene != scene || r.sweep != "variants") continue;
      pts.push_back({r.per_fragment(static_cast<double>(r.dram_bytes)), r.psnr_db, r.variant});
    }
    p.series.push_back(labelled_series(scene, pts));
  }
  return p;
}

// DRAM bytes per fragment for each placement, one series per scene and format.
PlotSpec placement_plot(const std::vector<FormatsStudyRow>& rows) {
  PlotSpec p;
  p.title = "DRAM bytes per fragment by decoder placement (16 KB L1, 256 KB L2)";
  p.xlabel = "placement (1 before_l1, 2 after_l1, 3 after_l2)";
  p.ylabel = "DRAM bytes per fragment";
  p.logy = true;
  std::map<std::string, std::vector<LabelledPoint>> series;
  std::vector<std::string> order;
  for (const FormatsStudyRow& r : rows) {
    if (r.sweep != "placement" || !r.compressed) continue;
    const std::string name = r.scene + ", " + r.variant;
    if (!series.count(name)) order.push_back(name);
    const double x = r.placement == "before_l1" ? 1 : r.placement == "after_l1" ? 2 : 3;
    series[name].push_back({x, r.per_fragment(static_cast<double>(r.dram_bytes)),
                            "L1 " + fmt(100 * r.l1_hit_rate, 3) + "%"});
  }
  for (const std::string& name : order) p.series.push_back(labelled_series(name, series[name]));
  return p;
}

std::string markdown(const std::vector<FormatsStudyRow>& rows, const StudyFormatsOptions& opt) {
  std::string s =
      "# Study formats: texel storage formats and block compression\n\n"
      "Each row is one timed run with the ground truth (`texsim run SCENE --no-workload`) with "
      "the `--set` overrides of its row (formats.csv, last column) on top of a fixed base: ";
  for (const auto& [k, v] : base_set()) s.append("`").append(k).append("=").append(v).append("` ");
  s += "and every texture of the scene stored in the row's variant. PSNR is against the truth, "
       "which samples the texture as loaded. Per fragment: bytes filled into the L1, into the L2 "
       "(from DRAM) and read from DRAM, cycles, energy ([tech.energy] defaults), blocks decoded "
       "and the decoder's energy (`blocks.decode.<format>`).\n";
  if (opt.quick) s += "\n`--quick`: a handful of rows on photo at 96x64 (a CI check).\n";
  const std::vector<std::pair<std::string, std::string>> sweeps = {
      {"variants", "Formats (decoder after the L1, no L2)"},
      {"placement", "Decoder placement (L2 of 256 KB, one slice, over flat DRAM)"}};
  for (const auto& [key, title] : sweeps) {
    std::vector<FormatsStudyRow> part;
    for (const FormatsStudyRow& r : rows)
      if (r.sweep == key) part.push_back(r);
    if (part.empty()) continue;
    s += "\n## " + title + "\n\n" + table(part, false).markdown();
  }
  return s;
}

}  // namespace

std::vector<std::string> FormatsStudyRow::overrides() const { return overrides_of(set); }

std::vector<FormatsStudyRow> formats_study_plan(const StudyFormatsOptions& opt) {
  std::vector<FormatsStudyRow> rows;
  for (const SceneRef& sc : scenes_of(opt)) plan_scene(sc, opt, rows);
  return rows;
}

int run_study_formats(const std::string& out_dir, std::ostream& log, const StudyFormatsOptions& opt,
                      std::vector<FormatsStudyRow>* out_rows) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudyFiles files(out_dir);
  std::vector<FormatsStudyRow> rows = formats_study_plan(opt);
  log << "study formats: " << rows.size() << " runs\n";
  const std::string work = files.path(".runs");
  parallel_tasks(rows.size(), opt.threads,
                 [&](size_t k) { measure(rows[k], work + "/" + std::to_string(k)); });
  std::filesystem::remove_all(work);
  files.csv("formats.csv", table(rows, true));
  files.text("formats.md", markdown(rows, opt));
  files.plot("formats_pareto.png", pareto_plot(rows));
  files.plot("formats_placement.png", placement_plot(rows));
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study formats: wrote " << out_dir
      << "/formats.csv, formats.md, formats_pareto.png, formats_placement.png in " << fmt(secs, 3)
      << " s\n";
  if (out_rows) *out_rows = std::move(rows);
  return 0;
}

}  // namespace texsim
