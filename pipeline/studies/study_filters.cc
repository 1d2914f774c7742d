#include "pipeline/studies/study_filters.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <sstream>
#include <tuple>

#include "blocks/base/atomic_file.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/feline_filter.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "blocks/texture/footprint/weight_map.h"
#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/texture_cache.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/kernel/clocked_pipeline.h"
#include "pipeline/reference/footprint_reference.h"
#include "pipeline/reference/oiio_peer.h"
#include "pipeline/report/image_metrics.h"
#include "pipeline/report/plot.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"

namespace texsim {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string fmt_g(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

// ---- Scenes -------------------------------------------------------------------------------

struct StudyTexture {
  std::string name;  // "checker", "photo", "noise"
  std::string source;
  Texture tex;
};

// One view: a plane tilted by θ = acos(1/N) about the screen's x axis, seen by a camera with a
// 20° field of view, so the footprint's anisotropy at the image centre is N. The plane spans
// depths D/2 … 2D along its receding axis (no horizon: footprints stay finite) and its texture
// scale puts `tpp` level-0 texels per pixel on the minor axis at the centre.
struct View {
  double nominal = 1;
  Scene scene;
  std::unique_ptr<PlaneProjection> proj;
};

std::string view_scene_text(double aniso, int size, double tpp, int tex_size) {
  const double D = 10.0;
  const double theta = std::acos(1.0 / aniso);
  const double cs = std::cos(theta), sn = std::sin(theta);
  const double su = 0.8 * D, sv = 1.5 * D;
  const double pixel = 2.0 * D * std::tan(10.0 * kPi / 180.0) / size;  // world size at depth D
  const double texel = pixel / tpp;
  const double ox = -su / 2, oy = -0.5 * D * cs, oz = -D + 0.5 * D * sn;
  std::ostringstream s;
  s.precision(17);
  s << "[output]\nwidth = " << size << "\nheight = " << size << "\nbackground = [0.0, 0.0, 0.0]\n"
    << "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nup = [0.0, 1.0, 0.0]\n"
    << "fov_y = 20.0\nnear = 0.01\n"
    << "[textures.t]\nsource = \"procedural:checker?size=4\"\n"
    << "[materials.m]\ntexture = \"t\"\n"
    << "[[planes]]\nmaterial = \"m\"\norigin = [" << ox << ", " << oy << ", " << oz << "]\n"
    << "edge_u = [" << su << ", 0.0, 0.0]\nedge_v = [0.0, " << sv * cs << ", " << -sv * sn << "]\n"
    << "uv_scale = [" << su / (texel * tex_size) << ", " << sv / (texel * tex_size) << "]\n";
  return s.str();
}

// ---- Methods ------------------------------------------------------------------------------

using FilterFn =
    std::function<FilterOutput(const Texture&, const Fragment&, std::vector<TexelRef>&, OpCounts&)>;

struct Method {
  std::string name;
  std::string family;  // baseline, ewa, weight map, probes, oiio
  std::string arithmetic;
  FilterFn run;
  TimingSpec front;   // per-fragment stage in front (LOD unit); latency 1 if none
  TimingSpec filter;  // address/scan stage; a fragment occupies it issue(stats) cycles
  std::function<uint32_t(const FilterStats&)> issue;
  double area = 0;  // front + filter datapaths (adder equivalents)
  // Shader-like model: arithmetic a texture unit would do for a map read (interpolation),
  // per map read, and entries per read (4 bilinear, 2 linear).
  double tmu_ops_per_map_read = 0;
  uint32_t entries_per_map_read = 0;
  bool hardware = true;    // false: a software peer (no cycles, no cache model)
  std::string compare_to;  // also report the NMSE of this method's image against that method's
  uint64_t map_bytes = 0;  // weight-map memory
};

Method baseline(const std::string& name, AnisoMode aniso, const TechTable& tech) {
  LodUnit::Config lc;
  lc.aniso = aniso;
  lc.max_aniso = 16;
  TexelAddressGen::Config ac;
  ac.filter = FilterMode::Trilinear;
  const LodUnit lod(lc);
  const TexelAddressGen addr(ac);
  const TexelBlend blend{TexelBlend::Config{}};
  auto taps = std::make_shared<FilterTaps>();
  Method m;
  m.name = name;
  m.family = "baseline";
  m.arithmetic = "float32 LOD and coordinates, u0.8 weights, float32 blend";
  m.run = [lod, addr, blend, taps](const Texture& tex, const Fragment& f,
                                   std::vector<TexelRef>& fetched, OpCounts& ops) {
    FilterOutput o;
    const LodResult l = lod.eval(f, tex.width(0), tex.height(0), ops);
    addr.taps(tex, f.u, f.v, l, *taps, ops);
    o.colour = blend.blend(*taps, tex, ops);
    for (int i = 0; i < taps->count; ++i) {
      const TexelTap& t = taps->tap[static_cast<size_t>(i)];
      fetched.push_back({t.level, t.x, t.y});
    }
    o.stats.texels = static_cast<uint32_t>(taps->count);
    o.stats.probes = TexelAddressGen::issue_cycles(l);
    o.stats.visited = o.stats.probes;
    o.stats.level = taps->count > 0 ? taps->tap[0].level : 0;
    return o;
  };
  m.front = lod.timing(tech);
  m.filter = addr.timing(tech);
  m.issue = [](const FilterStats& s) { return std::max<uint32_t>(1, s.probes); };
  m.area = m.front.area + m.filter.area;
  return m;
}

Method ewa_method(const std::string& name, const std::string& family, const EwaFilter::Config& c,
                  const TechTable& tech, std::shared_ptr<const WeightMap> map = nullptr) {
  auto ewa = std::make_shared<const EwaFilter>(c, map);
  Method m;
  m.name = name;
  m.family = family;
  m.arithmetic = ewa->arithmetic();
  m.run = [ewa](const Texture& tex, const Fragment& f, std::vector<TexelRef>& fetched,
                OpCounts& ops) { return ewa->filter(tex, f, &fetched, ops); };
  m.front = TimingSpec{1, 1, 1, 0};
  m.filter = ewa->timing(tech);
  m.issue = [ewa](const FilterStats& s) { return ewa->issue_cycles(s); };
  m.area = m.filter.area;
  if (c.weight == EwaFilter::Weight::Map && ewa->weight_map()) {
    const WeightMap& wm = *ewa->weight_map();
    const OpCounts r = wm.ops_per_item();
    m.entries_per_map_read = static_cast<uint32_t>(r.mem);
    m.tmu_ops_per_map_read = static_cast<double>(r.arithmetic());
    m.map_bytes = wm.bytes();
  }
  return m;
}

// A block with filter(), timing() and issue_cycles() as one method.
template <class Block>
Method block_method(const std::string& name, const std::string& family,
                    std::shared_ptr<const Block> b, const TechTable& tech,
                    const std::string& arithmetic) {
  Method m;
  m.name = name;
  m.family = family;
  m.arithmetic = arithmetic;
  m.run = [b](const Texture& tex, const Fragment& f, std::vector<TexelRef>& fetched,
              OpCounts& ops) { return b->filter(tex, f, &fetched, ops); };
  m.front = TimingSpec{1, 1, 1, 0};
  m.filter = b->timing(tech);
  m.issue = [b](const FilterStats& s) { return b->issue_cycles(s); };
  m.area = m.filter.area;
  return m;
}

// ---- Timing harness: front → filter → cache (+DRAM) → blend, as the texture unit ----------

struct HarnessConfig {
  TextureCache::Config cache;
  DramModel::Config dram;
  TexelBlend::Config blend;
  uint32_t fifo_depth = 4;
};

class Harness {
 public:
  Harness(const Method& m, const HarnessConfig& hc, const TechTable& tech)
      : hc_(hc), cache_(hc.cache), dram_(hc.dram), blend_(hc.blend) {
    auto one_item = [](TimingSpec t) {  // a fragment-serial stage: lanes work inside one item
      t.lanes = 1;
      t.ii = 1;
      return t;
    };
    TimingSpec cache_t;
    cache_t.latency = hc.cache.hit_latency;
    std::vector<StageConfig> st(4);
    st[0] = {"front", one_item(m.front), hc.fifo_depth, 0};
    st[1] = {"filter", one_item(m.filter), hc.fifo_depth, 0};
    st[2] = {"cache", cache_t, hc.fifo_depth, hc.cache.miss_queue};
    st[3] = {"blend", one_item(blend_.timing(tech)), hc.fifo_depth, 0};
    pipe_ = std::make_unique<ClockedPipeline>(std::move(st));
  }

  void issue(const Texture& tex, const std::vector<TexelRef>& fetched, uint32_t filter_cycles) {
    lines_.clear();
    for (const TexelRef& t : fetched)
      lines_.push_back(cache_.line_of(tex.address(t.level, t.x, t.y)));
    std::sort(lines_.begin(), lines_.end());
    lines_.erase(std::unique(lines_.begin(), lines_.end()), lines_.end());
    const auto n = static_cast<uint32_t>(fetched.size());
    const uint32_t tpc = std::max<uint32_t>(1, hc_.cache.texels_per_cycle);
    const auto bpc = static_cast<uint32_t>(std::max(1, hc_.blend.taps_per_cycle));
    ItemCost cost[4];
    cost[1].extra_ii = filter_cycles - 1;
    cost[2].extra_ii = n > 0 ? (n + tpc - 1) / tpc - 1 : 0;
    cost[3].extra_ii = n > 0 ? (n + bpc - 1) / bpc - 1 : 0;
    pipe_->issue_with(0, [&](int s, uint64_t start) {
      if (s == 2) {
        uint64_t ready = start + hc_.cache.hit_latency;
        for (uint64_t line : lines_) {
          if (!cache_.access(line * hc_.cache.line_bytes)) {
            ++misses_;
            ready = std::max(ready, dram_.read(start, hc_.cache.line_bytes));
          }
        }
        cost[2].extra_latency = static_cast<uint32_t>(ready - (start + hc_.cache.hit_latency));
      }
      return cost[s];
    });
  }
  uint64_t cycles() const { return pipe_->cycles(); }
  uint64_t misses() const { return misses_; }
  uint64_t line_lookups() const { return cache_.stats().accesses; }

 private:
  HarnessConfig hc_;
  TextureCache cache_;
  DramModel dram_;
  TexelBlend blend_;
  std::unique_ptr<ClockedPipeline> pipe_;
  std::vector<uint64_t> lines_;
  uint64_t misses_ = 0;
};

// Shader-like issue model (the seed's measurements were GPU shader timings): the arithmetic
// runs on ALUs issuing kAluOps per cycle; each texel read (and each filtered weight-map read)
// is one texture instruction, kTexOps per cycle; the slower of the two bounds the fragment.
constexpr double kAluOpsPerCycle = 16.0;
constexpr double kTexFetchesPerCycle = 4.0;

// ---- Results ------------------------------------------------------------------------------

struct Row {
  std::string texture;
  double nominal = 0;
  double aniso_p50 = 0, aniso_p90 = 0;
  std::string method, family, arithmetic;
  AccuracyMetrics acc;
  double se = 0, sref = 0;  // Σ err², Σ ref² (for pooling)
  uint64_t fragments = 0;
  OpCounts ops;  // totals
  uint64_t texels = 0, visited = 0, map_reads = 0, fallbacks = 0;
  uint64_t misses = 0, line_lookups = 0, cycles = 0;
  double shader_cycles = 0;
  double area = 0;
  uint32_t latency = 0;
  double seconds = 0;  // functional run time of the method on this view
  bool hardware = true;
  std::string compare_to;
  double se_pair = 0, sref_pair = 0;  // against compare_to's image
};

double per(uint64_t v, uint64_t n) {
  return n ? static_cast<double>(v) / static_cast<double>(n) : 0.0;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t i =
      std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5));
  return v[i];
}

void sums_vs(const ImageRgb& img, const ImageRgb& ref, double& se, double& sref) {
  se = sref = 0;
  for (size_t i = 0; i < img.covered.size(); ++i) {
    if (!img.covered[i]) continue;
    for (int c = 0; c < 3; ++c) {
      const double e = static_cast<double>(img.rgb[i * 3 + c]) - ref.rgb[i * 3 + c];
      se += e * e;
      sref += static_cast<double>(ref.rgb[i * 3 + c]) * ref.rgb[i * 3 + c];
    }
  }
}

// Pooled figures of one method over a set of rows.
struct Pooled {
  std::string method, family, arithmetic;
  uint64_t pixels = 0, fragments = 0;
  double se = 0, sref = 0, max_abs = 0;
  OpCounts ops;
  uint64_t texels = 0, visited = 0, misses = 0, cycles = 0, map_reads = 0, fallbacks = 0;
  double shader = 0, area = 0, seconds = 0, se_pair = 0, sref_pair = 0;
  uint32_t latency = 0;
  bool hardware = true;
  std::string compare_to;
  double mse() const { return pixels ? se / (3.0 * static_cast<double>(pixels)) : 0; }
  double psnr() const { return mse() > 0 ? 10.0 * std::log10(1.0 / mse()) : 999.0; }
  double nmse() const { return sref > 0 ? se / sref : 0; }
  void add(const Row& r) {
    method = r.method;
    family = r.family;
    arithmetic = r.arithmetic;
    hardware = r.hardware;
    compare_to = r.compare_to;
    area = r.area;
    latency = r.latency;
    pixels += r.acc.pixels;
    fragments += r.fragments;
    se += r.se;
    sref += r.sref;
    max_abs = std::max(max_abs, r.acc.max_abs);
    ops += r.ops;
    texels += r.texels;
    visited += r.visited;
    misses += r.misses;
    cycles += r.cycles;
    map_reads += r.map_reads;
    fallbacks += r.fallbacks;
    shader += r.shader_cycles;
    seconds += r.seconds;
    se_pair += r.se_pair;
    sref_pair += r.sref_pair;
  }
};

std::vector<Pooled> pool(const std::vector<Row>& rows, const std::vector<Method>& methods,
                         const std::function<bool(const Row&)>& keep) {
  std::vector<Pooled> out(methods.size());
  for (const Row& r : rows) {
    if (!keep(r)) continue;
    for (size_t k = 0; k < methods.size(); ++k) {
      if (methods[k].name == r.method) out[k].add(r);
    }
  }
  return out;
}

std::string ops_cells(const OpCounts& o, uint64_t n, const char* sep) {
  std::string s;
  for (int k = 0; k < kOpKinds; ++k) {
    if (k) s += sep;
    s += fmt_g(per(o.get(static_cast<OpKind>(k)), n), 4);
  }
  return s;
}

std::string csv_quote(const std::string& s) { return "\"" + s + "\""; }

void write_outputs(const std::string& out_dir, const std::vector<Row>& rows,
                   const std::vector<Method>& methods, const StudyFiltersOptions& opt,
                   std::ostream& log) {
  // filters.csv: one row per texture × view × method.
  {
    AtomicTextFile csv(out_dir + "/filters.csv");
    auto& o = csv.out();
    o << "texture,aniso_nominal,aniso_p50,aniso_p90,method,family,pixels,psnr_db,nmse,max_abs,mean_"
         "abs";
    for (int k = 0; k < kOpKinds; ++k)
      o << "," << kOpKindNames[static_cast<size_t>(k)] << "_per_frag";
    o << ",texels_per_frag,visited_per_frag,map_reads_per_frag,cache_misses_per_frag,cycles_per_"
         "frag,"
         "shader_cycles_per_frag,fallback_frac,latency_cycles,area,functional_ns_per_lookup,"
         "nmse_vs,nmse_vs_method,arithmetic\n";
    for (const Row& r : rows) {
      o << r.texture << "," << r.nominal << "," << fmt_g(r.aniso_p50, 5) << ","
        << fmt_g(r.aniso_p90, 5) << "," << csv_quote(r.method) << "," << r.family << ","
        << r.acc.pixels << "," << fmt_g(r.acc.psnr_db, 5) << "," << fmt_g(r.acc.nmse, 5) << ","
        << fmt_g(r.acc.max_abs, 5) << "," << fmt_g(r.acc.mean_abs, 5) << ","
        << ops_cells(r.ops, r.fragments, ",") << "," << fmt_g(per(r.texels, r.fragments), 5) << ","
        << fmt_g(per(r.visited, r.fragments), 5) << "," << fmt_g(per(r.map_reads, r.fragments), 5)
        << ",";
      if (r.hardware) {
        o << fmt_g(per(r.misses, r.fragments), 5) << "," << fmt_g(per(r.cycles, r.fragments), 5)
          << "," << fmt_g(r.fragments ? r.shader_cycles / static_cast<double>(r.fragments) : 0, 5)
          << ",";
      } else {
        o << ",,,";
      }
      o << fmt_g(per(r.fallbacks, r.fragments), 4) << ",";
      if (r.hardware)
        o << r.latency << "," << fmt_g(r.area, 5) << ",";
      else
        o << ",,";
      o << fmt_g(r.fragments ? 1e9 * r.seconds / static_cast<double>(r.fragments) : 0, 4) << ",";
      if (!r.compare_to.empty() && r.sref_pair > 0) o << fmt_g(r.se_pair / r.sref_pair, 5);
      o << "," << csv_quote(r.compare_to) << "," << csv_quote(r.arithmetic) << "\n";
    }
    csv.commit();
  }

  const std::vector<Pooled> all = pool(rows, methods, [](const Row&) { return true; });

  // filters.md
  {
    AtomicTextFile md(out_dir + "/filters.md");
    auto& o = md.out();
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
         "with "
         "≥ 32×32 screen-space supersamples (4 per texel of footprint extent) through the exact "
         "projective map, Gaussian pixel model σ = 0.5 px truncated at 1 px (EWA's α = 2 at R = 1 "
         "px).\n\n"
      << "Cycles: each method as the filter stage of the texture unit's pipeline (front → filter → "
         "cache "
      << 16
      << " KiB 4-way, 64 B lines, 4 texels/cycle → DRAM 100 cycles → blend 8 "
         "texels/cycle), default technology table; cycles per fragment = last fragment's leave "
         "time / "
         "fragments. Shader cycles: an issue-bound model of a shader implementation ("
      << kAluOpsPerCycle << " ALU ops/cycle, " << kTexFetchesPerCycle
      << " texture fetches/cycle; one fetch per texel or per filtered weight-map read).\n\n";
    o << "## All views pooled (Σ err² / Σ ref² over every compared pixel)\n\n"
      << "| method | family | PSNR dB | NMSE | max err | texels/frag | misses/frag | cycles/frag | "
         "shader "
         "cycles/frag | add | mul | div | rcp | sqrt | lut | cmp | mem | fallback % | latency | "
         "area |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Pooled& p : all) {
      o << "| " << p.method << " | " << p.family << " | " << fmt_g(p.psnr(), 4) << " | "
        << fmt_g(p.nmse(), 3) << " | " << fmt_g(p.max_abs, 3) << " | "
        << fmt_g(per(p.texels, p.fragments), 4) << " | ";
      if (p.hardware) {
        o << fmt_g(per(p.misses, p.fragments), 3) << " | " << fmt_g(per(p.cycles, p.fragments), 4)
          << " | " << fmt_g(p.fragments ? p.shader / static_cast<double>(p.fragments) : 0, 4)
          << " | ";
      } else {
        o << "— | — | — | ";
      }
      o << ops_cells(p.ops, p.fragments, " | ") << " | "
        << fmt_g(100.0 * per(p.fallbacks, p.fragments), 3) << " | ";
      if (p.hardware)
        o << p.latency << " | " << fmt_g(p.area, 4) << " |\n";
      else
        o << "— | — |\n";
    }
    // PSNR by anisotropy, per texture.
    for (const char* tname : {"checker", "photo", "noise"}) {
      o << "\n## PSNR (dB) by nominal anisotropy: " << tname << "\n\n| method |";
      for (double a : opt.anisotropies) o << " " << a << ":1 |";
      o << "\n|---|";
      for (size_t i = 0; i < opt.anisotropies.size(); ++i) o << "---|";
      o << "\n";
      for (const Method& m : methods) {
        o << "| " << m.name << " |";
        for (double a : opt.anisotropies) {
          for (const Row& r : rows) {
            if (r.texture == tname && r.nominal == a && r.method == m.name)
              o << " " << fmt_g(r.acc.psnr_db, 4) << " |";
          }
        }
        o << "\n";
      }
    }
    o << "\n## Cycles per fragment by nominal anisotropy (all textures)\n\n| method |";
    for (double a : opt.anisotropies) o << " " << a << ":1 |";
    o << "\n|---|";
    for (size_t i = 0; i < opt.anisotropies.size(); ++i) o << "---|";
    o << "\n";
    for (const Method& m : methods) {
      if (!m.hardware) continue;
      o << "| " << m.name << " |";
      for (double a : opt.anisotropies) {
        uint64_t cyc = 0, n = 0;
        for (const Row& r : rows) {
          if (r.nominal == a && r.method == m.name) {
            cyc += r.cycles;
            n += r.fragments;
          }
        }
        o << " " << fmt_g(per(cyc, n), 4) << " |";
      }
      o << "\n";
    }

    // The seed's claims, re-measured.
    auto find = [&](const std::string& name) -> const Pooled* {
      for (const Pooled& p : all) {
        if (p.method == name) return &p;
      }
      return nullptr;
    };
    o << "\n## The seed's claims, re-measured\n\n";
    const Pooled* pc = find("ewa pow8 computed");
    const Pooled* pu = find("ewa uniform weights");
    o << "**Weight maps vs computed weights** (thesis ch. 3/5: NMSE 0.000708, +25% speed). Each "
         "map "
         "holds the power-8 function the computed row evaluates; NMSE is the map image against the "
         "computed-weight image over all views; speed = cycles(computed) / cycles(map) − 1.\n\n"
      << "| map | against | memory (bytes) | NMSE vs computed | seed NMSE | NMSE vs truth | "
         "speed-up, pipelined | "
         "speed-up, shader model | seed speed-up |\n|---|---|---|---|---|---|---|---|---|\n";
    for (const Pooled& p : all) {
      if (p.family != "weight map") continue;
      const Pooled* pc_own = find(p.compare_to);
      if (!pc_own) continue;
      const double nm = p.sref_pair > 0 ? p.se_pair / p.sref_pair : 0;
      const double sp =
          p.cycles ? static_cast<double>(pc_own->cycles) / static_cast<double>(p.cycles) - 1 : 0;
      const double ss = p.shader > 0 ? pc_own->shader / p.shader - 1 : 0;
      uint64_t bytes = 0;
      for (const Method& m : methods) {
        if (m.name == p.method) bytes = m.map_bytes;
      }
      o << "| " << p.method << " | " << p.compare_to << " | " << bytes << " | " << fmt_g(nm, 3)
        << " | 0.000708 | " << fmt_g(p.nmse(), 3) << " | " << fmt_g(100 * sp, 3) << "% | "
        << fmt_g(100 * ss, 3) << "% | +25% |\n";
    }
    if (pc && pu) {
      const double sp = static_cast<double>(pc->cycles) / static_cast<double>(pu->cycles) - 1;
      const double ss = pc->shader / pu->shader - 1;
      o << "\n**Computing Gaussian weights in real time costs ≤ 5%** (thesis ch. 5): computed "
           "power-8 "
           "weights against uniform weights over the same ellipse: pipelined "
        << fmt_g(100 * sp, 3) << "% more cycles, shader model " << fmt_g(100 * ss, 3)
        << "% more cycles; PSNR " << fmt_g(pu->psnr(), 4) << " dB (uniform) → "
        << fmt_g(pc->psnr(), 4) << " dB (Gaussian).\n";
    }
    md.commit();
  }

  // Pareto plots.
  auto plot = [&](const std::string& path, bool by_cycles) {
    PlotSpec p;
    p.title = by_cycles
                  ? "Anisotropic filters: NMSE vs cycles per fragment (all views pooled)"
                  : "Anisotropic filters: NMSE vs texels fetched per fragment (all views pooled)";
    p.xlabel = by_cycles ? "cycles per fragment" : "texels fetched per fragment";
    p.ylabel = "NMSE vs ground truth";
    p.logx = true;
    p.logy = true;
    std::map<std::string, PlotSeries> fam;
    struct Pt {
      double x, y;
    };
    std::vector<Pt> pts;
    for (const Pooled& q : all) {
      if (!q.hardware || q.fragments == 0) continue;
      const double x = by_cycles ? per(q.cycles, q.fragments) : per(q.texels, q.fragments);
      PlotSeries& s = fam[q.family];
      s.label = q.family;
      s.x.push_back(x);
      s.y.push_back(q.nmse());
      pts.push_back({x, q.nmse()});
    }
    for (auto& [k, s] : fam) p.series.push_back(s);
    std::sort(pts.begin(), pts.end(),
              [](const Pt& a, const Pt& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    PlotSeries front;
    front.label = "Pareto front";
    front.lines = true;
    double best = 1e300;
    for (const Pt& q : pts) {
      if (q.y < best) {
        best = q.y;
        front.x.push_back(q.x);
        front.y.push_back(q.y);
      }
    }
    p.series.push_back(front);
    write_plot_png(path, p);
  };
  plot(out_dir + "/filters.png", true);
  plot(out_dir + "/filters_texels.png", false);
  for (const Pooled& p : all) {
    log << "  " << p.method << ": PSNR " << fmt_g(p.psnr(), 4) << " dB, NMSE "
        << fmt_g(p.nmse(), 3);
    if (p.hardware) {
      log << ", texels/frag " << fmt_g(per(p.texels, p.fragments), 4) << ", cycles/frag "
          << fmt_g(per(p.cycles, p.fragments), 4);
    }
    log << ", " << fmt_g(p.fragments ? 1e9 * p.seconds / static_cast<double>(p.fragments) : 0, 4)
        << " ns/lookup\n";
  }
}

}  // namespace

int run_study_filters(const std::string& out_dir, std::ostream& log) {
  return run_study_filters(out_dir, log, StudyFiltersOptions{});
}

int run_study_filters(const std::string& out_dir, std::ostream& log,
                      const StudyFiltersOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  ensure_dir(out_dir);
  const TechTable tech = TechTable::defaults();
  const HarnessConfig hc;

  // Textures: a checkerboard (sharp edges), a photo, high-frequency noise.
  std::vector<StudyTexture> textures;
  textures.push_back({"checker", "procedural:checker?size=256&cells=16", {}});
  textures.push_back({"photo", "/usr/share/glmark2/textures/crate-base.png", {}});
  textures.push_back({"noise", "procedural:noise?size=256&cells=32", {}});
  for (StudyTexture& t : textures) {
    t.tex = is_procedural_source(t.source) ? make_procedural_texture(t.source, "study filters")
                                           : load_texture(t.source, "");
    t.tex.place(0, TexelLayout::Tiled4x4);
  }

  // Methods.
  std::vector<Method> methods;
  methods.push_back(baseline("trilinear (isotropic)", AnisoMode::Isotropic, tech));
  methods.push_back(baseline("trilinear aniso 16 (Vulkan probes)", AnisoMode::Vulkan, tech));
  {
    EwaFilter::Config c;  // defaults: LUT 256 u0.16, α = 2, max aniso 16, budget 1024, float
    methods.push_back(ewa_method("ewa lut256", "ewa", c, tech));
    EwaFilter::Config d = c;
    d.scan = EwaFilter::Scan::RowSpan;
    methods.push_back(ewa_method("ewa lut256 row-span", "ewa", d, tech));
    d = c;
    d.lut_size = 32;
    d.lut_bits = 8;
    methods.push_back(ewa_method("ewa lut32 u0.8", "ewa", d, tech));
    d = c;
    d.arith = NumberFormat::S18_30;
    methods.push_back(ewa_method("ewa lut256 fixed Q", "ewa", d, tech));
    d = c;
    d.arith = NumberFormat::Double;
    d.weight = EwaFilter::Weight::Exp;
    methods.push_back(ewa_method("ewa exp double", "ewa", d, tech));
    d = c;
    d.mip = EwaFilter::Mip::Linear;
    methods.push_back(ewa_method("ewa lut256 linear-mip", "ewa", d, tech));
    d = c;
    d.reconstruction = 0;
    methods.push_back(ewa_method("ewa lut256 no reconstruction", "ewa", d, tech));
    d = c;
    d.max_aniso = 64;
    d.texel_budget = 4096;
    methods.push_back(ewa_method("ewa lut256 aniso 64", "ewa", d, tech));
    d = c;
    d.minor_texels = 2;
    methods.push_back(ewa_method("ewa lut256 minor 2 texels", "ewa", d, tech));
    // V(d) sub-texel cut-off of the texels within half a texel of the ellipse boundary.
    for (const auto& [k, fk, label] :
         {std::tuple{VdEvaluatorKind::Exact, NumberFormat::Double, "exact double"},
          std::tuple{VdEvaluatorKind::P2, NumberFormat::Fx16, "P2 fx16"}}) {
      d = c;
      d.edge = EwaFilter::Edge::Vd;
      d.vd.evaluator = k;
      d.vd.format = fk;
      methods.push_back(ewa_method(std::string("ewa lut256 edge V(d) ") + label, "ewa", d, tech));
    }
    // Control for the cut-off: a smaller reconstruction term also narrows the edge weights.
    d = c;
    d.reconstruction = 0.5;
    methods.push_back(ewa_method("ewa lut256 reconstruction 0.5", "ewa", d, tech));
    d = c;
    d.weight = EwaFilter::Weight::Uniform;
    methods.push_back(ewa_method("ewa uniform weights", "weights", d, tech));
    d = c;
    d.weight = EwaFilter::Weight::Exp;
    methods.push_back(ewa_method("ewa exp computed", "weights", d, tech));
    d = c;
    d.weight = EwaFilter::Weight::Pow8;
    methods.push_back(ewa_method("ewa pow8 computed", "weights", d, tech));
    // Weight maps holding the same power-8 function the computed row evaluates.
    struct MapVariant {
      WeightMap::Kind kind;
      WeightMap::Element el;
      int size;
      WeightMap::Transform tr;
    };
    const std::vector<MapVariant> maps = {
        {WeightMap::Kind::Full2D, WeightMap::Element::U16, 64, WeightMap::Transform::Cholesky},
        {WeightMap::Kind::Quarter, WeightMap::Element::U16, 32, WeightMap::Transform::Cholesky},
        {WeightMap::Kind::Quarter, WeightMap::Element::U8, 32, WeightMap::Transform::Cholesky},
        {WeightMap::Kind::Quarter, WeightMap::Element::Float, 64, WeightMap::Transform::Cholesky},
        {WeightMap::Kind::RadialR, WeightMap::Element::U16, 64, WeightMap::Transform::Cholesky},
        {WeightMap::Kind::RadialR2, WeightMap::Element::U16, 64, WeightMap::Transform::Cholesky},
        {WeightMap::Kind::RadialR2, WeightMap::Element::U8, 16, WeightMap::Transform::Cholesky},
    };
    for (const MapVariant& mv : maps) {
      WeightMap::Config mc;
      mc.kind = mv.kind;
      mc.element = mv.el;
      mc.size = mv.size;
      mc.function = WeightMap::Function::Pow8;
      mc.alpha = c.alpha;
      mc.transform = mv.tr;
      auto wm = std::make_shared<const WeightMap>(mc);
      d = c;
      d.weight = EwaFilter::Weight::Map;
      std::string nm = "ewa map " + wm->name();
      if (mv.tr == WeightMap::Transform::Jacobian) nm += " jacobian";
      methods.push_back(ewa_method(nm, "weight map", d, tech, wm));
      methods.back().compare_to = "ewa pow8 computed";
    }
    // The thesis's own set-up: no reconstruction term, (x, y) = J⁻¹(U, V) from the derivatives.
    d = c;
    d.weight = EwaFilter::Weight::Pow8;
    d.reconstruction = 0;
    methods.push_back(ewa_method("ewa pow8 computed, no reconstruction", "weights", d, tech));
    for (const MapVariant& mv : {MapVariant{WeightMap::Kind::Quarter, WeightMap::Element::U16, 32,
                                            WeightMap::Transform::Jacobian},
                                 MapVariant{WeightMap::Kind::Quarter, WeightMap::Element::U8, 16,
                                            WeightMap::Transform::Jacobian},
                                 MapVariant{WeightMap::Kind::RadialR, WeightMap::Element::U8, 16,
                                            WeightMap::Transform::Jacobian}}) {
      WeightMap::Config mc;
      mc.kind = mv.kind;
      mc.element = mv.el;
      mc.size = mv.size;
      mc.function = WeightMap::Function::Pow8;
      mc.alpha = c.alpha;
      mc.transform = mv.tr;
      auto wm = std::make_shared<const WeightMap>(mc);
      d = c;
      d.weight = EwaFilter::Weight::Map;
      d.reconstruction = 0;
      methods.push_back(ewa_method("ewa map " + wm->name() + " jacobian, no reconstruction",
                                   "weight map", d, tech, wm));
      methods.back().compare_to = "ewa pow8 computed, no reconstruction";
    }
  }

  {
    const std::string probe_arith =
        "float32 footprint set-up, positions and weights in double, trilinear probes (u0.8 "
        "weights), float32 blend";
    MultiProbeFilter::Config mp;
    methods.push_back(block_method("multi-ellipse probes α=1 max 15", "probes",
                                   std::make_shared<const MultiProbeFilter>(mp), tech,
                                   probe_arith));
    MultiProbeFilter::Config mp2 = mp;
    mp2.alpha = 2;
    methods.push_back(block_method("multi-ellipse probes α=2 max 15", "probes",
                                   std::make_shared<const MultiProbeFilter>(mp2), tech,
                                   probe_arith));
    mp2 = mp;
    mp2.seed_theta = true;
    methods.push_back(block_method("multi-ellipse probes α=1, θ as printed", "probes",
                                   std::make_shared<const MultiProbeFilter>(mp2), tech,
                                   probe_arith));
    mp2 = mp;
    mp2.temporal = true;
    methods.push_back(block_method("multi-ellipse probes α=1, half per frame", "probes",
                                   std::make_shared<const MultiProbeFilter>(mp2), tech,
                                   probe_arith));
    mp2 = mp;
    mp2.arith = NumberFormat::S16_24HalfUp;
    methods.push_back(block_method("multi-ellipse probes α=1 max 15, fixed", "probes",
                                   std::make_shared<const MultiProbeFilter>(mp2), tech,
                                   MultiProbeFilter(mp2).arithmetic()));
    methods.back().compare_to = "multi-ellipse probes α=1 max 15";
    FelineFilter::Config fc;
    methods.push_back(block_method("feline (major axis, Gaussian) max 16", "probes",
                                   std::make_shared<const FelineFilter>(fc), tech, probe_arith));
    FelineFilter::Config fx = fc;
    fx.arith = NumberFormat::S16_24HalfUp;
    methods.push_back(block_method("feline (major axis, Gaussian) max 16, fixed", "probes",
                                   std::make_shared<const FelineFilter>(fx), tech,
                                   FelineFilter(fx).arithmetic()));
    methods.back().compare_to = "feline (major axis, Gaussian) max 16";
    fc.axis = FelineFilter::Axis::Parallelogram;
    fc.weights = FelineFilter::Weights::Equal;
    methods.push_back(block_method("texram (longer side, equal) max 16", "probes",
                                   std::make_shared<const FelineFilter>(fc), tech, probe_arith));
    SpafFilter::Config sc;
    const std::string spaf_arith =
        "float32 edge functions and Q, 4x4 sub-texel masks, float32 blend";
    methods.push_back(block_method("spaf 4x4 mask, budget 64", "spaf",
                                   std::make_shared<const SpafFilter>(sc), tech, spaf_arith));
    sc.texel_budget = 256;
    methods.push_back(block_method("spaf 4x4 mask, budget 256", "spaf",
                                   std::make_shared<const SpafFilter>(sc), tech, spaf_arith));
    sc.half_px = 0.5;
    sc.gaussian = false;
    methods.push_back(block_method("spaf area only (pixel square), budget 256", "spaf",
                                   std::make_shared<const SpafFilter>(sc), tech, spaf_arith));
    // V(d) coverage instead of sub-texel masks (vd.lanes cut-off units per lane), and the
    // edge-function/Q datapath in double and fixed point.
    auto spaf_row = [&](const std::string& name, const SpafFilter::Config& cfg) {
      auto b = std::make_shared<const SpafFilter>(cfg);
      methods.push_back(block_method(name, "spaf", b, tech, b->arithmetic()));
    };
    struct VdRow {
      VdEvaluatorKind k;
      NumberFormat f;
      uint32_t units;
      int budget;
      const char* label;
    };
    for (const VdRow& vr :
         {VdRow{VdEvaluatorKind::Exact, NumberFormat::Double, 1, 64, "exact double"},
          VdRow{VdEvaluatorKind::Exact, NumberFormat::Fx16, 1, 64, "exact fx16"},
          VdRow{VdEvaluatorKind::P3, NumberFormat::Fx16, 1, 64, "P3 fx16"},
          VdRow{VdEvaluatorKind::P2, NumberFormat::Float, 1, 64, "P2 float"},
          VdRow{VdEvaluatorKind::P2, NumberFormat::Fx16, 1, 64, "P2 fx16"},
          VdRow{VdEvaluatorKind::P2, NumberFormat::Fx16, 4, 64, "P2 fx16 x4 units"},
          VdRow{VdEvaluatorKind::P1, NumberFormat::Fx16, 1, 64, "P1 fx16"},
          VdRow{VdEvaluatorKind::P1, NumberFormat::Fx8, 1, 64, "P1 fx8"},
          VdRow{VdEvaluatorKind::Exact, NumberFormat::Double, 1, 256, "exact double"},
          VdRow{VdEvaluatorKind::P2, NumberFormat::Fx16, 1, 256, "P2 fx16"}}) {
      SpafFilter::Config vc;
      vc.texel_budget = vr.budget;
      vc.coverage = SpafFilter::Coverage::Vd;
      vc.vd.evaluator = vr.k;
      vc.vd.format = vr.f;
      vc.vd.lanes = vr.units;
      spaf_row(std::string("spaf V(d) ") + vr.label + ", budget " + std::to_string(vr.budget), vc);
    }
    for (int budget : {64, 256}) {
      SpafFilter::Config fc2;
      fc2.texel_budget = budget;
      fc2.arith = NumberFormat::S20_28HalfUp;
      spaf_row("spaf 4x4 mask, budget " + std::to_string(budget) + ", fixed " + SpafFixed::name(),
               fc2);
    }
    SpafFilter::Config dc;
    dc.arith = NumberFormat::Double;
    spaf_row("spaf 4x4 mask, budget 64, double", dc);
  }
  if (opt.oiio) {
    // OpenImageIO's TextureSystem on the same queries: one .tx per texture, made on first use.
    auto peers = std::make_shared<std::map<const Texture*, std::unique_ptr<OiioPeer>>>();
    Method m;
    m.name = "OpenImageIO TextureSystem aniso 16";
    m.family = "oiio";
    m.arithmetic = "OpenImageIO (float, MipModeAniso, bilinear, box-filtered MIP chain)";
    m.hardware = false;
    const std::string dir = out_dir;
    m.run = [peers, dir](const Texture& tex, const Fragment& f, std::vector<TexelRef>&, OpCounts&) {
      auto& p = (*peers)[&tex];
      if (!p) {
        OiioPeer::Config pc;
        pc.max_aniso = 16;
        p = std::make_unique<OiioPeer>(tex, pc);
      }
      FilterOutput o;
      o.colour = p->lookup(f);
      return o;
    };
    m.issue = [](const FilterStats&) { return 1u; };
    methods.push_back(m);
  }

  std::vector<Row> rows;
  FootprintReferenceConfig rc;
  rc.address_u = rc.address_v = AddressMode::Wrap;
  std::vector<TexelRef> fetched;
  fetched.reserve(8192);
  for (StudyTexture& st : textures) {
    for (double nominal : opt.anisotropies) {
      const auto tv = std::chrono::steady_clock::now();
      const std::string text =
          view_scene_text(nominal, opt.size, opt.texels_per_pixel, st.tex.width(0));
      const Scene scene = parse_scene(text, "study filters view", "");
      const PlaneProjection proj(scene, scene.planes[0]);
      // Fragments and the ground truth.
      std::vector<Fragment> frags;
      std::vector<double> anisos;
      ImageRgb ref(opt.size, opt.size, scene.background);
      for (int y = 0; y < opt.size; ++y) {
        for (int x = 0; x < opt.size; ++x) {
          const UvSample s = proj.at(x + 0.5, y + 0.5);
          if (!s.inside) continue;
          Fragment f;
          f.x = static_cast<uint32_t>(x);
          f.y = static_cast<uint32_t>(y);
          f.u = s.u;
          f.v = s.v;
          f.dudx = s.dudx;
          f.dvdx = s.dvdx;
          f.dudy = s.dudy;
          f.dvdy = s.dvdy;
          frags.push_back(f);
          OpCounts scratch;
          anisos.push_back(
              footprint_setup<double>(f, st.tex.width(0), st.tex.height(0), 1.0, 1e12, scratch)
                  .aniso);
          const ReferenceSample r = footprint_reference(st.tex, proj, x, y, rc);
          ref.set(x, y, glm::vec4(r.colour));
        }
      }
      const double p50 = percentile(anisos, 0.5), p90 = percentile(anisos, 0.9);
      const double t_ref =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - tv).count();
      log << "  " << st.name << " aniso " << nominal << ": " << frags.size()
          << " fragments, aniso p50 " << fmt_g(p50, 3) << " p90 " << fmt_g(p90, 3) << ", reference "
          << fmt_g(t_ref, 3) << " s\n";
      std::vector<ImageRgb> images;
      images.reserve(methods.size());
      for (const Method& m : methods) {
        Row r;
        r.texture = st.name;
        r.nominal = nominal;
        r.aniso_p50 = p50;
        r.aniso_p90 = p90;
        r.method = m.name;
        r.family = m.family;
        r.arithmetic = m.arithmetic;
        r.hardware = m.hardware;
        r.area = m.area;
        r.latency = m.front.latency + m.filter.latency;
        ImageRgb img(opt.size, opt.size, scene.background);
        std::unique_ptr<Harness> h;
        if (m.hardware) h = std::make_unique<Harness>(m, hc, tech);
        const auto tm = std::chrono::steady_clock::now();
        double shader = 0;
        for (const Fragment& f : frags) {
          fetched.clear();
          OpCounts ops;
          const FilterOutput o = m.run(st.tex, f, fetched, ops);
          img.set(static_cast<int>(f.x), static_cast<int>(f.y), o.colour);
          r.ops += ops;
          r.texels += o.stats.texels;
          r.visited += o.stats.visited;
          r.map_reads += o.stats.map_reads;
          r.fallbacks += o.stats.fallback ? 1 : 0;
          if (h) {
            h->issue(st.tex, fetched, m.issue(o.stats));
            const uint32_t map_reads =
                m.entries_per_map_read ? o.stats.map_reads / m.entries_per_map_read : 0;
            double alu = static_cast<double>(ops.arithmetic()) - m.tmu_ops_per_map_read * map_reads;
            double tex_ops = static_cast<double>(o.stats.texels + map_reads);
            if (m.family == "baseline") {  // the texture unit filters: one fetch per bilinear probe
              alu = 0;
              tex_ops = static_cast<double>(o.stats.texels) / 4.0;
            }
            shader += std::max(alu / kAluOpsPerCycle, tex_ops / kTexFetchesPerCycle);
          }
        }
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - tm).count();
        r.fragments = frags.size();
        r.acc = compare_images(img, ref);
        sums_vs(img, ref, r.se, r.sref);
        if (h) {
          r.cycles = h->cycles();
          r.misses = h->misses();
          r.line_lookups = h->line_lookups();
          r.shader_cycles = shader;
        }
        r.compare_to = m.compare_to;
        if (!m.compare_to.empty()) {
          for (size_t k = 0; k < images.size(); ++k) {
            if (methods[k].name == m.compare_to) sums_vs(img, images[k], r.se_pair, r.sref_pair);
          }
        }
        rows.push_back(r);
        images.push_back(img);
        if (opt.write_images) {
          write_image(out_dir + "/" + st.name + "_a" + fmt_g(nominal, 3) + "_" +
                          std::to_string(&m - methods.data()) + ".png",
                      img);
        }
      }
      if (opt.write_images)
        write_image(out_dir + "/" + st.name + "_a" + fmt_g(nominal, 3) + "_ref.png", ref);
    }
  }
  write_outputs(out_dir, rows, methods, opt, log);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study filters: wrote " << out_dir << "/filters.csv, filters.md, filters.png in "
      << fmt_g(secs, 3) << " s\n";
  return 0;
}

}  // namespace texsim
