#include "pipeline/studies/study_filters_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace texsim {

namespace {

std::string fmt_g(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

double per(uint64_t v, uint64_t n) {
  return n ? static_cast<double>(v) / static_cast<double>(n) : 0.0;
}
double per(double v, uint64_t n) { return n ? v / static_cast<double>(n) : 0.0; }

std::string csv_quote(const std::string& s) { return "\"" + s + "\""; }

std::vector<std::string> by_anisotropy_header_named(const std::string& first,
                                                    const StudyFiltersOptions& opt) {
  std::vector<std::string> h = {first};
  for (double a : opt.anisotropies) h.push_back(num(a) + ":1");
  return h;
}

void ops_cells(const OpCounts& o, uint64_t n, std::vector<std::string>& cells) {
  for (int k = 0; k < kOpKinds; ++k) cells.push_back(fmt_g(per(o.get(static_cast<OpKind>(k)), n)));
}

// Pooled figures of one method over a set of rows.
struct Pooled {
  const StudyFilterMethod* method = nullptr;
  uint64_t pixels = 0, fragments = 0;
  double se = 0, sref = 0, max_abs = 0;
  double se_box = 0, sref_box = 0;  // against the box-pixel truth
  FilterTally tally;
  uint64_t misses = 0, cycles = 0;
  double area = 0, seconds = 0, se_pair = 0, sref_pair = 0;
  uint32_t latency = 0;
  bool hardware() const { return method->hardware(); }
  double mse() const { return pixels ? se / (3.0 * static_cast<double>(pixels)) : 0; }
  double psnr() const { return mse() > 0 ? 10.0 * std::log10(1.0 / mse()) : 999.0; }
  double nmse() const { return sref > 0 ? se / sref : 0; }
  double psnr_box() const {
    const double m = pixels ? se_box / (3.0 * static_cast<double>(pixels)) : 0;
    return m > 0 ? 10.0 * std::log10(1.0 / m) : 999.0;
  }
  double nmse_box() const { return sref_box > 0 ? se_box / sref_box : 0; }
  void add(const FilterRow& r) {
    method = r.method;
    area = r.run.area;
    latency = r.run.latency;
    pixels += r.acc.pixels;
    fragments += r.fragments;
    se += r.se;
    sref += r.sref;
    se_box += r.se_box;
    sref_box += r.sref_box;
    max_abs = std::max(max_abs, r.acc.max_abs);
    tally.ops += r.run.tally.ops;
    tally.texels += r.run.tally.texels;
    tally.visited += r.run.tally.visited;
    tally.map_reads += r.run.tally.map_reads;
    tally.fallbacks += r.run.tally.fallbacks;
    tally.shader_cycles += r.run.tally.shader_cycles;
    misses += r.run.misses;
    cycles += r.run.cycles;
    seconds += r.seconds;
    se_pair += r.se_pair;
    sref_pair += r.sref_pair;
  }
};

std::vector<Pooled> pool(const std::vector<FilterRow>& rows,
                         const std::vector<StudyFilterMethod>& methods) {
  std::vector<Pooled> out(methods.size());
  for (const FilterRow& r : rows) out[static_cast<size_t>(r.method - methods.data())].add(r);
  return out;
}

StudyTable csv_table(const std::vector<FilterRow>& rows) {
  std::vector<std::string> head = {"texture", "aniso_nominal", "aniso_p50", "aniso_p90",
                                   "method",  "family",        "pixels",    "psnr_db",
                                   "nmse",    "max_abs",       "mean_abs"};
  for (int k = 0; k < kOpKinds; ++k)
    head.push_back(std::string(kOpKindNames[static_cast<size_t>(k)]) + "_per_frag");
  for (const char* c :
       {"texels_per_frag", "visited_per_frag", "map_reads_per_frag", "cache_misses_per_frag",
        "cycles_per_frag", "shader_cycles_per_frag", "fallback_frac", "latency_cycles", "area",
        "nmse_vs", "nmse_vs_method", "arithmetic", "psnr_box_db", "nmse_box"})
    head.emplace_back(c);
  StudyTable t(head);
  for (const FilterRow& r : rows) {
    const StudyFilterMethod& m = *r.method;
    const FilterTally& y = r.run.tally;
    const uint64_t n = r.fragments;
    std::vector<std::string> c = {r.texture,
                                  num(r.nominal),
                                  fmt_g(r.aniso_p50, 5),
                                  fmt_g(r.aniso_p90, 5),
                                  csv_quote(m.name),
                                  m.family,
                                  std::to_string(r.acc.pixels),
                                  fmt_g(r.acc.psnr_db, 5),
                                  fmt_g(r.acc.nmse, 5),
                                  fmt_g(r.acc.max_abs, 5),
                                  fmt_g(r.acc.mean_abs, 5)};
    ops_cells(y.ops, n, c);
    for (uint64_t v : {y.texels, y.visited, y.map_reads}) c.push_back(fmt_g(per(v, n), 5));
    const bool hw = m.hardware();
    c.push_back(hw ? fmt_g(per(r.run.misses, n), 5) : "");
    c.push_back(hw ? fmt_g(per(r.run.cycles, n), 5) : "");
    c.push_back(hw ? fmt_g(per(y.shader_cycles, n), 5) : "");
    c.push_back(fmt_g(per(y.fallbacks, n), 4));
    c.push_back(hw ? std::to_string(r.run.latency) : "");
    c.push_back(hw ? fmt_g(r.run.area, 5) : "");
    c.push_back(!m.compare_to.empty() && r.sref_pair > 0 ? fmt_g(r.se_pair / r.sref_pair, 5) : "");
    c.push_back(csv_quote(m.compare_to));
    c.push_back(csv_quote(m.arithmetic));
    c.push_back(fmt_g(r.acc_box.psnr_db, 5));
    c.push_back(fmt_g(r.acc_box.nmse, 5));
    t.add(std::move(c));
  }
  return t;
}

// Wall-clock time of each method per view, apart from filters.csv so that the study's figures
// are the same on every run and machine.
StudyTable timing_table(const std::vector<FilterRow>& rows) {
  StudyTable t({"texture", "aniso_nominal", "method", "fragments", "functional_ns_per_lookup"});
  for (const FilterRow& r : rows) {
    t.add({r.texture, num(r.nominal), csv_quote(r.method->name), std::to_string(r.fragments),
           fmt_g(1e9 * per(r.seconds, r.fragments), 4)});
  }
  return t;
}

// The two truths of each view against each other.
StudyTable truths_table(const std::vector<ViewTruths>& truths) {
  StudyTable t(
      {"texture", "aniso_nominal", "psnr_box_vs_gaussian_db", "nmse_box_vs_gaussian", "max_abs"});
  for (const ViewTruths& v : truths) {
    t.add({v.texture, num(v.nominal), fmt_g(v.box_vs_gaussian.psnr_db, 5),
           fmt_g(v.box_vs_gaussian.nmse, 5), fmt_g(v.box_vs_gaussian.max_abs, 5)});
  }
  return t;
}

std::string md_truths(const std::vector<ViewTruths>& truths, const StudyFiltersOptions& opt) {
  StudyTable t(by_anisotropy_header_named("texture", opt));
  for (const char* tname : {"checker", "photo", "noise"}) {
    std::vector<std::string> c = {tname};
    for (double a : opt.anisotropies) {
      for (const ViewTruths& v : truths) {
        if (v.texture == tname && v.nominal == a) c.push_back(fmt_g(v.box_vs_gaussian.psnr_db, 4));
      }
    }
    t.add(std::move(c));
  }
  return "\n## The two truths: PSNR (dB) of the box-pixel truth against the Gaussian-pixel truth "
         "per view\n\n" +
         t.markdown();
}

// The methods ranked by pooled PSNR against one truth (best first; ties in table order).
std::string md_ranking(const std::vector<Pooled>& all, bool box) {
  std::vector<const Pooled*> order;
  for (const Pooled& p : all) {
    if (p.fragments > 0) order.push_back(&p);
  }
  std::stable_sort(order.begin(), order.end(), [box](const Pooled* a, const Pooled* b) {
    return box ? a->psnr_box() > b->psnr_box() : a->psnr() > b->psnr();
  });
  StudyTable t({"rank", "method", "family", "PSNR dB", "NMSE",
                box ? "PSNR dB (Gaussian truth)" : "PSNR dB (box truth)"});
  int rank = 0;
  for (const Pooled* p : order) {
    t.add({std::to_string(++rank), p->method->name, p->method->family,
           fmt_g(box ? p->psnr_box() : p->psnr(), 4), fmt_g(box ? p->nmse_box() : p->nmse(), 3),
           fmt_g(box ? p->psnr() : p->psnr_box(), 4)});
  }
  return std::string(box ? "\n## Ranking against the box-pixel truth (the pixel's square, "
                           "uniform weight: `[reference] pixel = box`)\n\n"
                         : "\n## Ranking against the Gaussian-pixel truth (σ = 0.5 px truncated "
                           "at 1 px: `[reference] pixel = gaussian`)\n\n") +
         t.markdown();
}

std::string md_intro(const StudyFiltersOptions& opt) {
  std::ostringstream o;
  o << "# Anisotropic filters: error against the Gaussian-footprint ground truth, and what it "
       "costs\n\n"
    << "Views: a plane tilted so that the footprint's anisotropy at the image centre is ";
  for (size_t i = 0; i < opt.anisotropies.size(); ++i)
    o << (i ? ", " : "") << opt.anisotropies[i] << ":1";
  o << " (it varies across the image: the p50/p90 columns of filters.csv give the measured "
       "spread), "
    << opt.size << "×" << opt.size << " pixels, " << opt.texels_per_pixel
    << " level-0 texels per pixel along the minor axis at the centre, wrap addressing. Textures: "
       "checkerboard 256² (16 cells), photo crate-base.png 512², value noise 256² (32 cells).\n\n"
    << "Ground truth: level 0 reconstructed bilinearly, integrated over each pixel's footprint "
       "with ≥ 32×32 screen-space supersamples (4 per texel of footprint extent) through the exact "
       "projective map, Gaussian pixel model σ = 0.5 px truncated at 1 px (EWA's α = 2 at R = 1 "
       "px). "
       "A second truth, the box pixel (the pixel's square, uniform weight, the same sample "
       "density over it), ranks the methods again: the ranking depends on the pixel model. Every "
       "table uses the Gaussian-pixel truth unless its heading names the box; filters.csv has "
       "both (psnr_db, nmse: Gaussian; psnr_box_db, nmse_box: box), filters_truths.csv the two "
       "truths against each other per view.\n\n"
    << "Cycles: each method as a material of the texture unit (TextureUnit, the pipeline `texsim "
       "run` simulates: LOD → address or footprint filter → cache 16 KiB 4-way, 64 B lines, 4 "
       "texels/cycle → DRAM 100 cycles → blend), default [pipeline] and technology table; cycles "
       "per fragment = last fragment's leave time / fragments. Shader cycles: not a pipeline "
       "model but an issue bound computed from each fragment's op counts, for a shader "
       "implementation ("
    << kAluOpsPerCycle << " ALU ops/cycle, " << kTexFetchesPerCycle
    << " texture fetches/cycle; one fetch per texel or per filtered weight-map read).\n\n";
  return o.str();
}

std::string md_pooled(const std::vector<Pooled>& all) {
  StudyTable t({"method",      "family",      "PSNR dB",
                "NMSE",        "max err",     "texels/frag",
                "misses/frag", "cycles/frag", "shader cycles/frag",
                "add",         "mul",         "div",
                "rcp",         "sqrt",        "lut",
                "cmp",         "mem",         "fallback %",
                "latency",     "area"});
  for (const Pooled& p : all) {
    const uint64_t n = p.fragments;
    std::vector<std::string> c = {p.method->name,      p.method->family,
                                  fmt_g(p.psnr(), 4),  fmt_g(p.nmse(), 3),
                                  fmt_g(p.max_abs, 3), fmt_g(per(p.tally.texels, n), 4)};
    const bool hw = p.hardware();
    c.push_back(hw ? fmt_g(per(p.misses, n), 3) : "—");
    c.push_back(hw ? fmt_g(per(p.cycles, n), 4) : "—");
    c.push_back(hw ? fmt_g(per(p.tally.shader_cycles, n), 4) : "—");
    ops_cells(p.tally.ops, n, c);
    c.push_back(fmt_g(100.0 * per(p.tally.fallbacks, n), 3));
    c.push_back(hw ? std::to_string(p.latency) : "—");
    c.push_back(hw ? fmt_g(p.area, 4) : "—");
    t.add(std::move(c));
  }
  return "## All views pooled (Σ err² / Σ ref² over every compared pixel)\n\n" + t.markdown();
}

std::vector<std::string> by_anisotropy_header(const StudyFiltersOptions& opt) {
  return by_anisotropy_header_named("method", opt);
}

std::string md_by_anisotropy(const std::vector<FilterRow>& rows,
                             const std::vector<StudyFilterMethod>& methods,
                             const StudyFiltersOptions& opt) {
  std::string s;
  for (const char* tname : {"checker", "photo", "noise"}) {
    StudyTable t(by_anisotropy_header(opt));
    for (const StudyFilterMethod& m : methods) {
      std::vector<std::string> c = {m.name};
      for (double a : opt.anisotropies) {
        for (const FilterRow& r : rows) {
          if (r.texture == tname && r.nominal == a && r.method == &m)
            c.push_back(fmt_g(r.acc.psnr_db, 4));
        }
      }
      t.add(std::move(c));
    }
    s += std::string("\n## PSNR (dB) by nominal anisotropy: ") + tname + "\n\n" + t.markdown();
  }
  StudyTable t(by_anisotropy_header(opt));
  for (const StudyFilterMethod& m : methods) {
    if (!m.hardware()) continue;
    std::vector<std::string> c = {m.name};
    for (double a : opt.anisotropies) {
      uint64_t cyc = 0, n = 0;
      for (const FilterRow& r : rows) {
        if (r.nominal == a && r.method == &m) {
          cyc += r.run.cycles;
          n += r.fragments;
        }
      }
      c.push_back(fmt_g(per(cyc, n), 4));
    }
    t.add(std::move(c));
  }
  return s + "\n## Cycles per fragment by nominal anisotropy (all textures)\n\n" + t.markdown();
}

const Pooled* find(const std::vector<Pooled>& all, const std::string& name) {
  for (const Pooled& p : all) {
    if (p.method->name == name) return &p;
  }
  return nullptr;
}

std::string md_claims(const std::vector<Pooled>& all) {
  std::ostringstream o;
  o << "\n## The seed's claims, re-measured\n\n"
    << "**Weight maps vs computed weights** (thesis ch. 3/5: NMSE 0.000708, +25% speed). Each map "
       "holds the power-8 function the computed row evaluates; NMSE is the map image against the "
       "computed-weight image over all views; speed = cycles(computed) / cycles(map) − 1.\n\n";
  StudyTable t({"map", "against", "memory (bytes)", "NMSE vs computed", "seed NMSE",
                "NMSE vs truth", "speed-up, pipelined", "speed-up, shader model", "seed speed-up"});
  for (const Pooled& p : all) {
    if (p.method->family != "weight map") continue;
    const Pooled* own = find(all, p.method->compare_to);
    if (!own) continue;
    const double nm = p.sref_pair > 0 ? p.se_pair / p.sref_pair : 0;
    const double sp =
        p.cycles ? static_cast<double>(own->cycles) / static_cast<double>(p.cycles) - 1 : 0;
    const double ss =
        p.tally.shader_cycles > 0 ? own->tally.shader_cycles / p.tally.shader_cycles - 1 : 0;
    t.add({p.method->name, p.method->compare_to, std::to_string(p.method->map_bytes), fmt_g(nm, 3),
           "0.000708", fmt_g(p.nmse(), 3), fmt_g(100 * sp, 3) + "%", fmt_g(100 * ss, 3) + "%",
           "+25%"});
  }
  o << t.markdown();
  const Pooled* pc = find(all, "ewa pow8 computed");
  const Pooled* pu = find(all, "ewa uniform weights");
  if (pc && pu) {
    const double sp = static_cast<double>(pc->cycles) / static_cast<double>(pu->cycles) - 1;
    const double ss = pc->tally.shader_cycles / pu->tally.shader_cycles - 1;
    o << "\n**Computing Gaussian weights in real time costs ≤ 5%** (thesis ch. 5): computed "
         "power-8 weights against uniform weights over the same ellipse: pipelined "
      << fmt_g(100 * sp, 3) << "% more cycles, shader model " << fmt_g(100 * ss, 3)
      << "% more cycles; PSNR " << fmt_g(pu->psnr(), 4) << " dB (uniform) → "
      << fmt_g(pc->psnr(), 4) << " dB (Gaussian).\n";
  }
  return o.str();
}

// NMSE against cycles (or texels) per fragment: one labelled series per family, and the
// Pareto front over all hardware methods.
PlotSpec pareto_plot(const std::vector<Pooled>& all, bool by_cycles) {
  PlotSpec p;
  p.title = by_cycles ? "Anisotropic filters: NMSE vs cycles per fragment (all views pooled)"
                      : "Anisotropic filters: NMSE vs texels fetched per fragment (all views "
                        "pooled)";
  p.xlabel = by_cycles ? "cycles per fragment" : "texels fetched per fragment";
  p.ylabel = "NMSE vs ground truth";
  p.pareto = ParetoFront::lower_y_better;
  p.logx = true;
  p.logy = true;
  std::map<std::string, std::vector<LabelledPoint>> fam;
  std::vector<LabelledPoint> pts;
  for (const Pooled& q : all) {
    if (!q.hardware() || q.fragments == 0) continue;
    const double x = by_cycles ? per(q.cycles, q.fragments) : per(q.tally.texels, q.fragments);
    fam[q.method->family].push_back({x, q.nmse(), q.method->name});
    pts.push_back({x, q.nmse(), q.method->name});
  }
  for (const auto& [family, points] : fam) p.series.push_back(labelled_series(family, points));
  std::sort(pts.begin(), pts.end(), [](const LabelledPoint& a, const LabelledPoint& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  PlotSeries front;
  front.label = "Pareto front";
  front.lines = true;
  double best = 1e300;
  for (const LabelledPoint& q : pts) {
    if (q.y < best) {
      best = q.y;
      front.x.push_back(q.x);
      front.y.push_back(q.y);
    }
  }
  p.series.push_back(front);
  return p;
}

}  // namespace

void write_study_filters_outputs(const StudyFiles& files, const std::vector<FilterRow>& rows,
                                 const std::vector<ViewTruths>& truths,
                                 const std::vector<StudyFilterMethod>& methods,
                                 const StudyFiltersOptions& opt, std::ostream& log) {
  files.csv("filters.csv", csv_table(rows));
  files.csv("filters_timing.csv", timing_table(rows));
  files.csv("filters_truths.csv", truths_table(truths));
  const std::vector<Pooled> all = pool(rows, methods);
  files.text("filters.md", md_intro(opt) + md_pooled(all) + md_ranking(all, false) +
                               md_ranking(all, true) + md_truths(truths, opt) +
                               md_by_anisotropy(rows, methods, opt) + md_claims(all));
  files.plot("filters.png", pareto_plot(all, true));
  files.plot("filters_texels.png", pareto_plot(all, false));
  for (const Pooled& p : all) {
    log << "  " << p.method->name << ": PSNR " << fmt_g(p.psnr(), 4) << " dB, NMSE "
        << fmt_g(p.nmse(), 3) << " (box truth: " << fmt_g(p.psnr_box(), 4) << " dB)";
    if (p.hardware()) {
      log << ", texels/frag " << fmt_g(per(p.tally.texels, p.fragments), 4) << ", cycles/frag "
          << fmt_g(per(p.cycles, p.fragments), 4);
    }
    log << ", " << fmt_g(1e9 * per(p.seconds, p.fragments), 4) << " ns/lookup\n";
  }
}

}  // namespace texsim
