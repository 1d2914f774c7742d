#include "pipeline/app/run.h"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <map>
#include <ostream>
#include <set>
#include <sstream>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/output_set.h"
#include "blocks/base/sample_op.h"
#include "blocks/base/version.h"
#include "blocks/texture/memory/storage_format.h"
#include "pipeline/app/board_sampler.h"
#include "pipeline/app/error_ledger.h"
#include "pipeline/app/fragment_router.h"
#include "pipeline/app/run_images.h"
#include "pipeline/app/run_object_space.h"
#include "pipeline/geometry/geometry_unit.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/image_io/astcenc_encoder.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/kernel/stage_timeline.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/raster/scene_front_end.h"
#include "pipeline/reference/ground_truth.h"
#include "pipeline/reference/layered_reference.h"
#include "pipeline/reference/operation_reference.h"
#include "pipeline/reference/surface_reference.h"
#include "pipeline/reference/truth_cache.h"
#include "pipeline/render/draw_fragment_trace.h"
#include "pipeline/report/run_report.h"
#include "pipeline/report/workload_feed.h"
#include "pipeline/scene/layered_source.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/scene_memory.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/texture_unit.h"
#include "pipeline/texture/unit_array.h"
#include "traces/prefetch_reader.h"
#include "traces/trace_csv.h"
#include "traces/trace_file.h"
#include "traces/trace_tools.h"

namespace texsim {

namespace {

class Progress {
 public:
  explicit Progress(bool on) : on_(on), t0_(std::chrono::steady_clock::now()) {}
  void tick(uint64_t n) {
    if (!on_ || (n & 0xFFFF) != 0) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    if (s < 1.0) return;
    std::fprintf(stderr, "\r  %llu fragments, %.1f M/s   ", static_cast<unsigned long long>(n),
                 static_cast<double>(n) / s / 1e6);
    shown_ = true;
  }
  ~Progress() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  bool on_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point t0_;
};

// The textures of a run and the map from fragment texture ids to them.
struct RunTextures {
  TextureSet set;
  std::map<uint32_t, int> index;       // texture id of the input -> texture of the set
  std::map<std::string, int> by_name;  // texture name -> texture of the set
  std::vector<std::string> names;      // "name = source", for the report
  std::vector<InputDigest> digests;    // texture files, for the report's provenance
};

InputDigest texture_digest(const std::string& name, const std::string& source,
                           const std::string& dir) {
  if (is_procedural_source(source)) return {"texture " + name, source, "", 0};

  return digest_file("texture " + name, resolve_texture_path(source, dir));
}

// The digests of a texture: one, or for a layered texture with file slices one per slice.
void add_texture_digests(std::vector<InputDigest>& out, const std::string& name,
                         const std::string& source, const std::string& dir) {
  if (!is_layered_source(source)) return out.push_back(texture_digest(name, source, dir));
  const LayeredSource ls = parse_layered_source(source, source);
  if (std::all_of(ls.slices.begin(), ls.slices.end(), is_procedural_source))
    return out.push_back({"texture " + name, source, "", 0});
  for (size_t k = 0; k < ls.slices.size(); ++k)
    out.push_back(texture_digest(name + " slice " + std::to_string(k), ls.slices[k], dir));
}

// The report's "name = source" of a texture, with its storage when it has one.
// "name = source", with the texture's storage and, for blocks, what produced them (the
// encoder with its version and options, or the file's format): the report's record of it.
std::string texture_label(const SceneTexture& t, const Texture& loaded) {
  const std::string spec = texture_storage_spec(t);
  const std::string note =
      t.format ? std::string(to_string(*t.format)) : spec.substr(spec.find('=') + 1);
  std::string label = t.name + " = " + t.source;
  if (!spec.empty()) label.append(" (").append(note).append(")");
  if (loaded.compressed()) label.append(" [").append(loaded.blocks()->provenance).append("]");
  return label;
}

// A trace's texture table: each texture loaded (relative to the trace), stored as its entry
// says (the scene run's conversion or encoder), and checked against the size the table declares.
RunTextures load_trace_textures(const TraceReader& reader, const std::string& trace_path) {
  RunTextures t;
  const std::string dir = std::filesystem::path(trace_path).parent_path().string();
  DrawTextureCache draws;  // textures of draw traces ("draws:PATH#ID", from trace gen --draws)
  std::set<std::string> draw_files;
  for (const auto& e : reader.header().textures) {
    // Name the trace and its table entry as well as the file.
    std::string entry = "texture table entry " + std::to_string(e.id);
    entry.append(" ('").append(e.name).append("')");
    SceneTexture st{e.name, e.source, "", {}, {}};
    set_texture_storage(st, e.storage, std::string(trace_path).append(": ").append(entry));
    Texture tex = [&] {
      try {
        return store_texture(
            is_draws_source(e.source) ? draws.load(e.source, dir) : load_texture(e.source, dir),
            st);
      } catch (const InputError& err) {
        throw InputError(trace_path, entry + ": " + err.what());
      }
    }();
    if (static_cast<uint32_t>(tex.width(0)) != e.width ||
        static_cast<uint32_t>(tex.height(0)) != e.height) {
      throw InputError(trace_path, "texture " + std::to_string(e.id) + " ('" + e.source + "') is " +
                                       std::to_string(tex.width(0)) + "x" +
                                       std::to_string(tex.height(0)) +
                                       " but the trace's texture table says " +
                                       std::to_string(e.width) + "x" + std::to_string(e.height));
    }
    const int id = t.set.add(std::move(tex));
    t.index[e.id] = id;
    t.by_name[e.name] = id;
    t.names.push_back(texture_label(st, t.set[id]));
    if (!is_draws_source(e.source)) {
      add_texture_digests(t.digests, e.name, e.source, dir);
    } else if (const std::string p = DrawTextureCache::path_of(e.source, dir);
               draw_files.insert(p).second) {
      t.digests.push_back(digest_file("textures of draw trace", p));  // once per file
    }
  }
  return t;
}

// A scene's textures, ids in declaration order.
RunTextures load_scene_textures(const Scene& scene) {
  RunTextures t;
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const int id = t.set.add(load_scene_texture(scene, i));
    t.index[static_cast<uint32_t>(i)] = id;
    t.by_name[scene.textures[i].name] = id;
    const SceneTexture& st = scene.textures[i];
    t.names.push_back(texture_label(st, t.set[id]));
    add_texture_digests(t.digests, scene.textures[i].name, scene.textures[i].source,
                        scene.base_dir);
  }
  return t;
}

// A trace's sampler table against its scene's [samplers]: the same entries in the same order,
// or an InputError naming the first sampler that differs and how.
void check_same_samplers(const SamplerTable& scene_table, const std::vector<TraceSampler>& trace,
                         const std::string& scene_path, const std::string& trace_path) {
  if (scene_table.size() != trace.size()) {
    throw InputError(trace_path, "the sampler table has " + std::to_string(trace.size()) +
                                     " entries and the [samplers] of " + scene_path + " " +
                                     std::to_string(scene_table.size()) +
                                     "; a record's sampler id must mean the same in both");
  }
  for (size_t k = 0; k < trace.size(); ++k) {
    const TraceSampler mine = to_trace_sampler(scene_table[k]);
    if (mine == trace[k]) continue;
    // The first key=value of the CSV directive form that differs.
    std::istringstream a(csv_sampler_directive(trace[k])), b(csv_sampler_directive(mine));
    std::string ta, tb, diff;
    while (a >> ta && b >> tb) {
      if (ta != tb) {
        diff = "the trace has ";
        diff += ta;
        diff += ", the scene ";
        diff += tb;
        break;
      }
    }
    std::string what = "sampler table entry " + std::to_string(k + 1);
    what += " ('" + trace[k].name;
    what += "') differs from sampler '" + mine.name;
    what += "' (id " + std::to_string(k + 1);
    what += ") of " + scene_path;
    what += ": " + diff;
    throw InputError(trace_path, what);
  }
}

// The scene's materials (a fragment's material is that of plane `prim`), or one default. Each
// material's texture is bound by name to the loaded textures (with a trace: its table's). The
// sampler table a record's `sampler` indexes: the scene's, which a trace's own table must
// equal, else the trace's.
std::vector<MaterialSetup> run_materials(const Scene& scene, bool use_scene,
                                         const RunTextures& textures, const std::string& trace,
                                         const std::vector<TraceSampler>& trace_samplers,
                                         std::ostream& log) {
  const bool from_trace = !trace.empty();
  std::vector<MaterialSetup> mats;
  std::shared_ptr<const SamplerTable> samplers = use_scene ? build_samplers(scene) : nullptr;
  if (from_trace && !trace_samplers.empty()) {
    if (samplers) {
      check_same_samplers(*samplers, trace_samplers, scene.path, trace);
    } else {
      samplers = sampler_table_of(trace_samplers, trace);
    }
  }
  if (use_scene) {
    for (const auto& m : scene.materials) {
      const std::string& name = scene.textures[static_cast<size_t>(m.texture)].name;
      const auto it = textures.by_name.find(name);
      if (it == textures.by_name.end()) {
        std::string have;
        for (const auto& [n, id] : textures.by_name) have += (have.empty() ? "'" : ", '") + n + "'";
        throw InputError(trace, "the texture table has no texture named '" + name +
                                    "', which material '" + m.name + "' of " + scene.path +
                                    " uses (the table has " + (have.empty() ? "none" : have) + ")");
      }
      mats.push_back(material_from_toml(m.name, it->second, *m.effects, scene.path,
                                        &textures.by_name, samplers));
      check_sampler_texture(scene, m, mats.back());
    }
  }
  if (from_trace) {
    // Trace fragments carry their coordinates: a material's coordinate unit has nothing to do.
    for (auto& m : mats) {
      if (!m.coords) continue;
      log << "texsim run: note: material '" << m.name
          << "': coords ignored, the trace's fragments carry their own coordinates\n";
      m.coords.reset();
    }
  }
  if (mats.empty()) {
    MaterialSetup d;
    d.name = "default";
    d.filter.filter = FilterMode::Trilinear;
    d.samplers = samplers;
    mats.push_back(d);
  }
  return mats;
}

// A fragment's ground truth: exact through its plane's projective map when the scene's planes
// are known, otherwise over the footprint its derivatives span.
struct GroundTruth {
  const TextureSet& textures;
  const std::vector<MaterialSetup>& mats;
  const std::vector<PlaneProjection>& maps;  // empty: from the fragment's derivatives
  // Materials with relief or lighting (empty: none): their reference, and the primitives'
  // shading frames.
  const std::vector<SurfaceReference>* surface = nullptr;
  const std::vector<SurfaceFrame>* frames = nullptr;
  PixelIntegrator integrate;  // the pixel model and how it is sampled ([reference])
  bool none = false;          // --reference none: black, nothing evaluated
  // A camera path: every frame's maps, by frame number (null: `maps` serve every fragment).
  // Several units record a frame's last fragments after the next frame has begun.
  const std::vector<std::vector<PlaneProjection>>* frame_maps = nullptr;
  // Array layers' level 0 as 2-D textures, made when a fragment first reads them.
  std::shared_ptr<LayerTextures> layers = std::make_shared<LayerTextures>();

  bool exact() const { return !maps.empty(); }
  const PlaneProjection& map_of(const Fragment& f) const {
    return frame_maps ? (*frame_maps)[f.frame][f.prim] : maps[f.prim];
  }
  // Adaptive sampling: pixels may be refined to finer tiers (TruthSampling).
  bool tiered() const { return !none && integrate.sampling().adaptive(); }
  // The sampler state of fragment f's operation truth (operation_reference.h), or none: a
  // plain sample, a footprint filter, a 3-D or cube texture (their own truths).
  std::optional<OperationSampler> operation_sampler(const Fragment& f, int material,
                                                    const Texture& stored) const {
    const MaterialSetup& ms = mats[static_cast<size_t>(material)];
    if (ms.footprint || stored.volume() || stored.shape().type == TextureType::Cube)
      return std::nullopt;
    const bool own = f.sampler == 0 || f.sampler == ms.sampler || !ms.samplers ||
                     f.sampler > ms.samplers->size();
    const TexelAddressGen::Config& c = own ? ms.filter : (*ms.samplers)[f.sampler - 1u].filter;
    const LodUnit::Config& l = own ? ms.lod : (*ms.samplers)[f.sampler - 1u].lod;
    OperationSampler s;
    s.au = c.address_u;
    s.av = c.address_v;
    s.border = glm::dvec4(border_texel(stored.storage(), c.border));
    s.offset_u = c.offset_u + f.offset_u;  // the record's offsets join the sampler's
    s.offset_v = c.offset_v + f.offset_v;
    s.compare = c.compare;
    s.reduction = c.reduction;
    s.unnormalized = c.unnormalized;
    const StorageFormatInfo& fi = format_info(stored.storage());
    s.unorm_depth = fi.depth && fi.coding == ChannelCoding::Unorm;
    s.lod_bias = l.lod_bias;
    s.min_lod = l.min_lod;
    s.max_lod = l.max_lod;
    // A record on another sampler than its material's (even a plain one) reads that sampler.
    if (!operation_truth_applies(f, s) && own) return std::nullopt;
    return s;
  }
  // Whether g's truth is an operation's (it reads fields the truth cache's key lacks).
  bool by_operation(const Fragment& g, int material) const {
    const Texture& stored = textures[static_cast<int>(g.tex)];
    return !none && (operation_sampler(g, material, stored).has_value() ||
                     (stored.volume() && volume_operation(g)));
  }
  // A 3-D fragment with its operation's truth: an explicit LOD or explicit gradients.
  static bool volume_operation(const Fragment& f) {
    return f.op == static_cast<uint8_t>(SampleOp::kSampleLod) ||
           f.op == static_cast<uint8_t>(SampleOp::kSampleGrad);
  }
  // f: the fragment as given; g: the same with its texture id mapped to the loaded texture;
  // tier: the adaptive tolerance's tier; *samples: the points the truth evaluated; *reach: the
  // finest tier whose value this also is.
  glm::dvec4 operator()(const Fragment& f, const Fragment& g, int material, int* samples,
                        int tier = 0, int* reach = nullptr) const {
    if (reach) *reach = TruthSampling::kTiers - 1;
    if (none) return glm::dvec4(0);
    const Texture& tex = textures[static_cast<int>(g.tex)].reference();
    const MaterialSetup& ms = mats[static_cast<size_t>(material)];
    const int x = static_cast<int>(f.x), y = static_cast<int>(f.y);
    const PixelIntegrator in = integrate.at_tier(tier);
    if (exact() && surface && (*surface)[static_cast<size_t>(material)].active()) {
      return (*surface)[static_cast<size_t>(material)](tex, map_of(f), (*frames)[f.prim], x, y, in,
                                                       samples, reach);
    }
    // The border colour as the unit's texture format reads it (border_texel), and the offset.
    const Texture& stored = textures[static_cast<int>(g.tex)];
    SamplerExtras extras;
    if (!ms.footprint) {
      extras.border = glm::dvec4(border_texel(stored.storage(), ms.filter.border));
      extras.offset_u = ms.filter.offset_u;
      extras.offset_v = ms.filter.offset_v;
    }
    if (tex.volume()) {  // level 0 trilinear in space; r from the material's lookup in a scene
      const AddressMode m3[3] = {ms.filter.address_u, ms.filter.address_v, ms.filter.address_w};
      const double* r = ms.lookup && ms.lookup->has_r ? ms.lookup->r : nullptr;
      static constexpr double kZero[3] = {0, 0, 0};
      if (volume_operation(f)) {
        OperationSampler s;
        s.lod_bias = ms.lod.lod_bias;
        s.min_lod = ms.lod.min_lod;
        s.max_lod = ms.lod.max_lod;
        return ground_truth_volume_operation(tex, m3, extras.border, s, f, in, samples, reach);
      }
      return ground_truth_volume(tex, m3, extras.border, f, exact() ? &map_of(f) : nullptr,
                                 r ? r : kZero, x, y, in, samples, reach);
    }
    if (tex.shape().type == TextureType::Cube) {  // through the fragment's direction map
      return ground_truth_cube(tex, reference_layer(f.layer, tex.shape().slices / 6),
                               ms.filter.seamless_cube, ms.address_u(), ms.address_v(),
                               extras.border, DirectionMap::of(f), x, y, in, samples, reach);
    }
    const Texture& t2d =
        tex.layered() ? layers->get(tex, reference_layer(f.layer, tex.shape().slices)) : tex;
    if (const std::optional<OperationSampler> s = operation_sampler(f, material, stored)) {
      return ground_truth_operation(t2d, *s, g, exact() ? &map_of(f) : nullptr, x, y, in, samples,
                                    reach);
    }
    return exact() ? ground_truth_exact(t2d, ms.address_u(), ms.address_v(), map_of(f), x, y, in,
                                        samples, reach, extras)
                   : ground_truth_footprint(t2d, ms.address_u(), ms.address_v(), g, in, samples,
                                            reach, extras);
  }
};

// Relief and lighting need each primitive's shading frame, in the unit and the reference
// (empty when no material has either effect).
struct SurfaceSetup {
  std::vector<SurfaceFrame> frames;
  std::vector<SurfaceReference> refs;
  bool active() const { return !refs.empty(); }
};

SurfaceSetup surface_setup(const Scene& scene, const std::vector<MaterialSetup>& mats,
                           const TextureSet& set) {
  SurfaceSetup s;
  if (std::none_of(mats.begin(), mats.end(),
                   [](const MaterialSetup& m) { return m.relief || m.lighting; }))
    return s;
  for (const auto& p : scene.primitives) s.frames.emplace_back(scene, p);
  for (const auto& m : mats) s.refs.emplace_back(m, set, scene.reference_relief_per_sample);
  return s;
}

// The run's link to the truth cache (truth_cache.h): the key, what the cache had and what the
// run computed. Only the exact truth is cached: a trace without a scene judges each fragment
// by its own derivatives, which its identity does not hold.
struct TruthMemo {
  std::unique_ptr<TruthCache> cache;
  TruthKey key{};
  std::shared_ptr<const TruthTable> table;  // null: the cache had nothing
  std::vector<char> cached;                 // per material: its truths may be cached
  std::vector<TruthRecord> fresh;           // computed by this run
  uint64_t hits = 0;
  const char* found_in = "";  // where the cache found `table`
  // The finer tiers (TruthSampling), each its own entry (truth_tier_key), looked up when the
  // run first needs that tier.
  struct Tier {
    TruthKey key{};
    std::shared_ptr<const TruthTable> table;
    std::vector<TruthRecord> fresh;
    bool looked = false;
  };
  std::array<Tier, TruthSampling::kTiers> tiers;
  std::vector<std::future<void>> writing;  // the entries being stored (awaited at the end)

  bool covers(int material) const { return cached[static_cast<size_t>(material)] != 0; }
  // Looks up each tier of `needed` (tiers[k] != 0) not looked up before (one thread).
  void find_tiers(const std::array<char, TruthSampling::kTiers>& needed) {
    for (int k = 1; k < TruthSampling::kTiers; ++k) {
      Tier& t = tiers[static_cast<size_t>(k)];
      if (!needed[static_cast<size_t>(k)] || t.looked) continue;
      t.looked = true;
      t.key = truth_tier_key(key, k);
      t.table = cache->find(t.key);
    }
  }
  // Keeps what the run computed (merged with what the cache had), on a thread of its own: the
  // entries are written while the run assembles and writes its outputs.
  void store() {
    auto keep = [this](const TruthKey& k, const std::shared_ptr<const TruthTable>& old,
                       std::vector<TruthRecord>& mine) {
      if (mine.empty()) return;
      auto t = old ? old->merged(mine) : std::make_shared<const TruthTable>(std::move(mine));
      writing.push_back(std::async(std::launch::async,
                                   [c = cache.get(), k, t = std::move(t)] { c->store(k, t); }));
    };
    keep(key, table, fresh);
    for (Tier& t : tiers) keep(t.key, t.table, t.fresh);
  }
  std::string summary() const {
    std::string s = "  truth cache: " + std::to_string(hits) + " of " +
                    std::to_string(hits + fresh.size()) + " fragment truths from ";
    s += table ? std::string(found_in) : "nowhere (a miss)";
    return s + ", key " + Sha256::hex(key).substr(0, 16) + "\n";
  }
};

// The geometry and rasterisation sections of a scene run (raster: per material, empty when
// the coordinate front end drew the scene).
SubsystemsInfo scene_subsystems(const Scene& scene, const std::vector<PlaneProjection>& maps,
                                const std::vector<MaterialSetup>& mats,
                                const std::vector<RasterCounters>& raster) {
  SubsystemsInfo s;
  s.geometry = run_geometry(scene, maps);
  for (size_t m = 0; m < raster.size() && m < mats.size(); ++m) {
    const RasterSetup& r = mats[m].raster;
    const char* coords = r.method == RasterSetup::Method::Edge ? ""
                         : r.constant_depth()                  ? "constant_depth"
                                                               : "exact";
    const bool parity = r.method == RasterSetup::Method::RectScan &&
                        r.rect_scan.coverage == RectScanCoverage::OutlineParity;
    s.raster.push_back({mats[m].name, r.block_name(), raster[m], coords, parity});
  }
  return s;
}

// Where a run's images lie: the canvas written and the extent of its buffers.
struct ImageLayout {
  int canvas_w = 0, canvas_h = 0;
  PixelRect extent;
  int pairs = 1;  // buffer pairs: two when a kept frame waits while later frames are compared
  uint64_t scene_bytes = 0;         // a scene run's primitive projections and depth test
  uint64_t object_space_bytes = 0;  // its object-space passes' splat and pass buffers
};

// A trace's layout from a first pass over it (which also finds bad records before the run):
// the canvas holds the scene's image (if any) and every fragment; the buffers only the
// fragments' bounding box.
ImageLayout trace_layout(const TraceSummary& sum, const Scene* scene, const std::string& path) {
  // The image a trace draws is at most as wide and high as a scene's (16384): a pixel beyond
  // it is refused here rather than wrapped into a negative extent.
  constexpr double kMaxPixel = 16383;
  if (sum.x.hi > kMaxPixel || sum.y.hi > kMaxPixel) {
    const bool in_x = sum.x.hi > kMaxPixel;
    throw InputError(path, std::string("a fragment lies at ") + (in_x ? "x = " : "y = ") +
                               std::to_string(static_cast<uint64_t>(in_x ? sum.x.hi : sum.y.hi)) +
                               ": a run draws pixels 0 to 16383 in x and y (an image of at most "
                               "16384 x 16384, as a scene's [output])");
  }
  ImageLayout l;
  l.extent = {static_cast<int>(sum.x.lo), static_cast<int>(sum.y.lo),
              static_cast<int>(sum.x.hi) + 1, static_cast<int>(sum.y.hi) + 1};
  l.canvas_w = std::max(scene ? scene->width : 0, l.extent.x1);
  l.canvas_h = std::max(scene ? scene->height : 0, l.extent.y1);
  l.pairs = sum.frames.size() > 1 || sum.frames_overflow ? 2 : 1;
  return l;
}

uint64_t texture_bytes(const TextureSet& set) {
  uint64_t b = 0;
  for (int t = 0; t < set.size(); ++t) {
    for (int l = 0; l < set[t].levels(); ++l) {
      b = sat_add(b, sat_mul(sat_mul(static_cast<uint64_t>(set[t].width(l)),
                                     static_cast<uint64_t>(set[t].height(l))),
                             static_cast<uint64_t>(set[t].bytes_per_texel())));
    }
  }
  return b;
}

std::string gib(uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f GiB", static_cast<double>(bytes) / (1 << 30));
  return buf;
}

// Refuses a run whose estimated memory exceeds --max-memory, naming what sets the size.
void check_memory(const RunOptions& opt, const ImageLayout& l, const TextureSet& textures,
                  const std::string& source, const std::string& what) {
  const uint64_t tex = texture_bytes(textures);
  const uint64_t img = RunImages::estimate_bytes(l.extent, l.pairs, l.canvas_w, l.canvas_h);
  const uint64_t total = sat_add(sat_add(sat_add(tex, img), l.scene_bytes), l.object_space_bytes);
  if (total <= opt.max_memory) return;
  throw InputError(source, what + ": the run needs an estimated " + gib(total) + " (images " +
                               std::to_string(l.extent.x1 - l.extent.x0) + " x " +
                               std::to_string(l.extent.y1 - l.extent.y0) + " pixels of a " +
                               std::to_string(l.canvas_w) + " x " + std::to_string(l.canvas_h) +
                               " image: " + gib(img) + "; textures: " + gib(tex) +
                               "; primitives and depth test: " + gib(l.scene_bytes) +
                               "; object-space buffers: " + gib(l.object_space_bytes) +
                               "), over the --max-memory limit of " + gib(opt.max_memory));
}

// The trace's digest for the provenance (its whole file is hashed): read beside the run when
// it has more than one thread, else when asked for; the same digest either way.
std::future<InputDigest> trace_digest(const RunOptions& opt) {
  if (opt.trace.empty()) return {};
  const auto policy = resolve_threads(opt.threads) > 1 ? std::launch::async : std::launch::deferred;
  return std::async(policy, [path = opt.trace] { return digest_file("trace", path); });
}

Provenance run_provenance(const RunOptions& opt, const std::string& scene_path,
                          const RunTextures& textures, const PipelineSetup& setup,
                          const TechTable& tech, std::future<InputDigest>& trace) {
  Provenance p;
  p.version = kTexsimVersion;
  p.command = opt.command;
  if (!scene_path.empty()) {
    p.inputs.push_back(opt.scene.empty() || opt.scene == "default" || !opt.scene_text.empty()
                           ? InputDigest{"scene", scene_path, "", 0}
                           : digest_file("scene", scene_path));
  }
  if (trace.valid()) p.inputs.push_back(trace.get());
  p.inputs.insert(p.inputs.end(), textures.digests.begin(), textures.digests.end());
  p.setup = setup;
  p.tech = tech;
  return p;
}

// The material of trace record `index`: its primitive's in the scene.
int primitive_material(const Fragment& f, uint64_t index, const Scene& scene,
                       const std::string& trace) {
  if (f.prim >= scene.primitives.size()) {
    throw InputError(trace, "record " + std::to_string(index) + ": primitive " +
                                std::to_string(f.prim) + " is not a primitive of scene " +
                                scene.path);
  }
  return scene.primitives[f.prim].material;
}

// Every fragment of the trace, in order, to `handle`. With more than one thread the next
// chunks are read and decoded while these simulate.
template <class Handle>
void stream_trace(TraceReader& reader, int threads, Handle&& handle) {
  std::unique_ptr<PrefetchReader> ahead;
  if (resolve_threads(threads) > 1) ahead = std::make_unique<PrefetchReader>(reader);
  std::vector<Fragment> chunk;
  while ((ahead ? ahead->next_chunk(chunk) : reader.next_chunk(chunk)) > 0) {
    for (const Fragment& f : chunk) handle(f);
  }
}

// A scene whose materials compute their own coordinates: planes drawn one by one through the
// front end (unit 0 runs the coordinate units; with several units each fragment is textured
// by its tile's unit). `workload` (if not null) counts every fragment that leaves the front end,
// in the order it leaves (units record theirs later, in an order that depends on their timing).
void draw_front_end(const Scene& scene, const std::vector<PlaneProjection>& maps, UnitArray& units,
                    const RunTextures& textures, const UnitArray::Record& record, uint64_t& index,
                    WorkloadStats* workload) {
  auto emitted = [workload](const Fragment& f, const Fragment& g) {
    if (workload) workload->add(f, g.tex);
  };
  auto loaded = [&](const Fragment& f) {
    Fragment g = f;
    g.tex = static_cast<uint32_t>(textures.index.at(f.tex));
    return g;
  };
  if (!units.several()) {
    draw_scene_front_end(scene, maps, units.unit(0),
                         [&](const Fragment& f, int material, const Rgba* c) {
                           const Fragment g = loaded(f);
                           emitted(f, g);
                           record(f, g, material, c, index++);
                         });
    return;
  }
  FrontEndTarget target;
  target.texture = [&](const Fragment& f, int m, const ItemCost* front) {
    const Fragment g = loaded(f);
    emitted(f, g);
    units.add(f, g, g, m, index++, front);
  };
  target.drop = [&](int m, const ItemCost* front, bool rejected, int32_t x, int32_t y) {
    units.drop(m, front, rejected, x, y);
  };
  target.untextured = [&](const Fragment& f, int m) {
    const Fragment g = loaded(f);
    emitted(f, g);
    record(f, g, m, nullptr, index++);
  };
  draw_scene_front_end(scene, maps, units.unit(0), target);
}

// Quad derivatives replace the fragment's own; a coordinate unit computes them itself.
void refuse_quad_derivatives_with_coords(const PipelineSetup& setup,
                                         const std::vector<MaterialSetup>& mats,
                                         const std::string& scene_path) {
  if (setup.derivatives == QuadDerivatives::Own) return;
  for (const MaterialSetup& m : mats) {
    if (m.coords) {
      throw InputError(scene_path, "[pipeline] derivatives: material '" + m.name +
                                       "' computes its own coordinates and derivatives "
                                       "(coords); set derivatives = \"fragment\"");
    }
  }
}

// The report's quads section, when the run has one.
void quad_info(RunInfo& info, const PipelineSetup& setup, const QuadFeed* quads,
               const UnitArray& units) {
  if (!quads && !setup.quad_merge) return;
  QuadInfo& q = info.quads;
  q.derivatives = setup.derivatives;
  q.merge = setup.quad_merge;
  if (quads) q.counts = quads->counts();
  q.merged_lookups = units.quad_merged_lookups();
}

// Fragments waiting for their ground truth, computed in parallel a batch at a time and then
// recorded in arrival order. Each truth depends on its fragment alone, so every thread count
// gives the same bits.
class TruthBatch {
 public:
  TruthBatch(const GroundTruth& truth, RunImages& images, Progress& progress, std::string input,
             int threads, std::unique_ptr<TruthMemo> memo)
      : truth_(truth),
        images_(images),
        progress_(progress),
        input_(std::move(input)),
        threads_(threads),
        memo_(std::move(memo)) {
    items_.reserve(kSize);
  }
  // colour null: not textured.
  void add(const Fragment& f, const Fragment& g, int material, const Rgba* colour, uint64_t index) {
    if (truth_.none) {  // nothing to compute: the fragment goes to the images at once
      set_image(f, material, colour, glm::dvec4(0), index);
      ++pixels_;
      return;
    }
    // A cached fragment's likely place in the table: the cache's records are in arrival order.
    Item it{f, g, material, colour != nullptr, colour ? *colour : Rgba(0), index};
    it.cacheable = memo_ && memo_->covers(material) && !truth_.by_operation(g, material);
    const size_t hint = it.cacheable ? hint_++ : SIZE_MAX;
    it.hint = hint;
    items_.push_back(it);
    if (items_.size() == kSize) flush();
  }
  void flush() {
    // Chunks taken in turn: adaptive pixels cost from 9 to 4225 samples, unevenly spread.
    const size_t chunks = (items_.size() + kChunk - 1) / kChunk;
    parallel_tasks(chunks, threads_, [&](size_t c) {
      for (size_t i = c * kChunk; i < std::min(items_.size(), (c + 1) * kChunk); ++i)
        judge(items_[i]);
    });
    refine_all();
    for (const Item& it : items_) {
      samples_ += static_cast<uint64_t>(it.samples);
      refined_ += it.tier > 0 ? 1 : 0;
      if (memo_ && it.cached) ++memo_->hits;
      if (!it.cached && it.cacheable) memo_->fresh.push_back(record_of(it));
      if (it.tier > 0 && !it.tier_cached && it.cacheable) {
        memo_->tiers[static_cast<size_t>(it.tier)].fresh.push_back(
            {id_of(it), {it.truth.r, it.truth.g, it.truth.b, it.truth.a}, it.samples, 0});
      }
      set_image(it.f, it.material, it.textured ? &it.colour : nullptr, it.truth, it.index);
    }
    pixels_ += items_.size();
    items_.clear();
  }
  // The last batch; the truths computed are kept in the truth cache, and the log says where
  // the truths came from.
  void finish(std::ostream& log) {
    flush();
    if (!memo_) return;
    log << memo_->summary() << "  truth tiers: " << refined_ << " of " << pixels_
        << " fragment truths refined beside a small filter error\n";
    memo_->store();
  }
  // Mean points evaluated per fragment so far.
  double mean_samples() const {
    return pixels_ ? static_cast<double>(samples_) / static_cast<double>(pixels_) : 0;
  }

 private:
  static constexpr size_t kSize = 16384, kChunk = 256;
  struct Item {
    Fragment f, g;
    int material;
    bool textured;
    Rgba colour;
    uint64_t index;
    glm::dvec4 truth{0};     // the truth compared (tier 0's, or a finer tier's)
    int samples = 0;         // its points
    bool cached = false;     // tier 0 taken from the truth cache
    size_t hint = SIZE_MAX;  // where the truth cache's table likely has it
    glm::dvec4 truth0{0};    // tier 0: its truth, points and reach
    int samples0 = 0, reach0 = 0;
    int tier = 0;              // the tier of `truth`
    bool tier_cached = false;  // that tier's truth taken from the truth cache
    // Its truth may be kept in the truth cache (not an operation's: see by_operation).
    bool cacheable = false;
  };
  void set_image(const Fragment& f, int material, const Rgba* colour, const glm::dvec4& truth,
                 uint64_t index) {
    try {
      images_.set(f.frame, static_cast<int>(f.x), static_cast<int>(f.y), colour, material, truth);
    } catch (const std::invalid_argument& e) {
      throw InputError(input_, "record " + std::to_string(index) + ": " + e.what());
    }
    progress_.tick(images_.count());
  }
  static TruthId id_of(const Item& it) {
    return {it.f.frame, it.f.prim, it.f.x, it.f.y, static_cast<uint32_t>(it.material), it.g.tex};
  }
  static TruthRecord record_of(const Item& it) {
    return {id_of(it),
            {it.truth0.r, it.truth0.g, it.truth0.b, it.truth0.a},
            it.samples0,
            static_cast<uint32_t>(it.reach0)};
  }
  // The item's tier-0 truth: the cached one when the cache has it, else computed.
  void judge(Item& it) const {
    if (it.cacheable && memo_->table) {
      if (const TruthRecord* r = memo_->table->find(id_of(it), it.hint)) {
        it.truth0 = {r->rgba[0], r->rgba[1], r->rgba[2], r->rgba[3]};
        it.samples0 = r->samples;
        it.reach0 = static_cast<int>(r->reach);
        it.cached = true;
      }
    }
    if (!it.cached) it.truth0 = truth_(it.f, it.g, it.material, &it.samples0, 0, &it.reach0);
    it.truth = it.truth0;
    it.samples = it.samples0;
  }
  // The tier each textured item needs beside the filter's error e there (against tier 0):
  // asked of e, or of E²/e where e is below its material's RMS error E so far (this batch
  // included), so that every pixel's share |e|·tol stays under E²/kTierRatio and pixels the
  // filter gets nearly right are not refined beyond what the material's figure needs
  // (docs/architecture.md#reference-generator-and-ground-truth). In item order, one thread:
  // the same tiers with any thread count and with or without the truth cache.
  void decide_tiers() {
    if (!truth_.tiered()) return;
    for (const Item& it : items_) {
      if (!it.textured) continue;
      const glm::dvec3 e = glm::dvec3(it.colour) - glm::dvec3(it.truth0);
      const auto m = static_cast<size_t>(it.material);
      if (m >= err_sq_.size()) err_sq_.resize(m + 1, {0, 0});
      err_sq_[m].first += glm::dot(e, e);
      err_sq_[m].second += 3;
    }
    for (Item& it : items_) {
      if (!it.textured) continue;
      const glm::dvec3 e = glm::abs(glm::dvec3(it.colour) - glm::dvec3(it.truth0));
      const auto& [sum, n] = err_sq_[static_cast<size_t>(it.material)];
      const double err = std::max(std::max(e.r, e.g), e.b), rms_sq = sum / n;
      if (!(err > 0)) continue;  // no share of the cross term (or no figure: NaN)
      const int need = TruthSampling::refine_tier(err < rms_sq / err ? rms_sq / err : err);
      if (need > it.reach0) it.tier = need;  // else tier 0's value already is that tier's
    }
  }
  // The finer tier's truth of every item that needs one: cached, else computed.
  void refine_all() {
    decide_tiers();
    std::vector<size_t> todo;
    std::array<char, TruthSampling::kTiers> needed{};
    for (size_t i = 0; i < items_.size(); ++i) {
      if (items_[i].tier == 0) continue;
      todo.push_back(i);
      needed[static_cast<size_t>(items_[i].tier)] = 1;
    }
    if (todo.empty()) return;
    if (memo_) memo_->find_tiers(needed);
    constexpr size_t kRefineChunk = 32;
    parallel_tasks((todo.size() + kRefineChunk - 1) / kRefineChunk, threads_, [&](size_t c) {
      for (size_t j = c * kRefineChunk; j < std::min(todo.size(), (c + 1) * kRefineChunk); ++j)
        refine(items_[todo[j]]);
    });
  }
  void refine(Item& it) const {
    if (it.cacheable) {
      const auto& table = memo_->tiers[static_cast<size_t>(it.tier)].table;
      if (const TruthRecord* r = table ? table->find(id_of(it)) : nullptr) {
        it.truth = {r->rgba[0], r->rgba[1], r->rgba[2], r->rgba[3]};
        it.samples = r->samples;
        it.tier_cached = true;
        return;
      }
    }
    it.truth = truth_(it.f, it.g, it.material, &it.samples, it.tier);
  }
  const GroundTruth& truth_;
  RunImages& images_;
  Progress& progress_;
  std::string input_;
  int threads_;
  std::unique_ptr<TruthMemo> memo_;  // null: no truth cache
  size_t hint_ = 0;                  // cached fragments added so far
  std::vector<Item> items_;
  uint64_t samples_ = 0, pixels_ = 0, refined_ = 0;
  std::vector<std::pair<double, double>> err_sq_;  // per material: Σ err² over R, G, B, and n
};

// Writes the images and reports to opt.out and a summary to log.
void write_run_outputs(const RunOptions& opt, const RunInfo& info, const RunImages& images,
                       const UnitArray& unit, const RunSummary& sum, const LedgerRun& ledger,
                       std::ostream& log) {
  // Every file is moved into opt.out together, once every one was written.
  OutputSet outputs(opt.out);
  // The truth's two images are encoded on threads of their own beside the image's (the same
  // bytes; each waits for its thread before an error of another leaves) — but one at a time
  // on a large canvas, where each holds an 8-bit copy of the whole canvas (768 MiB at 16384²).
  const std::string image_png = outputs.path("image.png");
  const ImageRgb& img = images.image();
  constexpr int64_t kParallelCanvasPixels = int64_t{1} << 25;  // 96 MiB per 8-bit canvas
  const bool parallel = resolve_threads(opt.threads) > 1 &&
                        int64_t{img.canvas_width} * img.canvas_height <= kParallelCanvasPixels;
  std::future<void> reference, error;
  if (info.has_truth && !parallel) {
    write_image(outputs.path("reference.png"), images.reference());
    write_error_heatmap(outputs.path("error.png"), images.image(), images.reference(),
                        info.error_scale);
  } else if (info.has_truth) {
    reference = std::async(std::launch::async, [&images, p = outputs.path("reference.png")] {
      write_image(p, images.reference());
    });
    error = std::async(std::launch::async, [&images, &info, p = outputs.path("error.png")] {
      write_error_heatmap(p, images.image(), images.reference(), info.error_scale);
    });
  }
  write_image(image_png, images.image());
  if (reference.valid()) reference.get();
  if (error.valid()) error.get();
  for (const auto& [file, exact] : ledger.maps)
    write_error_heatmap(outputs.path(file), exact, images.image(), info.error_scale);
  write_run_reports(outputs.staging(), info, unit, sum.accuracy);
  outputs.commit();
  log << "texsim run: " << sum.fragments << " fragments, " << sum.cycles << " cycles, ";
  if (!info.has_truth) {
    log << "no ground truth (--reference none): no accuracy figures";
  } else {
    log << "PSNR " << sum.accuracy.psnr_db << " dB";
  }
  if (info.frames.size() > 1) {
    log << " over " << info.frames.size() << " frames (images: frame " << info.image_frame << ")";
  }
  log << "\n  report: " << opt.out << "/report.json, " << opt.out << "/report.md\n";
  log << "  images: " << opt.out << "/image.png";
  if (info.has_truth) log << ", " << opt.out << "/reference.png, " << opt.out << "/error.png";
  log << "\n";
  if (!ledger.maps.empty())
    log << "  ledger maps: " << opt.out << "/ledger_<block>.png (" << ledger.maps.size() << ")\n";
}

// The run's images and figures for a caller that compares runs.
RunCapture capture_run(const RunImages& images, const UnitArray& unit, const RunSummary& sum) {
  RunCapture c;
  c.image = std::make_unique<ImageRgb>(images.image());
  c.reference = std::make_unique<ImageRgb>(images.reference());
  c.total = sum.accuracy;
  for (int m = 0; m < unit.material_count(); ++m) {
    c.materials.push_back(images.material(m));
    c.material_names.push_back(unit.material(m).name);
  }
  c.cycles = sum.cycles;
  c.blocks = unit.blocks();
  for (const BlockUse& b : c.blocks) c.area += b.timing.area;
  return c;
}

// The constant-depth coordinate block of each rect_scan material that drives it (the ledger's
// `raster_coords` cost).
std::vector<BlockUse> raster_coord_blocks(const std::vector<MaterialSetup>& mats,
                                          const std::vector<RasterCounters>& raster) {
  std::vector<BlockUse> out;
  for (size_t m = 0; m < raster.size() && m < mats.size(); ++m) {
    if (!mats[m].raster.constant_depth()) continue;
    BlockUse b;
    b.name = "raster.rect_scan.coords";
    b.arithmetic = "double";
    b.ops = raster[m].coord_ops;
    b.materials = {mats[m].name};
    out.push_back(std::move(b));
  }
  return out;
}

// First pass over a trace: its records are checked, its pixel extent and frames found.
TraceSummary first_pass(const RunOptions& opt) {
  struct stat st {};
  if (::stat(opt.trace.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    throw InputError(opt.trace,
                     "is not a regular file: a run reads its trace twice (first for the "
                     "pixels and frames it covers)");
  }
  TraceSummary sum = summarize_trace(opt.trace, resolve_threads(opt.threads) > 1);
  if (sum.records == 0) throw InputError(opt.trace, "no fragments to render");
  if (opt.frame >= 0 && !sum.frames_overflow &&
      sum.frames.count(static_cast<uint32_t>(opt.frame)) == 0) {
    std::string have;
    for (const auto& [f, n] : sum.frames) {
      if (have.size() > 60) {
        have += ", ...";
        break;
      }
      have += (have.empty() ? "" : ", ") + std::to_string(f);
    }
    throw InputError(opt.trace, "--frame " + std::to_string(opt.frame) +
                                    ": the trace has no such frame (its frames: " + have + ")");
  }
  return sum;
}

// Object-space passes (run_object_space.h): each keeps an image, coverage and drawn flags of
// the whole image; the splat buffer (colour, weight and depth in double) lives while one
// pass renders.
uint64_t object_space_bytes(const Scene& scene) {
  uint64_t passes = 0;
  for (const SceneMaterial& m : scene.materials) passes += m.object_space ? 1 : 0;
  if (passes == 0) return 0;
  const uint64_t px = sat_mul(static_cast<uint64_t>(std::max(scene.width, 0)),
                              static_cast<uint64_t>(std::max(scene.height, 0)));
  return sat_mul(px, sat_add(6 * sizeof(double), sat_mul(passes, sizeof(Rgba) + 2)));
}

// The run's layout, checked against --max-memory before any buffer is made.
ImageLayout run_layout(const RunOptions& opt, const Scene& scene, bool use_scene,
                       const TraceSummary* trace, const std::vector<PlaneProjection>& maps,
                       const TextureSet& textures) {
  if (trace != nullptr) {
    const ImageLayout l = trace_layout(*trace, use_scene ? &scene : nullptr, opt.trace);
    check_memory(opt, l, textures, opt.trace,
                 "its fragments cover pixels (" + std::to_string(l.extent.x0) + ", " +
                     std::to_string(l.extent.y0) + ") to (" + std::to_string(l.extent.x1 - 1) +
                     ", " + std::to_string(l.extent.y1 - 1) + ")");
    return l;
  }
  if (opt.frame >= scene.frames) {
    throw InputError(scene.path,
                     "--frame " + std::to_string(opt.frame) + ": the scene renders " +
                         (scene.frames == 1 ? std::string("frame 0 only")
                                            : "frames 0 to " + std::to_string(scene.frames - 1)));
  }
  ImageLayout l{scene.width, scene.height, scene_extent(scene, maps), 1};
  if (scene.frames > 1) {  // a camera path: every frame may cover any pixel
    l.extent = {0, 0, scene.width, scene.height};
    l.pairs = 2;
  }
  l.scene_bytes = sat_add(
      sat_mul(l.extent.pixels(), kDepthTestBytesPerPixel),
      sat_mul(maps.size(), sizeof(PlaneProjection) * (2 + (scene.frames > 1 ? scene.frames : 0))));
  // The run's maps and the generator's, and with a camera path every frame's (for the truth).
  l.object_space_bytes = object_space_bytes(scene);
  check_memory(opt, l, textures, scene.path,
               "[output] width = " + std::to_string(scene.width) +
                   ", height = " + std::to_string(scene.height));
  return l;
}

std::string reference_text(const GroundTruth& truth, double mean_samples, size_t frames,
                           bool surface, const std::vector<MaterialSetup>& mats,
                           bool relief_per_sample) {
  if (truth.none) {
    return "No ground truth (--reference none): it was not computed, so this report has no "
           "accuracy figures (null in report.json) and the run writes no reference.png or "
           "error.png.";
  }
  const PixelIntegrator& in = truth.integrate;
  std::string s = "Ground truth: level-0 texture, bilinear reconstruction in double, " +
                  in.sampling().describe(in.pixel()) + " " +
                  (truth.exact() ? "mapped exactly through each plane's projective map."
                                 : "over the parallelogram spanned by the fragment's derivatives.");
  if (in.sampling().adaptive()) {
    char buf[96];
    std::snprintf(buf, sizeof buf, " Mean %.1f samples per fragment.", mean_samples);
    s += buf;
  }
  if (surface && relief_per_sample) {
    s += " Materials with relief: every sample is shifted along its own view ray to where it "
         "meets the height field (1024-layer search, 24 halvings, double; [reference] relief = "
         "\"per_sample\"). Materials with lighting: every sample is lit (Blinn-Phong in double) "
         "with the normal at its own coordinates and the pixel's view vector, then averaged.";
  } else if (surface) {
    s += " Materials with relief: every sample is shifted by the (u, v) offset of the pixel "
         "centre's view ray meeting the height field (1024-layer search, 24 halvings, double). "
         "Materials with lighting: every sample is lit (Blinn-Phong in double) with the normal "
         "at its own coordinates and the pixel's view vector, then averaged.";
  }
  if (std::any_of(mats.begin(), mats.end(), [](const MaterialSetup& m) {
        return m.relief && m.relief->method == ReliefSetup::Method::Terrain;
      })) {
    s += " Relief method terrain: the ray is marched in steps of 1/16 texel over the "
         "finite-function surface (direct sum), then 40 halvings.";
  }
  if (frames > 1) {
    s += " Each of the " + std::to_string(frames) +
         " frames is compared with its own ground truth (frames[].accuracy); the totals pool "
         "the covered pixels of all frames.";
  }
  return s;
}

// The stage timeline when --timeline asks for one (then each fragment's stage times are
// copied), else null.
std::unique_ptr<StageTimeline> make_timeline(const RunOptions& opt, const UnitArray& units) {
  if (opt.timeline.empty()) return nullptr;
  if (!units.unit(0).pipeline()) {
    throw InputError(opt.timeline, "--timeline needs the clocked pipeline (not --functional)");
  }
  return std::make_unique<StageTimeline>(opt.timeline_limit);
}

// The loaded texture's index of a streamed fragment; its texture id must be in the table and
// its pixel within the image limit.
uint32_t loaded_texture(const Fragment& f, uint64_t index, const RunTextures& textures,
                        const std::string& input, const std::string& trace) {
  auto it = textures.index.find(f.tex);
  if (it == textures.index.end()) {
    throw InputError(input, "record " + std::to_string(index) + ": texture id " +
                                std::to_string(f.tex) + " is not in the texture table");
  }
  if (f.x >= (1u << 14) || f.y >= (1u << 14)) {
    throw InputError(trace, "record " + std::to_string(index) + ": pixel (" + std::to_string(f.x) +
                                ", " + std::to_string(f.y) +
                                ") is outside the 16384x16384 image limit");
  }
  return static_cast<uint32_t>(it->second);
}

// A record's sampler: 0 (its material's own) or an id of the scene's sampler table; an
// unnormalised sampler refuses what Vulkan refuses, and one that compares or reduces a texture
// other than 2-D.
void check_record_sampler(const Fragment& f, uint64_t index, const MaterialSetup& m,
                          TextureType type, const std::string& input) {
  const size_t n = m.samplers ? m.samplers->size() : 0;
  if (f.sampler > n) {
    throw InputError(input, "record " + std::to_string(index) + ": sampler " +
                                std::to_string(f.sampler) + " is not in the sampler table (" +
                                (n == 0 ? std::string("the scene has no [samplers]")
                                        : "ids 1.." + std::to_string(n) + ", 0 = the material's") +
                                ")");
  }
  const TexelAddressGen::Config& c =
      f.sampler == 0 ? m.filter : (*m.samplers)[f.sampler - 1u].filter;
  if (m.footprint && type != TextureType::Tex2D) {
    throw InputError(input, "record " + std::to_string(index) + ": texture " +
                                std::to_string(f.tex) + " is a " + to_string(type) +
                                " texture, which the material's footprint filter (" +
                                m.footprint->name() + ") does not sample");
  }
  if (type == TextureType::Volume && f.op == static_cast<uint8_t>(SampleOp::kGather)) {
    throw InputError(input, "record " + std::to_string(index) + ": texture " +
                                std::to_string(f.tex) +
                                " is a 3-D texture: op 'gather' reads 2-D and cube images only");
  }
  if (c.reduces() && type != TextureType::Tex2D) {
    throw InputError(input, "record " + std::to_string(index) + ": texture " +
                                std::to_string(f.tex) + " (" + to_string(type) +
                                ") cannot be read with a sampler that compares or reduces (the "
                                "cube, array and 3-D paths have no texel reducer)");
  }
  if (!c.unnormalized) return;
  std::string why = unnormalized_refusal(type);
  if (why.empty()) why = unnormalized_refusal(f);
  if (!why.empty()) throw InputError(input, "record " + std::to_string(index) + ": " + why);
}

// A record's material (its primitive's when the scene's planes are known, else 0), with its
// sampler checked.
int record_material(const Fragment& f, uint64_t index, bool by_primitive, const Scene& scene,
                    const std::vector<MaterialSetup>& mats, TextureType type,
                    const std::string& trace, const std::string& input) {
  const int material = by_primitive ? primitive_material(f, index, scene, trace) : 0;
  check_record_sampler(f, index, mats[static_cast<size_t>(material)], type, input);
  return material;
}

// The report's image, texture and accuracy fields of a finished run.
RunInfo images_info(const RunOptions& opt, const ImageLayout& layout, const RunTextures& textures,
                    const UnitArray& unit, const RunImages& images) {
  RunInfo info;
  info.trace = opt.trace;
  info.width = layout.canvas_w;
  info.height = layout.canvas_h;
  info.textures = textures.names;
  for (int m = 0; m < unit.material_count(); ++m)
    info.material_accuracy.push_back(images.material(m));
  info.frames = images.frames();
  info.image_frame = images.kept_frame();
  info.error_scale_auto = !(opt.error_scale > 0);
  info.error_scale = info.error_scale_auto ? images.kept_accuracy().max_abs : opt.error_scale;
  info.error_bar_rows = colour_bar_rows(layout.canvas_h);
  return info;
}

// A scene with a camera path renders its frames one after another through the fragment
// generator; what builds per-primitive state once for one camera cannot follow it.
void check_scene_frames(const Scene& scene, const UnitArray& units, const ObjectSpaceFrame& os,
                        const SurfaceSetup& surf) {
  if (scene.frames == 1) return;
  const char* what = units.front_stages() > 0 ? "coordinates of their own (coords)"
                     : os.active()            ? "object_space"
                     : surf.active()          ? "relief or lighting"
                                              : nullptr;
  if (what == nullptr) return;
  throw InputError(scene.path, "output.frames = " + std::to_string(scene.frames) +
                                   ": materials with " + what +
                                   " are drawn for one camera only; render one frame (frames = 1)");
}

// The scene's fragments frame after frame (one frame without a camera path). Frame k's maps
// are kept in frame_maps[k] (a camera path), so that every fragment is judged through its own
// frame's projective maps whenever it is recorded; `maps` follow the current frame.
template <class Emit>
void scene_frames(Scene& scene, std::vector<PlaneProjection>& maps,
                  std::vector<std::vector<PlaneProjection>>& frame_maps,
                  const std::vector<MaterialSetup>& mats, std::vector<RasterCounters>& raster,
                  FragmentRouter& router, TruthBatch& batch, Emit&& emit) {
  for (int k = 0; k < scene.frames; ++k) {
    if (k > 0) {
      router.flush();
      batch.flush();
      scene.camera = frame_camera(scene, k);
      for (size_t i = 0; i < maps.size(); ++i)
        maps[i] = PlaneProjection(scene, scene.primitives[i]);
    }
    if (scene.frames > 1) frame_maps.push_back(maps);
    std::vector<RasterCounters> frame_raster;
    generate_fragments(scene, static_cast<uint32_t>(k), emit, &frame_raster, &mats);
    raster.resize(std::max(raster.size(), frame_raster.size()));
    for (size_t m = 0; m < frame_raster.size(); ++m) raster[m] += frame_raster[m];
  }
}

// The run's ground truth: the scene's pixel model; relief and lighting have only the box.
GroundTruth ground_truth(const Scene& scene, const TextureSet& set,
                         const std::vector<MaterialSetup>& mats,
                         const std::vector<PlaneProjection>& maps, const SurfaceSetup& surf,
                         bool none) {
  if (none) {
    return {set, mats, maps, nullptr, nullptr, PixelIntegrator(TruthPixel::Box, {1}), true};
  }
  if (surf.active() && scene.reference_pixel != TruthPixel::Box) {
    throw InputError(scene.path,
                     "[reference] pixel = \"gaussian\" is not available for materials with relief "
                     "or lighting (their reference is box-filtered)");
  }
  return {set,          mats,
          maps,         surf.active() ? &surf.refs : nullptr,
          &surf.frames, PixelIntegrator(scene.reference_pixel, {scene.reference_samples})};
}

// The run's truth cache, when its truth is the exact one and the cache is on (else null):
// the key made of the truth's inputs, and what the cache holds under it.
// trace: the run's trace, if any (its records: the fragments to expect).
std::unique_ptr<TruthMemo> truth_memo(const RunOptions& opt, const Scene& scene,
                                      const GroundTruth& truth, const TextureSet& set,
                                      const std::vector<MaterialSetup>& mats,
                                      const TraceSummary* trace) {
  if (!opt.truth_cache || truth.none || !truth.exact()) return nullptr;
  TruthKeyInputs in;
  in.width = scene.width;
  in.height = scene.height;
  in.cameras.push_back(scene.camera);  // the maps' camera; a path's frames have their own
  for (int k = 0; truth.frame_maps && k < scene.frames; ++k)  // a camera path
    in.cameras.push_back(frame_camera(scene, k));
  in.primitives = &scene.primitives;
  in.textures = &set;
  auto memo = std::make_unique<TruthMemo>();
  for (const MaterialSetup& m : mats) {
    const bool surface = m.relief.has_value() || m.lighting.has_value();
    in.materials.push_back({m.texture, m.address_u(), m.address_v(), surface, m.filter.border,
                            m.footprint ? 0 : m.filter.offset_u,
                            m.footprint ? 0 : m.filter.offset_v});
    // A layered texture's truth reads the fragment's direction or layer, which the key lacks.
    memo->cached.push_back(surface || set[m.texture].layered() ? 0 : 1);
  }
  in.pixel = truth.integrate.pixel();
  in.samples = truth.integrate.sampling().fixed;
  memo->key = truth_key(in);
  memo->cache = std::make_unique<TruthCache>(TruthCacheConfig::from_env(true));
  memo->table = memo->cache->find(memo->key);
  memo->found_in = memo->cache->found_in();
  if (!memo->table && trace) memo->fresh.reserve(trace->records);
  return memo;
}

// The scene's [pipeline] (or the defaults).
PipelineSetup pipeline_setup(const Scene& scene) {
  // Both branches lvalues: a conditional with a temporary would copy the table, and a copied
  // toml table loses the line:column its messages name.
  static const toml::table kNoPipeline;
  return PipelineSetup::from_toml(scene.pipeline ? *scene.pipeline : kNoPipeline, scene.path);
}

// The projective map of each primitive of a scene run (none for a trace alone).
std::vector<PlaneProjection> plane_maps(const Scene& scene, bool use_scene) {
  std::vector<PlaneProjection> maps;
  if (!use_scene) return maps;
  maps.reserve(scene.primitives.size());
  for (const auto& p : scene.primitives) maps.emplace_back(scene, p);
  return maps;
}

// Several units: each unit's timeline tracks, observed as each fragment leaves its unit.
// The timeline's tracks: every unit's stages (several units: at each commit), and the memory
// levels behind the L1s.
// Several units record through `record`; on a camera path put back in frame order (returned).
std::unique_ptr<FrameOrder> set_unit_record(UnitArray& units, bool camera_path,
                                            const UnitArray::Record& record) {
  if (!units.several()) return nullptr;
  std::unique_ptr<FrameOrder> order;
  if (camera_path) order = std::make_unique<FrameOrder>(record);
  units.set_record(order ? order->recorder() : record);
  return order;
}

void observe_units(StageTimeline* timeline, UnitArray& units) {
  if (!timeline) return;
  std::vector<int> tracks;
  for (const std::string& level : units.memory().levels())
    tracks.push_back(timeline->memory_track(level));
  units.memory().observe([timeline, tracks](int level, uint64_t now, uint64_t ready, int) {
    timeline->observe_request(tracks[static_cast<size_t>(level)], now, ready);
  });
  if (!units.several()) return;
  units.set_commit_observer(
      [timeline](int u, const ClockedPipeline& p) { timeline->observe(p, u); });
}

// A trace run's first pass, the digest of its file (computed meanwhile) and its reader; all
// empty without a trace.
struct TraceInput {
  std::unique_ptr<TraceSummary> summary;
  std::future<InputDigest> digest;
  std::unique_ptr<TraceReader> reader;
};
TraceInput open_trace(const RunOptions& opt) {
  TraceInput t;
  if (opt.trace.empty()) return t;
  t.digest = trace_digest(opt);  // hashed beside the first pass (with more than one thread)
  t.summary = std::make_unique<TraceSummary>(first_pass(opt));
  t.reader = std::make_unique<TraceReader>(opt.trace);
  return t;
}

}  // namespace

Scene load_run_scene(const RunOptions& opt) {
  if (!opt.scene_text.empty()) {
    const std::string name = opt.scene.empty() ? "<scene text>" : opt.scene;
    return parse_scene(opt.scene_text, name, "", opt.overrides);
  }
  return (opt.scene.empty() || opt.scene == "default") ? default_scene(opt.overrides)
                                                       : load_scene(opt.scene, opt.overrides);
}

namespace {

// --board virtual|hid: the fixed-arithmetic materials' fragments go to the RTL sampler on a
// board (null without --board).
std::unique_ptr<BoardSampler> attach_board(const std::string& link, UnitArray& units,
                                           std::ostream& log) {
  if (link.empty()) return nullptr;
  auto board = std::make_unique<BoardSampler>(link, units);
  units.set_fixed_board(board.get());
  log << "board (" << link << "): texsim_sampler runs the fixed-arithmetic materials";
  for (const std::string& m : board->materials()) log << " " << m;
  log << " (up to " << board->fragments_per_stream() << " fragments per STREAM)\n";
  return board;
}

void board_info(BoardSampler& board, RunInfo& info, std::ostream& log) {
  board.finish();
  info.board_link = board.link();
  info.board_blocks = board.blocks();
  info.board_fragments = board.fragments();
  info.board_streams = board.streams();
  info.board_lerps = board.lerps();
  log << "board (" << info.board_link << "): texsim_sampler sampled " << info.board_fragments
      << " fragments in " << info.board_streams << " STREAMs";
  if (info.board_lerps > 0)
    log << "; bilinear_lerp ran their " << info.board_lerps << " lerps, each equal to BilinearLerp";
  log << "\n";
}

// Hands the run to opt.capture and runs the error ledger if asked; false: a capture that writes
// no outputs (the caller returns).
bool capture_and_ledger(const RunOptions& opt, const RunImages& images, const UnitArray& units,
                        const RunSummary& sum, const std::vector<BlockUse>& raster_blocks,
                        RunInfo& info, LedgerRun& ledger, std::ostream& log) {
  if (opt.capture) {
    const bool write = opt.capture->write_outputs;
    *opt.capture = capture_run(images, units, sum);
    opt.capture->write_outputs = write;
    opt.capture->raster_blocks = raster_blocks;
    opt.capture->board_fragments = info.board_fragments;
    opt.capture->board_streams = info.board_streams;
    opt.capture->board_lerps = info.board_lerps;
    if (!write) return false;
  }
  if (opt.ledger) {
    RunCapture hw = capture_run(images, units, sum);
    hw.raster_blocks = raster_blocks;
    ledger = run_error_ledger(opt, hw, log);
    info.ledger = ledger.ledger;
  }
  return true;
}

}  // namespace

RunSummary run_simulation(const RunOptions& opt, std::ostream& log) {
  ensure_dir(opt.out);  // an unwritable --out is found before the run, not after it
  // Scene: a file, the built-in default, or (trace only) none.
  const bool use_scene = !opt.scene.empty() || !opt.scene_text.empty() || opt.trace.empty();
  set_scene_memory_limit(opt.max_memory);  // meshes and DEMs are refused before allocation
  set_astcenc_threads(resolve_threads(opt.threads));  // encoding at load uses --threads too
  Scene scene = load_run_scene(opt);
  TraceInput trace = open_trace(opt);
  std::unique_ptr<TraceSummary>& trace_sum = trace.summary;
  std::unique_ptr<TraceReader>& reader = trace.reader;
  RunTextures textures =
      reader ? load_trace_textures(*reader, opt.trace) : load_scene_textures(scene);
  const std::vector<MaterialSetup> mats =
      run_materials(scene, use_scene, textures, opt.trace,
                    reader ? reader->header().samplers : std::vector<TraceSampler>{}, log);
  const PipelineSetup setup = pipeline_setup(scene);
  std::vector<PlaneProjection> maps = plane_maps(scene, use_scene);
  const ImageLayout layout = run_layout(opt, scene, use_scene, trace_sum.get(), maps, textures.set);
  refuse_quad_derivatives_with_coords(setup, mats, scene.path);
  UnitArray units(textures.set, mats, setup, scene.tech, !opt.functional, UnitArray::kWindow,
                  opt.capture && opt.capture->whole_fragments);
  TextureUnit& unit = units.unit(0);
  const std::unique_ptr<BoardSampler> board = attach_board(opt.board, units, log);
  WorkloadStats workload(workload_textures(textures.set));  // placed by the units: their addresses
  WorkloadFeed workload_feed(workload, opt.workload && resolve_threads(opt.threads) > 1);
  // Materials with `object_space`: drawn first, their pixels then take the resolved colours.
  ObjectSpaceFrame os =
      object_space_frame(scene, use_scene && !reader, textures.set, mats, setup, log);
  const SurfaceSetup surf = surface_setup(scene, mats, textures.set);
  if (surf.active()) units.set_surfaces(surf.frames);
  GroundTruth truth = ground_truth(scene, textures.set, mats, maps, surf, opt.reference == "none");
  const bool camera_path = use_scene && !reader && scene.frames > 1;
  std::vector<std::vector<PlaneProjection>> frame_maps;  // a camera path's, by frame
  if (camera_path) truth.frame_maps = &frame_maps;
  RunImages images(layout.extent, layout.canvas_w, layout.canvas_h, scene.background,
                   unit.material_count(), opt.frame);
  Progress progress(opt.progress);
  const std::string& input = opt.trace.empty() ? scene.path : opt.trace;
  // Fragments are processed as they stream in. f: as given; g: texture id of the loaded texture.
  TruthBatch batch(truth, images, progress, input, opt.threads,
                   truth_memo(opt, scene, truth, textures.set, mats, trace_sum.get()));
  const std::unique_ptr<StageTimeline> timeline = make_timeline(opt, units);
  // With a coordinate front end the workload is what leaves it (and reaches the units).
  const bool front_workload = opt.workload && !reader && unit.front_stages() > 0;
  auto record = [&](const Fragment& f, const Fragment& g, int material, const Rgba* colour,
                    uint64_t index) {
    if (timeline && !units.several()) timeline->observe(*unit.pipeline());
    batch.add(f, g, material, colour, index);
  };
  observe_units(timeline.get(), units);
  const std::unique_ptr<FrameOrder> order = set_unit_record(units, camera_path, record);
  // The unit's timeline observes the pipeline after every fragment: no batching then.
  FragmentRouter router(units, setup, os, record, timeline != nullptr);
  auto handle = [&](const Fragment& f, uint64_t index) {
    Fragment g = f;
    g.tex = loaded_texture(f, index, textures, input, opt.trace);
    const int material =
        record_material(f, index, truth.exact(), scene, mats,
                        textures.set[static_cast<int>(g.tex)].shape().type, opt.trace, input);
    // The screen-space texture unit's stream (materials drawn object-space are not in it).
    if (opt.workload && !os.drawn_by(material)) workload_feed.add(f, g.tex);
    if (order) order->emitted(f.frame);
    router.add(f, g, material, index);
  };
  uint64_t index = 0;
  std::vector<RasterCounters> raster;
  if (!reader) check_scene_frames(scene, units, os, surf);
  if (reader) {
    stream_trace(*reader, opt.threads, [&](const Fragment& f) { handle(f, index++); });
  } else if (unit.front_stages() > 0) {
    draw_front_end(scene, maps, units, textures, record, index,
                   front_workload ? &workload : nullptr);
  } else {
    scene_frames(scene, maps, frame_maps, mats, raster, router, batch,
                 [&](const Fragment& f) { handle(f, index++); });
  }
  router.flush();
  units.finish();
  if (order) order->check_drained();
  batch.finish(log);
  images.finish();
  if (images.count() == 0) throw InputError(input, "no fragments to render");
  if (!images.has_kept_frame()) {
    throw InputError(input, "--frame " + std::to_string(opt.frame) + ": no fragment of that frame");
  }

  units.check_timing_invariants();
  RunSummary sum;
  sum.fragments = units.fragments();
  sum.cycles = units.cycles();
  sum.accuracy = images.total();
  RunInfo info = images_info(opt, layout, textures, units, images);
  if (board) board_info(*board, info, log);
  workload_feed.finish();  // and the stats (its last batches ran beside the last truths)
  if (opt.workload) info.workload = &workload;
  info.scene = use_scene ? scene.path : "(none: trace only)";
  info.reference = reference_text(truth, batch.mean_samples(), info.frames.size(), surf.active(),
                                  mats, scene.reference_relief_per_sample);
  info.reference_pixel = to_string(scene.reference_pixel);
  info.has_truth = opt.reference != "none";
  if (use_scene && !reader) info.subsystems = scene_subsystems(scene, maps, mats, raster);
  finish_object_space(os, units.cycles(), raster, sum, info);
  quad_info(info, setup, router.quads(), units);
  info.provenance =
      run_provenance(opt, use_scene ? scene.path : "", textures, setup, scene.tech, trace.digest);
  info.provenance.energy = scene.energy;
  LedgerRun ledger;
  if (!capture_and_ledger(opt, images, units, sum, raster_coord_blocks(mats, raster), info, ledger,
                          log))
    return sum;
  if (timeline) timeline->write(opt.timeline);  // first: a bad path leaves no report
  write_run_outputs(opt, info, images, units, sum, ledger, log);
  if (timeline) log << "  timeline: " << opt.timeline << timeline->summary() << "\n";
  return sum;
}
uint64_t generate_scene_trace(const std::string& scene_path, const std::string& out_path,
                              const std::vector<std::string>& overrides) {
  Scene scene = scene_path.empty() ? default_scene(overrides) : load_scene(scene_path, overrides);
  TraceHeader h;
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture t = load_scene_texture(scene, i);
    std::string src = scene.textures[i].source;
    // Paths in the trace are absolute so the trace can be moved away from the scene (a layered
    // texture's, slice by slice).
    const auto absolute = [&](const std::string& p) {
      return is_procedural_source(p)
                 ? p
                 : std::filesystem::absolute(resolve_texture_path(p, scene.base_dir)).string();
    };
    if (is_layered_source(src)) {
      LayeredSource ls = parse_layered_source(src, scene.textures[i].where);
      for (auto& slice : ls.slices) slice = absolute(slice);
      src = layered_source(ls);
    } else {
      src = absolute(src);
    }
    // The storage too (version 3): a run of the trace converts or encodes it as the scene does.
    h.textures.push_back({static_cast<uint32_t>(i), scene.textures[i].name, src,
                          static_cast<uint32_t>(t.width(0)), static_cast<uint32_t>(t.height(0)),
                          texture_storage_spec(scene.textures[i])});
  }
  // Relief and lighting need the view vector: their scenes' traces carry it (version 2).
  const std::vector<MaterialSetup> mats = build_materials(scene);  // checks the effects too
  h.has_view = std::any_of(mats.begin(), mats.end(),
                           [](const MaterialSetup& m) { return m.relief || m.lighting; });
  // Layered textures' fragments carry a direction (w) or a layer, and a material's operation
  // its fields: the version-4 fields.
  h.has_ops = std::any_of(mats.begin(), mats.end(), [](const MaterialSetup& m) {
    return m.lookup.has_value() || m.operation.has_value();
  });
  // The scene's [samplers] (version 5): a record's sampler id means the same without the scene.
  if (const auto table = build_samplers(scene)) {
    for (const SamplerSetup& s : *table) h.samplers.push_back(to_trace_sampler(s));
  }
  // A camera path: one frame after another, each with its own camera (and view vectors).
  return write_trace(out_path, h, [&](auto& w) {
    for (int k = 0; k < scene.frames; ++k) {
      scene.camera = frame_camera(scene, k);
      std::vector<SurfaceFrame> frames;
      if (h.has_view) {
        for (const auto& p : scene.primitives) frames.emplace_back(scene, p);
      }
      generate_fragments(scene, static_cast<uint32_t>(k), [&](const Fragment& f) {
        if (!h.has_view) return w.write(f);
        const SurfaceFrame& sf = frames[f.prim];
        const glm::dvec3 v = sf.to_tangent(sf.view(f.x + 0.5, f.y + 0.5));
        Fragment g = f;
        g.view_x = static_cast<float>(v.x);
        g.view_y = static_cast<float>(v.y);
        g.view_z = static_cast<float>(v.z);
        w.write(g);
      });
    }
  });
}

}  // namespace texsim
