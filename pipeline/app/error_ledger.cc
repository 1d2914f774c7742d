#include "pipeline/app/error_ledger.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>
#include <sstream>

#include "pipeline/app/material_override.h"
#include "pipeline/scene/scene.h"

namespace texsim {

namespace {

enum LedgerBit : unsigned {
  kCoords,
  kDerivs,
  kRasterCoords,
  kLod,
  kSubtexel,
  kVd,
  kFilterArith,
  kTexels,
  kBits
};

struct BlockDef {
  const char* name;
  const char* exact;
  const char* prefix;  // the report's block names that carry its cost
};
constexpr BlockDef kDefs[kBits] = {
    {"coords", "heckbert division in double", "coords."},
    {"derivs", "analytic derivatives", "derivs."},
    {"raster_coords", "exact coordinates at the pixel centre (raster.coords = exact)",
     "raster.rect_scan.coords"},
    {"lod", "unquantised LOD fraction (mipmap_bits 16)", "lod"},
    {"subtexel", "unquantised weights (sub_texel_bits 16)", "filter."},
    {"vd", "exact V(d) in double", "filter."},
    {"filter_arith", "footprint set-up in double, exact Gaussian", "filter."},
    {"texels", "float texels (procedural textures: format=rgba32f)", "cache"},
};

constexpr const char* kFootprints[] = {"ewa", "multi_probe", "feline", "spaf"};

std::string str_at(const toml::table& t, const char* path, const char* def) {
  return t.at_path(path).value_or<std::string>(def);
}

bool classic(const toml::table& t) {
  return std::none_of(std::begin(kFootprints), std::end(kFootprints),
                      [&](const char* k) { return t.contains(k); });
}

// Whether material table `t` has block `b`.
bool has_block(const toml::table& t, unsigned b) {
  switch (b) {
    case kCoords:
      return t.contains("coords");
    case kDerivs:
      return t.contains("coords") && str_at(t, "coords.derivs", "analytic") != "none";
    case kRasterCoords:
      return str_at(t, "raster.method", "edge") == "rect_scan" &&
             str_at(t, "raster.coords", "constant_depth") == "constant_depth";
    case kLod:
      return classic(t) && str_at(t, "filter.mode", "bilinear") == "trilinear";
    case kSubtexel:
      return classic(t) && str_at(t, "filter.mode", "bilinear") != "nearest";
    case kVd:
      return str_at(t, "ewa.edge", "none") == "vd" || str_at(t, "spaf.coverage", "mask") == "vd";
    case kFilterArith:
      return t.contains("ewa") || t.contains("spaf") || t.contains("feline");
    default:  // kTexels depends on the texture: texel_exact_source()
      return false;
  }
}

// A procedural texture's source with float texels, or "" when the texture has no narrower
// format to replace (files are stored as their bit depth: an 8-bit file's texels are exact).
std::string texel_exact_source(const SceneTexture& t) {
  if (t.source.rfind("procedural:", 0) != 0 || t.source.find("format=rgba32f") != std::string::npos)
    return "";
  return t.source + (t.source.find('?') == std::string::npos ? "?" : "&") + "format=rgba32f";
}

bool bit(unsigned set, unsigned b) { return ((set >> b) & 1u) != 0; }

// The coordinate unit with its exact blocks: both exact drops it (the fragments then carry the
// reference generator's exact coordinates and derivatives).
void exact_coords(toml::table& t, unsigned x) {
  if (bit(x, kCoords) && (bit(x, kDerivs) || !has_block(t, kDerivs))) {
    t.erase("coords");
    return;
  }
  toml::table& c = sub_table(t, "coords");
  if (bit(x, kCoords)) {
    // Only the unit's own keys stay: the method's block keys belong to the old method.
    toml::table n;
    n.insert("method", "heckbert");
    n.insert("derivs", str_at(c, "derivs", "analytic"));
    n.insert("format", "double");
    if (c.contains("datapath")) n.insert("datapath", *c.get("datapath"));
    c = std::move(n);
  }
  if (bit(x, kDerivs) && has_block(t, kDerivs)) c.insert_or_assign("derivs", "analytic");
}

void exact_footprint(toml::table& t, unsigned x) {
  if (bit(x, kVd)) {
    for (const char* k : {"ewa", "spaf"}) {
      if (!t.contains(k)) continue;
      toml::table& vd = sub_table(sub_table(t, k), "vd");
      vd.insert_or_assign("evaluator", "exact");
      vd.insert_or_assign("format", "double");
    }
  }
  if (bit(x, kFilterArith)) {
    for (const char* k : {"ewa", "spaf", "feline"}) {
      if (!t.contains(k)) continue;
      toml::table& f = sub_table(t, k);
      f.insert_or_assign("arith", "double");
      if (std::string(k) == "ewa" && str_at(f, "weight", "lut") == "lut") {
        f.insert_or_assign("weight", "exp");
        f.erase("lut_size");
        f.erase("lut_bits");
      }
    }
  }
}

// Material table `orig` with the blocks of `x` that it has made exact.
toml::table exact_material(const toml::table& orig, unsigned x) {
  toml::table t = copy_table(orig);
  unsigned have = 0;
  for (unsigned b = 0; b < kBits; ++b) have |= has_block(orig, b) ? 1u << b : 0u;
  x &= have;
  if (bit(x, kCoords) || bit(x, kDerivs)) exact_coords(t, x);
  if (bit(x, kRasterCoords)) sub_table(t, "raster").insert_or_assign("coords", "exact");
  if (bit(x, kLod)) sub_table(t, "filter").insert_or_assign("mipmap_bits", 16);
  if (bit(x, kSubtexel)) sub_table(t, "filter").insert_or_assign("sub_texel_bits", 16);
  exact_footprint(t, x);
  return t;
}

// Max-channel absolute error of each buffer pixel; 0 where neither image is covered.
float pixel_error(const RunCapture& c, size_t i) {
  float e = 0;
  for (size_t k = 0; k < 3; ++k)
    e = std::max(e, std::abs(c.image->rgb[3 * i + k] - c.reference->rgb[3 * i + k]));
  return e;
}

LedgerDelta delta(const RunCapture& with, const RunCapture& without, double threshold) {
  LedgerDelta d;
  d.psnr_db = with.total.psnr_db;
  d.nmse = with.total.nmse;
  d.dpsnr_db = with.total.psnr_db - without.total.psnr_db;
  d.dnmse = without.total.nmse - with.total.nmse;
  d.dcycles = static_cast<int64_t>(with.cycles) - static_cast<int64_t>(without.cycles);
  const size_t n = with.image->covered.size();
  if (without.image->covered.size() != n) return d;  // not the same pixels: no per-pixel count
  for (size_t i = 0; i < n; ++i) {
    if (!with.image->covered[i] && !without.image->covered[i]) continue;
    if (std::abs(pixel_error(with, i) - pixel_error(without, i)) > threshold) ++d.pixels_changed;
  }
  if (without.total.pixels > 0)
    d.pixels_changed_pct =
        100.0 * static_cast<double>(d.pixels_changed) / static_cast<double>(without.total.pixels);
  return d;
}

RunCapture run_variant(const RunOptions& opt, const std::vector<std::string>& extra) {
  RunOptions o = opt;
  o.ledger = false;
  o.ledger_maps = false;
  o.progress = false;
  o.timeline.clear();
  o.overrides.insert(o.overrides.end(), extra.begin(), extra.end());
  RunCapture c;
  o.capture = &c;
  std::ostringstream quiet;
  run_simulation(o, quiet);
  return c;
}

void add_cost(LedgerRow& row, const BlockDef& def, const RunCapture& hw) {
  std::vector<BlockUse> all = hw.blocks;
  all.insert(all.end(), hw.raster_blocks.begin(), hw.raster_blocks.end());
  for (const BlockUse& b : all) {
    if (b.name.rfind(def.prefix, 0) != 0) continue;
    const bool ours = std::any_of(b.materials.begin(), b.materials.end(), [&](const auto& m) {
      return std::find(row.materials.begin(), row.materials.end(), m) != row.materials.end();
    });
    if (!ours) continue;
    row.ops += b.ops.total();
    row.area += b.timing.area;
  }
}

}  // namespace

std::vector<LedgerBlock> ledger_blocks(const Scene& scene) {
  std::vector<LedgerBlock> blocks;
  for (unsigned b = 0; b < kBits; ++b) {
    LedgerBlock lb{kDefs[b].name, kDefs[b].exact, {}};
    for (const SceneMaterial& m : scene.materials) {
      const bool has =
          b == kTexels ? !texel_exact_source(scene.textures[static_cast<size_t>(m.texture)]).empty()
                       : has_block(*m.effects, b);
      if (has) lb.materials.push_back(m.name);
    }
    blocks.push_back(lb);
  }
  return blocks;
}

std::vector<std::string> exact_overrides(const Scene& scene, unsigned exact) {
  std::vector<std::string> sets;
  for (const SceneMaterial& m : scene.materials) {
    const std::string before = inline_toml(*m.effects);
    const toml::table t = exact_material(*m.effects, exact);
    if (inline_toml(t) != before) sets.push_back(material_override(m.name, t));
  }
  if (bit(exact, kTexels)) {
    for (const SceneTexture& t : scene.textures) {
      const std::string src = texel_exact_source(t);
      if (!src.empty()) sets.push_back("textures." + t.name + ".source=\"" + src + "\"");
    }
  }
  return sets;
}

LedgerRun run_error_ledger(const RunOptions& opt, const RunCapture& hw, std::ostream& log) {
  const Scene scene = load_run_scene(opt);
  const std::vector<LedgerBlock> blocks = ledger_blocks(scene);
  unsigned all = 0;
  for (unsigned b = 0; b < kBits; ++b) all |= blocks[b].materials.empty() ? 0u : 1u << b;
  // One run per distinct set of exact blocks; set 0 is the run as configured.
  std::map<unsigned, RunCapture> runs;
  auto get = [&](unsigned set) -> const RunCapture& {
    if (set == 0) return hw;
    auto it = runs.find(set);
    if (it == runs.end())
      it = runs.emplace(set, run_variant(opt, exact_overrides(scene, set))).first;
    return it->second;
  };
  LedgerRun out;
  ErrorLedger& l = out.ledger;
  l.change_threshold = 0.5 / 255;  // half an 8-bit step
  l.hw_psnr_db = hw.total.psnr_db;
  l.hw_nmse = hw.total.nmse;
  l.hw_cycles = hw.cycles;
  l.pixels = hw.total.pixels;
  const RunCapture& exact = get(all);
  l.exact_psnr_db = exact.total.psnr_db;
  l.exact_nmse = exact.total.nmse;
  l.exact_cycles = exact.cycles;
  for (unsigned b = 0; b < kBits; ++b) {
    if (blocks[b].materials.empty()) continue;
    LedgerRow row;
    row.block = blocks[b].name;
    row.exact = blocks[b].exact;
    row.materials = blocks[b].materials;
    add_cost(row, kDefs[b], hw);
    const RunCapture& alone = get(1u << b);
    row.alone = delta(alone, hw, l.change_threshold);
    row.all_but = delta(exact, get(all & ~(1u << b)), l.change_threshold);
    if (opt.ledger_maps) {
      const std::string file = "ledger_" + row.block + ".png";
      out.maps.emplace_back(file, *alone.image);
      l.maps.push_back(file);
    }
    l.rows.push_back(std::move(row));
  }
  log << "texsim run: error ledger: " << l.rows.size() << " blocks, " << runs.size()
      << " extra runs\n";
  return out;
}

}  // namespace texsim
