#include "pipeline/studies/study_filter_methods.h"

#include <algorithm>
#include <map>
#include <tuple>
#include <utility>

#include "blocks/base/input_error.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/feline_filter.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "blocks/texture/footprint/weight_map.h"
#include "pipeline/reference/mesa_peer.h"
#include "pipeline/reference/oiio_peer.h"

namespace texsim {

void TalliedFootprint::count(const OpCounts& ops, const FilterStats& s) const {
  tally_.ops += ops;
  tally_.texels += s.texels;
  tally_.visited += s.visited;
  tally_.map_reads += s.map_reads;
  tally_.fallbacks += s.fallback ? 1 : 0;
  const uint32_t map_reads = entries_per_map_read_ ? s.map_reads / entries_per_map_read_ : 0;
  const double alu = static_cast<double>(ops.arithmetic()) - tmu_ops_per_map_read_ * map_reads;
  const double tex = static_cast<double>(s.texels + map_reads);
  tally_.shader_cycles += std::max(alu / issue_.alu_per_cycle, tex / issue_.tex_per_cycle);
}

namespace {

template <class Block>
class TalliedFootprintOf final : public TalliedFootprint {
 public:
  TalliedFootprintOf(Block block, std::string name)
      : block_(std::move(block)), name_(std::move(name)) {}
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const override {
    OpCounts own;
    const FilterOutput out = block_.filter(tex, f, fetched, own);
    count(own, out.stats);
    ops += own;
    return out;
  }
  uint32_t issue_cycles(const FilterStats& s) const override { return block_.issue_cycles(s); }
  TimingSpec timing(const TechTable& tech) const override { return block_.timing(tech); }
  std::string name() const override { return name_; }
  std::string arithmetic() const override { return block_.arithmetic(); }
  AddressMode address_u() const override { return block_.config().address_u; }
  AddressMode address_v() const override { return block_.config().address_v; }

 private:
  Block block_;
  std::string name_;
};

const char* const kProbeArith =
    "float32 footprint set-up, positions and weights in double, trilinear probes (u0.8 "
    "weights), float32 blend";
const char* const kSpafArith = "float32 edge functions and Q, 4x4 sub-texel masks, float32 blend";

StudyFilterMethod baseline(const std::string& name, AnisoMode aniso) {
  StudyFilterMethod m;
  m.name = name;
  m.family = "baseline";
  m.arithmetic = "float32 LOD and coordinates, u0.8 weights, float32 blend";
  m.material.name = name;
  m.material.lod.aniso = aniso;
  m.material.lod.max_aniso = 16;
  m.material.filter.filter = FilterMode::Trilinear;
  return m;
}

// A footprint block as a method: the material's footprint filter, tallied.
// `map_read` (entries, arithmetic per read) for a weight-map filter's shader model.
template <class Block>
StudyFilterMethod footprint_method(const std::string& name, const std::string& family, Block b,
                                   const std::string& block_name, const std::string& arithmetic,
                                   std::pair<uint32_t, double> map_read = {0, 0}) {
  auto f = std::make_shared<TalliedFootprintOf<Block>>(std::move(b), block_name);
  f->set_map_read(map_read.first, map_read.second);
  StudyFilterMethod m;
  m.name = name;
  m.family = family;
  m.arithmetic = arithmetic.empty() ? f->arithmetic() : arithmetic;
  m.material.name = name;
  m.material.footprint = f;
  m.tallied = f;
  return m;
}

StudyFilterMethod ewa_method(const std::string& name, const std::string& family,
                             const EwaFilter::Config& c,
                             const std::shared_ptr<const WeightMap>& map = nullptr) {
  const bool mapped = c.weight == EwaFilter::Weight::Map && map;
  std::pair<uint32_t, double> map_read{0, 0};
  if (mapped) {
    const OpCounts r = map->ops_per_item();
    map_read = {static_cast<uint32_t>(r.mem), static_cast<double>(r.arithmetic())};
  }
  StudyFilterMethod m =
      footprint_method(name, family, EwaFilter(c, map), "filter.ewa", "", map_read);
  if (mapped) m.map_bytes = map->bytes();
  return m;
}

void add_ewa_variants(std::vector<StudyFilterMethod>& out, const EwaFilter::Config& c) {
  out.push_back(ewa_method("ewa lut256", "ewa", c));
  EwaFilter::Config d = c;
  d.scan = EwaFilter::Scan::RowSpan;
  out.push_back(ewa_method("ewa lut256 row-span", "ewa", d));
  d = c;
  d.lut_size = 32;
  d.lut_bits = 8;
  out.push_back(ewa_method("ewa lut32 u0.8", "ewa", d));
  d = c;
  d.arith = NumberFormat::S18_30;
  out.push_back(ewa_method("ewa lut256 fixed Q", "ewa", d));
  d = c;
  d.arith = NumberFormat::Double;
  d.weight = EwaFilter::Weight::Exp;
  out.push_back(ewa_method("ewa exp double", "ewa", d));
  d = c;
  d.mip = EwaFilter::Mip::Linear;
  out.push_back(ewa_method("ewa lut256 linear-mip", "ewa", d));
  d = c;
  d.reconstruction = 0;
  out.push_back(ewa_method("ewa lut256 no reconstruction", "ewa", d));
  d = c;
  d.max_aniso = 64;
  d.texel_budget = 4096;
  out.push_back(ewa_method("ewa lut256 aniso 64", "ewa", d));
  d = c;
  d.minor_texels = 2;
  out.push_back(ewa_method("ewa lut256 minor 2 texels", "ewa", d));
  // V(d) sub-texel cut-off of the texels within half a texel of the ellipse boundary.
  for (const auto& [k, fk, label] :
       {std::tuple{VdEvaluatorKind::Exact, NumberFormat::Double, "exact double"},
        std::tuple{VdEvaluatorKind::P2, NumberFormat::Fx16, "P2 fx16"}}) {
    d = c;
    d.edge = EwaFilter::Edge::Vd;
    d.vd.evaluator = k;
    d.vd.format = fk;
    out.push_back(ewa_method(std::string("ewa lut256 edge V(d) ") + label, "ewa", d));
  }
  // Control for the cut-off: a smaller reconstruction term also narrows the edge weights.
  d = c;
  d.reconstruction = 0.5;
  out.push_back(ewa_method("ewa lut256 reconstruction 0.5", "ewa", d));
  d = c;
  d.weight = EwaFilter::Weight::Uniform;
  out.push_back(ewa_method("ewa uniform weights", "weights", d));
  d = c;
  d.weight = EwaFilter::Weight::Exp;
  out.push_back(ewa_method("ewa exp computed", "weights", d));
  d = c;
  d.weight = EwaFilter::Weight::Pow8;
  out.push_back(ewa_method("ewa pow8 computed", "weights", d));
}

struct MapVariant {
  WeightMap::Kind kind;
  WeightMap::Element el;
  int size;
  WeightMap::Transform tr;
};

// An EWA method whose weights come from a map holding the power-8 function (with the filter's
// α), compared with the computed-weight method `against`.
void add_map_method(std::vector<StudyFilterMethod>& out, const EwaFilter::Config& c,
                    const MapVariant& mv, const std::string& suffix, const std::string& against) {
  WeightMap::Config mc;
  mc.kind = mv.kind;
  mc.element = mv.el;
  mc.size = mv.size;
  mc.function = WeightMap::Function::Pow8;
  mc.alpha = c.alpha;
  mc.transform = mv.tr;
  auto wm = std::make_shared<const WeightMap>(mc);
  EwaFilter::Config d = c;
  d.weight = EwaFilter::Weight::Map;
  std::string nm = "ewa map " + wm->name();
  if (mv.tr == WeightMap::Transform::Jacobian) nm += " jacobian";
  out.push_back(ewa_method(nm + suffix, "weight map", d, wm));
  out.back().compare_to = against;
}

void add_weight_maps(std::vector<StudyFilterMethod>& out, const EwaFilter::Config& c) {
  using K = WeightMap::Kind;
  using E = WeightMap::Element;
  const auto ch = WeightMap::Transform::Cholesky;
  const auto jac = WeightMap::Transform::Jacobian;
  for (const MapVariant& mv :
       {MapVariant{K::Full2D, E::U16, 64, ch}, MapVariant{K::Quarter, E::U16, 32, ch},
        MapVariant{K::Quarter, E::U8, 32, ch}, MapVariant{K::Quarter, E::Float, 64, ch},
        MapVariant{K::RadialR, E::U16, 64, ch}, MapVariant{K::RadialR2, E::U16, 64, ch},
        MapVariant{K::RadialR2, E::U8, 16, ch}})
    add_map_method(out, c, mv, "", "ewa pow8 computed");
  // The thesis's own set-up: no reconstruction term, (x, y) = J⁻¹(U, V) from the derivatives.
  EwaFilter::Config d = c;
  d.weight = EwaFilter::Weight::Pow8;
  d.reconstruction = 0;
  out.push_back(ewa_method("ewa pow8 computed, no reconstruction", "weights", d));
  for (const MapVariant& mv :
       {MapVariant{K::Quarter, E::U16, 32, jac}, MapVariant{K::Quarter, E::U8, 16, jac},
        MapVariant{K::RadialR, E::U8, 16, jac}})
    add_map_method(out, d, mv, ", no reconstruction", "ewa pow8 computed, no reconstruction");
}

void add_probe_methods(std::vector<StudyFilterMethod>& out) {
  const MultiProbeFilter::Config mp;
  const auto multi = [&](const std::string& name, const MultiProbeFilter::Config& c,
                         const std::string& arith) {
    out.push_back(
        footprint_method(name, "probes", MultiProbeFilter(c), "filter.multi_probe", arith));
  };
  multi("multi-ellipse probes α=1 max 15", mp, kProbeArith);
  MultiProbeFilter::Config mp2 = mp;
  mp2.alpha = 2;
  multi("multi-ellipse probes α=2 max 15", mp2, kProbeArith);
  mp2 = mp;
  mp2.seed_theta = true;
  multi("multi-ellipse probes α=1, θ as printed", mp2, kProbeArith);
  mp2 = mp;
  mp2.temporal = true;
  multi("multi-ellipse probes α=1, half per frame", mp2, kProbeArith);
  mp2 = mp;
  mp2.arith = NumberFormat::S16_24HalfUp;
  multi("multi-ellipse probes α=1 max 15, fixed", mp2, "");
  out.back().compare_to = "multi-ellipse probes α=1 max 15";
  const auto feline = [&](const std::string& name, const FelineFilter::Config& c,
                          const std::string& arith) {
    out.push_back(footprint_method(name, "probes", FelineFilter(c), "filter.feline", arith));
  };
  FelineFilter::Config fc;
  feline("feline (major axis, Gaussian) max 16", fc, kProbeArith);
  FelineFilter::Config fx = fc;
  fx.arith = NumberFormat::S16_24HalfUp;
  feline("feline (major axis, Gaussian) max 16, fixed", fx, "");
  out.back().compare_to = "feline (major axis, Gaussian) max 16";
  fc.axis = FelineFilter::Axis::Parallelogram;
  fc.weights = FelineFilter::Weights::Equal;
  feline("texram (longer side, equal) max 16", fc, kProbeArith);
}

void add_spaf_methods(std::vector<StudyFilterMethod>& out) {
  const auto spaf = [&](const std::string& name, const SpafFilter::Config& c,
                        const std::string& arith) {
    out.push_back(footprint_method(name, "spaf", SpafFilter(c), "filter.spaf", arith));
  };
  SpafFilter::Config sc;
  spaf("spaf 4x4 mask, budget 64", sc, kSpafArith);
  sc.texel_budget = 256;
  spaf("spaf 4x4 mask, budget 256", sc, kSpafArith);
  sc.half_px = 0.5;
  sc.gaussian = false;
  spaf("spaf area only (pixel square), budget 256", sc, kSpafArith);
  // V(d) coverage instead of sub-texel masks (vd.lanes cut-off units per lane), and the
  // edge-function/Q datapath in double and fixed point.
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
    spaf(std::string("spaf V(d) ") + vr.label + ", budget " + std::to_string(vr.budget), vc, "");
  }
  for (int budget : {64, 256}) {
    SpafFilter::Config fc2;
    fc2.texel_budget = budget;
    fc2.arith = NumberFormat::S20_28HalfUp;
    spaf("spaf 4x4 mask, budget " + std::to_string(budget) + ", fixed " + SpafFixed::name(), fc2,
         "");
  }
  SpafFilter::Config dc;
  dc.arith = NumberFormat::Double;
  spaf("spaf 4x4 mask, budget 64, double", dc, "");
}

// OpenImageIO's TextureSystem on the same queries: one .tx per texture, made on first use.
StudyFilterMethod oiio_method() {
  auto peers = std::make_shared<std::map<const Texture*, std::unique_ptr<OiioPeer>>>();
  StudyFilterMethod m;
  m.name = "OpenImageIO TextureSystem aniso 16";
  m.family = "oiio";
  m.arithmetic = "OpenImageIO (float, MipModeAniso, bilinear, box-filtered MIP chain)";
  m.peer = [peers](const Texture& tex, const Fragment& f) {
    auto& p = (*peers)[&tex];
    if (!p) {
      OiioPeer::Config pc;
      pc.max_aniso = 16;
      p = std::make_unique<OiioPeer>(tex, pc);
    }
    return p->lookup(f);
  };
  return m;
}

// Mesa drawing the view's plane through OpenGL (mesa_peer.h): the same camera, plane and mip
// pyramid, wrap addressing, trilinear or anisotropic (16) sampling, an RGBA8 image. Its
// derivatives are OpenGL's (differences over 2x2 pixel quads), not the fragments' analytic
// ones. `compare_to`: the texsim method it is closest to.
StudyFilterMethod mesa_method(const std::shared_ptr<const MesaPeer>& peer, bool aniso,
                              const std::string& compare_to) {
  const std::string drv = to_string(peer->driver());
  StudyFilterMethod m;
  m.name = "Mesa " + drv + (aniso ? " aniso 16" : " trilinear");
  if (aniso && peer->driver() == MesaDriver::Softpipe) m.name += " (EWA)";
  m.family = "mesa";
  m.arithmetic = "OpenGL on EGL surfaceless (" + peer->renderer() +
                 "): rasterised plane, derivatives over 2x2 quads, " +
                 (aniso ? "GL_TEXTURE_MAX_ANISOTROPY 16" : "GL_LINEAR_MIPMAP_LINEAR") +
                 ", RGBA8 framebuffer";
  m.compare_to = compare_to;
  m.render = [peer, aniso](const Texture& tex, const Scene& view,
                           const std::vector<Fragment>& fragments) {
    MesaView mv;
    mv.camera = view.camera;
    mv.background = view.background;
    mv.filter = aniso ? MesaFilter::Anisotropic : MesaFilter::Trilinear;
    for (const ScenePrimitive& p : view.primitives) {
      mv.primitives.push_back(
          {&tex,
           AddressMode::Wrap,
           {p.origin, p.origin + p.edge_u, p.origin + p.edge_u + p.edge_v, p.origin + p.edge_v},
           {p.uv_origin, p.uv_origin + p.uv_edge_u, p.uv_origin + p.uv_edge_u + p.uv_edge_v,
            p.uv_origin + p.uv_edge_v}});
    }
    const MesaImage img = peer->render(mv);
    std::vector<Rgba> out;
    out.reserve(fragments.size());
    for (const Fragment& f : fragments)
      out.push_back(img.at(static_cast<int>(f.x), static_cast<int>(f.y)));
    return out;
  };
  return m;
}

// The Mesa rows of every driver that starts; the others are named in `log`.
void add_mesa_methods(std::vector<StudyFilterMethod>& out, std::ostream* log) {
  for (MesaDriver d : {MesaDriver::Softpipe, MesaDriver::Llvmpipe}) {
    auto peer = std::make_shared<const MesaPeer>(d);
    if (!peer->available()) {
      if (log)
        *log << "study filters: Mesa " << to_string(d) << " rows skipped: " << peer->why_not()
             << "\n";
      continue;
    }
    out.push_back(mesa_method(peer, false, "trilinear (isotropic)"));
    out.push_back(mesa_method(peer, true, "ewa lut256"));
  }
}

}  // namespace

std::vector<StudyFilterMethod> thesis_filter_methods() {
  std::vector<StudyFilterMethod> out;
  EwaFilter::Config p8;  // texsim's configuration: reconstruction 1, anisotropy clamp 16
  p8.weight = EwaFilter::Weight::Pow8;
  EwaFilter::Config th = p8;  // the thesis configuration: no reconstruction term
  th.reconstruction = 0;
  EwaFilter::Config thw = th;
  thw.weight = EwaFilter::Weight::Thesis;
  const auto group = [&](const std::string& tag, const EwaFilter::Config& computed,
                         WeightMap::Transform tr) {
    out.push_back(ewa_method(tag + " computed", "weights", computed));
    WeightMap::Config mc;
    mc.kind = WeightMap::Kind::Quarter;
    mc.element = WeightMap::Element::U16;
    mc.size = 32;
    mc.function = WeightMap::Function::Pow8;
    mc.alpha = computed.alpha;
    mc.transform = tr;
    EwaFilter::Config m = computed;
    m.weight = EwaFilter::Weight::Map;
    out.push_back(ewa_method(tag + " map", "weight map", m, std::make_shared<const WeightMap>(mc)));
    out.back().compare_to = tag + " computed";
    EwaFilter::Config u = computed;
    u.weight = EwaFilter::Weight::Uniform;
    out.push_back(ewa_method(tag + " uniform", "weights", u));
    EwaFilter::Config e = computed;  // the V(d) sub-texel weights at the edge
    e.edge = EwaFilter::Edge::Vd;
    e.vd.evaluator = VdEvaluatorKind::P2;
    e.vd.format = NumberFormat::Fx16;
    out.push_back(ewa_method(tag + " computed + edge V(d) P2 fx16", "ewa", e));
  };
  group("texsim", p8, WeightMap::Transform::Cholesky);
  group("thesis", thw, WeightMap::Transform::Seed);
  // The thesis configuration's exact counterpart: exact weights without the reconstruction
  // term, computed and read through J⁻¹ (this project's reading of the map transform); the
  // seed's formula (5) reading is "thesis map" (the map's weights do not depend on the rule).
  out.push_back(ewa_method("exact, no reconstruction, computed", "weights", th));
  WeightMap::Config jc;
  jc.kind = WeightMap::Kind::Quarter;
  jc.size = 32;
  jc.function = WeightMap::Function::Pow8;
  jc.alpha = th.alpha;
  jc.transform = WeightMap::Transform::Jacobian;
  EwaFilter::Config jm = th;
  jm.weight = EwaFilter::Weight::Map;
  out.push_back(ewa_method("exact, no reconstruction, map jacobian", "weight map", jm,
                           std::make_shared<const WeightMap>(jc)));
  out.back().compare_to = "exact, no reconstruction, computed";
  SpafFilter::Config sv;  // SPAF with V(d) coverage: the other V(d) weighting (§9)
  sv.coverage = SpafFilter::Coverage::Vd;
  sv.vd.evaluator = VdEvaluatorKind::P2;
  sv.vd.format = NumberFormat::Fx16;
  out.push_back(
      footprint_method("spaf V(d) P2 fx16, budget 64", "spaf", SpafFilter(sv), "filter.spaf", ""));
  return out;
}

std::vector<StudyFilterMethod> study_filter_methods(const StudyFiltersOptions& opt,
                                                    std::ostream* log) {
  std::vector<StudyFilterMethod> methods;
  methods.push_back(baseline("trilinear (isotropic)", AnisoMode::Isotropic));
  methods.push_back(baseline("trilinear aniso 16 (Vulkan probes)", AnisoMode::Vulkan));
  const EwaFilter::Config c;  // defaults: LUT 256 u0.16, α = 2, max aniso 16, budget 1024, float
  add_ewa_variants(methods, c);
  add_weight_maps(methods, c);
  add_probe_methods(methods);
  add_spaf_methods(methods);
  if (opt.oiio) methods.push_back(oiio_method());
  if (opt.mesa) add_mesa_methods(methods, log);
  return methods;
}

StudyFilterRun run_study_filter_method(const StudyFilterMethod& m, TextureSet& textures,
                                       const std::vector<Fragment>& fragments,
                                       const TechTable& tech, const Scene* view,
                                       const ShaderIssue& issue) {
  StudyFilterRun r;
  if (m.render) {
    if (!view) throw InputError(m.name, "a renderer needs the view's scene");
    r.colours = m.render(textures[0], *view, fragments);
    return r;
  }
  r.colours.reserve(fragments.size());
  if (!m.hardware()) {
    for (const Fragment& f : fragments) r.colours.push_back(m.peer(textures[0], f));
    return r;
  }
  if (m.tallied) m.tallied->reset_tally(issue);
  MaterialSetup mat = m.material;
  mat.texture = 0;
  TextureUnit unit(textures, {mat}, PipelineSetup{}, tech, true);
  r.colours.resize(fragments.size());
  unit.process_batch(fragments.data(), fragments.size(), 0, r.colours.data());
  r.cycles = unit.cycles();
  r.misses = unit.cache().stats().misses;
  const ClockedPipeline& pipe = *unit.pipeline();
  for (int s = 0; s < pipe.stage_count(); ++s) {
    const StageConfig& c = pipe.config(s);
    if (c.name == "lod" || c.name == "address") r.latency += c.timing.latency;
  }
  if (m.tallied) r.tally = m.tallied->tally();
  for (const BlockUse& b : unit.material_blocks(0)) {
    if (b.name != "blend") r.area += b.timing.area;
    if (m.tallied) continue;
    // A baseline: the unit's LOD, trilinear and blend blocks; its texels are the filter's
    // taps, one probe per taps_per_probe, one texture fetch per bilinear quad.
    r.tally.ops += b.ops;
    if (b.name.rfind("filter.", 0) == 0) {
      r.tally.texels = b.texels;
      r.tally.visited =
          b.texels / static_cast<uint64_t>(TexelAddressGen(m.material.filter).taps_per_probe());
      r.tally.shader_cycles = static_cast<double>(b.texels) / (4.0 * issue.tex_per_cycle);
    }
  }
  return r;
}

}  // namespace texsim
