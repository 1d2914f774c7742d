#include "pipeline/texture/texture_unit.h"

#include <algorithm>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"

namespace texsim {

namespace {
enum Stage { kLod, kAddress, kCache, kBlend, kStages };
constexpr int kMaxFront =
    2;  // coordinate and derivative stages (a constant bound for the compiler)
// The kernels' kFront for a timed unit with relief or lighting stages: stages by index.
constexpr int kAnyStages = 1000;
}  // namespace

TextureUnit::TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
                         const PipelineSetup& setup, const TechTable& tech, bool timing)
    : TextureUnit(textures, std::move(materials), setup, tech, timing,
                  std::make_unique<MemorySystem>(setup, 1), nullptr, 0) {}

TextureUnit::TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
                         const PipelineSetup& setup, const TechTable& tech, MemorySystem& memory,
                         int unit)
    : TextureUnit(textures, std::move(materials), setup, tech, true, nullptr, &memory, unit) {}

TextureUnit::~TextureUnit() = default;

TextureUnit::TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
                         const PipelineSetup& setup, const TechTable& tech, bool timing,
                         std::unique_ptr<MemorySystem> own, MemorySystem* shared, int unit)
    : textures_(textures),
      mats_(std::move(materials)),
      setup_(setup),
      tech_(tech),
      timing_(timing),
      blend_(setup.blend),
      own_memory_(std::move(own)),
      mem_(shared ? shared : own_memory_.get()),
      cache_(mem_->l1(unit)),
      next_(&mem_->behind_l1()),
      unit_(unit),
      quad_merge_(setup.quad_merge),
      defer_(shared != nullptr) {
  if (mats_.empty()) throw std::invalid_argument("texture unit: no materials");
  textures_.place(setup.layout);
  for (const auto& m : mats_) {
    Path p;
    p.lod = LodUnit(m.lod);
    p.addr = TexelAddressGen(m.filter);
    p.footprint = m.footprint.get();
    p.coords = m.coords.get();
    if (p.coords) {
      p.front_count = p.coords->has_derivs() ? 2 : 1;
      front_ = std::max(front_, p.front_count);
    }
    if (m.relief) {
      if (m.relief->height_tex < 0 || m.relief->height_tex >= textures_.size())
        throw std::invalid_argument("texture unit: material '" + m.name +
                                    "': relief height texture is not bound");
      p.relief_height = &textures_[m.relief->height_tex];
      p.relief_colour = &textures_[m.texture];
      // Each distance map in a region of its own, far above the textures.
      p.volume_base = (uint64_t{1} << 40) + (static_cast<uint64_t>(reliefs_.size()) << 32);
      reliefs_.push_back(
          std::make_unique<ReliefEffect>(*m.relief, *p.relief_height, p.relief_colour));
      p.relief = reliefs_.back().get();
      p.relief_step_ii = p.relief->timing(tech_).ii;
      if (p.relief->has_visibility_filter())
        p.vis_ii = std::max<uint32_t>(1, p.relief->visibility_filter().timing(tech_).ii);
    }
    if (m.lighting) {
      const int nt = m.lighting->normal_tex;
      if (m.lighting->normal != LightingSetup::Normal::Flat && (nt < 0 || nt >= textures_.size()))
        throw std::invalid_argument("texture unit: material '" + m.name +
                                    "': lighting normal texture is not bound");
      lightings_.push_back(
          std::make_unique<LightingEffect>(*m.lighting, nt >= 0 ? &textures_[nt] : nullptr));
      p.lighting = lightings_.back().get();
      p.light_extra_ii = p.lighting->timing(tech_).ii - 1;
    }
    const uint32_t tpc = setup.cache.texels_per_cycle;
    for (int n = 1; n <= 16; ++n) {
      FilterTaps t;
      t.count = n * p.addr.taps_per_probe();
      p.blend_extra_ii[n] = blend_.issue_cycles(t) - 1;
      p.cache_extra_ii[n] = (static_cast<uint32_t>(t.count) + tpc - 1) / tpc - 1;
    }
    paths_.push_back(p);
  }
  // Relief and lighting stages exist only when some material uses them.
  const bool any_relief =
      std::any_of(paths_.begin(), paths_.end(), [](const Path& p) { return p.relief; });
  const bool any_light =
      std::any_of(paths_.begin(), paths_.end(), [](const Path& p) { return p.lighting; });
  relief_stage_ = any_relief ? front_ : -1;
  base_ = front_ + (any_relief ? 1 : 0);
  light_stage_ = any_light ? base_ + kStages : -1;
  if (timing_) {
    // One stage per hardware unit; a unit serving several materials is sized for the slowest.
    TimingSpec lod_t{}, addr_t{};
    for (const auto& p : paths_) {
      const TimingSpec l = p.lod.timing(tech_);
      const TimingSpec a = p.footprint ? p.footprint->timing(tech_)
                           : p.relief && p.relief->has_visibility_filter()
                               ? p.relief->visibility_filter().timing(tech_)
                               : p.addr.timing(tech_);
      lod_t.latency = std::max(lod_t.latency, l.latency);
      addr_t.latency = std::max(addr_t.latency, a.latency);
    }
    TimingSpec cache_t;
    cache_t.latency = setup.cache.hit_latency;
    std::vector<StageConfig> st(static_cast<size_t>(base_ + kStages + (any_light ? 1 : 0)));
    // Front end: one stage per coordinate-unit stage, sized for the slowest and widest unit;
    // each unit's own throughput comes back through front_extra (per-fragment issue cycles).
    static const char* const front_names[2] = {"coords", "derivs"};
    for (int s = 0; s < front_; ++s) {
      TimingSpec t{};
      for (const auto& p : paths_) {
        if (p.front_count <= s) continue;
        const TimingSpec u = p.coords->stages(tech_)[static_cast<size_t>(s)].timing;
        t.latency = std::max(t.latency, u.latency);
        t.lanes = std::max(t.lanes, u.lanes);
      }
      t.ii = 1;
      for (auto& p : paths_) {
        if (p.front_count <= s) continue;
        const TimingSpec u = p.coords->stages(tech_)[static_cast<size_t>(s)].timing;
        p.front_extra[s] = (u.ii * t.lanes + u.lanes - 1) / u.lanes - 1;
      }
      st[static_cast<size_t>(s)] = {front_names[s], t, setup.fifo_depth, 0};
    }
    const auto at = [&](int stage) -> StageConfig& {
      return st[static_cast<size_t>(base_) + static_cast<size_t>(stage)];
    };
    // Relief: a loop issuing one step per step ii; lighting: normal unit then shader. Both
    // sized for the slowest material (issue cycles per fragment come per item).
    TimingSpec relief_t{}, light_t{};
    for (const auto& p : paths_) {
      if (p.relief) relief_t.latency = std::max(relief_t.latency, p.relief->timing(tech_).latency);
      if (p.lighting)
        light_t.latency = std::max(light_t.latency, p.lighting->timing(tech_).latency);
    }
    if (any_relief)
      st[static_cast<size_t>(relief_stage_)] = {"relief", relief_t, setup.fifo_depth, 0};
    if (any_light)
      st[static_cast<size_t>(light_stage_)] = {"lighting", light_t, setup.fifo_depth, 0};
    at(kLod) = {"lod", lod_t, setup.fifo_depth, 0};
    at(kAddress) = {"address", addr_t, setup.fifo_depth, 0};
    at(kCache) = {"cache", cache_t, setup.fifo_depth, setup.cache.miss_queue};
    at(kBlend) = {"blend", blend_.timing(tech_), setup.fifo_depth, 0};
    pipe_ = std::make_unique<ClockedPipeline>(std::move(st));
    defer_costs_.resize(static_cast<size_t>(pipe_->stage_count()));
  }
  for (size_t m = 0; m < paths_.size(); ++m) {
    paths_[m].kernel = choose_kernel(paths_[m]);
    choose_batch(paths_[m], mats_[m]);
  }
}

void TextureUnit::choose_batch(Path& p, const MaterialSetup& m) {
  // The batched datapath: a plain bilinear or trilinear material, on a unit without
  // front-end, relief or lighting stages.
  const FilterMode filter = p.addr.config().filter;
  const bool plain = !p.footprint && !p.coords && !p.relief && !p.lighting &&
                     filter != FilterMode::Nearest &&
                     blend_.quads_in_one_group(filter == FilterMode::Trilinear ? 2 : 1);
  if (!plain || front_ != 0 || relief_stage_ >= 0 || light_stage_ >= 0 || defer_) return;
  p.batch = std::make_shared<LinearBatchSampler>(m.lod, m.filter);
  p.batch_kernel = pipe_ ? pick_batch_kernel<0>(filter, textures_.layout())
                         : pick_batch_kernel<-1>(filter, textures_.layout());
  if (!batch_out_) batch_out_ = std::make_unique<LinearBatch>();
}

namespace {

// Adds `line` to lines[0 .. n) unless present (order of first use kept).
inline void add_line(uint64_t line, uint64_t* lines, int& n) {
  int k = 0;
  while (k < n && lines[k] != line) ++k;
  if (k == n) lines[n++] = line;
}

// Distinct cache lines of a fragment's taps, in order of first use, under layout L (a
// template argument, so the address arithmetic has no layout switch per texel). A linear
// filter's taps come in 2x2 quads (x0,y0) (x1,y0) (x0,y1) (x1,y1) on one level: their
// addresses are level base + row part + column part, two of each per quad.
template <TexelLayout L>
int distinct_lines(const FilterTaps& taps, const Texture& tex, uint32_t shift, uint64_t* lines) {
  const auto bpt = static_cast<uint64_t>(tex.bytes_per_texel());
  int n = 0;
  int i = 0;
  for (; i + 4 <= taps.count; i += 4) {
    const TexelTap* q = &taps.tap[static_cast<size_t>(i)];
    const bool quad = q[1].level == q[0].level && q[2].level == q[0].level &&
                      q[3].level == q[0].level && q[1].y == q[0].y && q[2].x == q[0].x &&
                      q[3].x == q[1].x && q[3].y == q[2].y;
    if (!quad) break;
    const Texture::Level& lv = tex.level(q[0].level);
    const uint64_t base = tex.base() + lv.offset;
    const uint64_t r0 = Texture::row_index(L, lv, q[0].y), r1 = Texture::row_index(L, lv, q[2].y);
    const uint64_t c0 = Texture::col_index(L, q[0].x), c1 = Texture::col_index(L, q[1].x);
    const uint64_t l00 = (base + (r0 + c0) * bpt) >> shift, l10 = (base + (r0 + c1) * bpt) >> shift;
    const uint64_t l01 = (base + (r1 + c0) * bpt) >> shift, l11 = (base + (r1 + c1) * bpt) >> shift;
    if (n == 0) {
      // First quad: its distinct lines without a search.
      lines[n++] = l00;
      if (l10 != l00) lines[n++] = l10;
      if (l01 != l00 && l01 != l10) lines[n++] = l01;
      if (l11 != l00 && l11 != l10 && l11 != l01) lines[n++] = l11;
    } else {
      add_line(l00, lines, n);
      add_line(l10, lines, n);
      add_line(l01, lines, n);
      add_line(l11, lines, n);
    }
  }
  for (; i < taps.count; ++i) {  // nearest taps, or anything not in quads
    const TexelTap& t = taps.tap[static_cast<size_t>(i)];
    const Texture::Level& lv = tex.level(t.level);
    add_line((tex.base() + lv.offset + Texture::texel_index(L, lv, t.x, t.y) * bpt) >> shift, lines,
             n);
  }
  return n;
}

}  // namespace

uint64_t TextureUnit::access_lines(const uint64_t* lines, int n, uint64_t texels, uint64_t start) {
  if (recording_) {
    // Two-step timing: the look-ups are made at commit(), at the cycle the scheduler allows.
    rec_groups_.push_back({rec_lines_.size(), static_cast<size_t>(n), texels});
    rec_lines_.insert(rec_lines_.end(), lines, lines + n);
    return 0;
  }
  if (quad_merge_) return access_quad_lines(lines, n, texels, start);
  const uint64_t hit_ready = start + setup_.cache.hit_latency;
  uint64_t ready = hit_ready;
  const uint32_t line_bytes = setup_.cache.line_bytes;
  const uint32_t shift = cache_.line_shift();
  for (int k = 0; k < n; ++k) {
    if (!cache_.access_line(lines[k]))
      ready = std::max(ready, next_->read_line(start, lines[k] << shift, line_bytes, unit_));
  }
  cache_.count_texels(texels);
  return ready - hit_ready;
}

uint64_t TextureUnit::access_quad_lines(const uint64_t* lines, int n, uint64_t texels,
                                        uint64_t start) {
  const uint64_t hit_ready = start + setup_.cache.hit_latency;
  uint64_t ready = hit_ready;
  for (int k = 0; k < n; ++k) {
    const auto it = std::find_if(quad_lines_.begin(), quad_lines_.end(),
                                 [&](const auto& e) { return e.first == lines[k]; });
    if (it != quad_lines_.end()) {
      // The quad's earlier lane looked it up: its data comes with that read (or its fill).
      ++quad_merged_;
      ready = std::max(ready, it->second);
      continue;
    }
    uint64_t r = hit_ready;
    if (!cache_.access_line(lines[k])) {
      r = std::max(r, next_->read_line(start, lines[k] << cache_.line_shift(),
                                       setup_.cache.line_bytes, unit_));
    }
    quad_lines_.emplace_back(lines[k], r);
    ready = std::max(ready, r);
  }
  cache_.count_texels(texels);
  return ready - hit_ready;
}

void TextureUnit::note_quad(const Fragment& f) {
  const uint32_t lane = 1u << ((f.x & 1) | (f.y & 1) << 1);
  const bool same = quad_open_ && f.frame == quad_frame_ && f.prim == quad_prim_ &&
                    f.x >> 1 == quad_x_ && f.y >> 1 == quad_y_ && (quad_mask_ & lane) == 0;
  if (!same) {
    // Every unit commits a fragment before it takes the next, so the quad's look-ups are done.
    quad_lines_.clear();
    quad_open_ = true;
    quad_frame_ = f.frame;
    quad_prim_ = f.prim;
    quad_x_ = f.x >> 1;
    quad_y_ = f.y >> 1;
    quad_mask_ = 0;
  }
  quad_mask_ |= lane;
}

uint64_t TextureUnit::cache_lookups(const FilterTaps& taps, const Texture& tex, uint64_t start) {
  // Each distinct line of the fragment's taps is one tag look-up.
  const uint32_t shift = cache_.line_shift();
  uint64_t lines[128];
  int n = 0;
  switch (tex.layout()) {
    case TexelLayout::Linear:
      n = distinct_lines<TexelLayout::Linear>(taps, tex, shift, lines);
      break;
    case TexelLayout::Tiled4x4:
      n = distinct_lines<TexelLayout::Tiled4x4>(taps, tex, shift, lines);
      break;
    case TexelLayout::Morton:
      n = distinct_lines<TexelLayout::Morton>(taps, tex, shift, lines);
      break;
  }
  return access_lines(lines, n, static_cast<uint64_t>(taps.count), start);
}

template <TexelLayout L>
uint64_t TextureUnit::cache_lookups(const TexelQuad* q, int n, const Texture& tex, uint64_t start) {
  // The lines distinct_lines() finds for the quads' taps, in the same order.
  const uint32_t shift = cache_.line_shift();
  const auto bpt = static_cast<uint64_t>(tex.bytes_per_texel());
  uint64_t lines[8];
  int k = 0;
  for (int j = 0; j < n; ++j) {
    const Texture::Level& lv = tex.level(q[j].level);
    const uint64_t base = tex.base() + lv.offset;
    const uint64_t r0 = Texture::row_index(L, lv, q[j].y0), r1 = Texture::row_index(L, lv, q[j].y1);
    const uint64_t c0 = Texture::col_index(L, q[j].x0), c1 = Texture::col_index(L, q[j].x1);
    const uint64_t l00 = (base + (r0 + c0) * bpt) >> shift, l10 = (base + (r0 + c1) * bpt) >> shift;
    const uint64_t l01 = (base + (r1 + c0) * bpt) >> shift, l11 = (base + (r1 + c1) * bpt) >> shift;
    if (j == 0) {
      lines[k++] = l00;
      if (l10 != l00) lines[k++] = l10;
      if (l01 != l00 && l01 != l10) lines[k++] = l01;
      if (l11 != l00 && l11 != l10 && l11 != l01) lines[k++] = l11;
    } else {
      add_line(l00, lines, k);
      add_line(l10, lines, k);
      add_line(l01, lines, k);
      add_line(l11, lines, k);
    }
  }
  return access_lines(lines, k, 4 * static_cast<uint64_t>(n), start);
}

void TextureUnit::new_frame(const Fragment& f) {
  if (!frames_.empty() && pipe_) frames_.back().cycles = pipe_->cycles();
  frames_.push_back({f.frame, 0, 0});
}

uint64_t TextureUnit::cache_lookups(const std::vector<TexelRef>& texels, const Texture& tex,
                                    uint64_t start) {
  lines_.clear();
  for (const TexelRef& t : texels) lines_.push_back(cache_.line_of(tex.address(t.level, t.x, t.y)));
  std::sort(lines_.begin(), lines_.end());
  lines_.erase(std::unique(lines_.begin(), lines_.end()), lines_.end());
  return access_lines(lines_.data(), static_cast<int>(lines_.size()), texels.size(), start);
}

// A footprint filter is one block that scans, weights and accumulates: it occupies the address
// stage for its issue cycles, its texels go through the cache, and the blend stage normalises.
Rgba TextureUnit::process_footprint(const Fragment& f, Path& p, const Texture& tex,
                                    const ItemCost* front) {
  fetched_.clear();
  const FilterOutput out = p.footprint->filter(tex, f, &fetched_, p.footprint_ops);
  ++p.fragments;
  p.footprint_texels += fetched_.size();
  count_frame(f);
  if (pipe_) {
    const auto n = static_cast<uint32_t>(fetched_.size());
    const uint32_t tpc = setup_.cache.texels_per_cycle;
    const uint32_t scan = p.footprint->issue_cycles(out.stats);
    const int addr = base_ + kAddress, cache = base_ + kCache;
    issue_any([&](int s, uint64_t start) {
      if (s < kMaxFront && s < front_) return front_cost(p, front, s);
      ItemCost c;
      add_effect_costs(s, c);
      if (s == addr) c.extra_ii = scan > 0 ? scan - 1 : 0;
      if (s == cache) {
        c.extra_ii = n > 0 ? (n + tpc - 1) / tpc - 1 : 0;
        const uint64_t relief_wait = relief_lookups(start);
        c.extra_latency = std::max(relief_wait, cache_lookups(fetched_, tex, start));
      }
      return c;
    });
  }
  return out.colour;
}

void TextureUnit::generate_coords(int material, const CoordTriangle& tri,
                                  std::vector<CoordUnitFragment>& out,
                                  std::vector<ItemCost>& costs) {
  Path& p = paths_[static_cast<size_t>(material)];
  if (!p.coords) throw std::logic_error("generate_coords: material has no coordinate unit");
  const size_t before = out.size();
  p.coords->generate(tri, tech_, out, costs, p.coord_ops, p.deriv_ops);
  front_stats_.generated += out.size() - before;
}

void TextureUnit::drop(int material, const ItemCost* front, bool rejected) {
  const Path& p = paths_[static_cast<size_t>(material)];
  ++(rejected ? front_stats_.rejected : front_stats_.occluded);
  if (!pipe_ || !front) return;
  for (int s = 0; s < p.front_count; ++s)
    pending_front_[s] += 1 + p.front_extra[s] + front[s].extra_ii;
}

Rgba TextureUnit::process(const Fragment& f, int material, const ItemCost* front) {
  Path& p = paths_[static_cast<size_t>(material)];
  if (p.relief || p.lighting) return process_surface(f, p, material, front);
  return filter_fragment(f, p, front);
}

void TextureUnit::process_batch(const Fragment* f, size_t n, int material, Rgba* out) {
  Path& p = paths_[static_cast<size_t>(material)];
  if (!p.batch_kernel) {
    for (size_t i = 0; i < n; ++i) out[i] = process(f[i], material);
    return;
  }
  // Batches of at most LinearBatch::kMax on the texture of their first fragment; a fragment
  // on another texture goes through the scalar kernel with its own.
  for (size_t i = 0; i < n; i += LinearBatch::kMax) {
    const size_t m = std::min(LinearBatch::kMax, n - i);
    const uint32_t t = f[i].tex;
    if (t >= static_cast<uint32_t>(textures_.size()))
      filter_fragment(f[i], p, nullptr);  // throws, naming the texture
    (this->*p.batch_kernel)(f + i, m, p, textures_[static_cast<int>(t)], out + i);
  }
}

Rgba TextureUnit::process_surface(const Fragment& f, Path& p, int material, const ItemCost* front) {
  if (f.prim >= surfaces_.size()) {
    throw std::invalid_argument(
        "texture unit: material '" + mats_[static_cast<size_t>(material)].name +
        "' has relief or lighting, which needs the plane of its primitive (a scene run); "
        "primitive " +
        std::to_string(f.prim) + " is not known");
  }
  const SurfaceFrame& sf = surfaces_[f.prim];
  // The eye direction in the primitive's tangent frame: the fragment's own (a version-2 trace
  // carries it), else through the pixel's centre from the scene's camera.
  const glm::dvec3 view_ts = f.has_view() ? glm::normalize(glm::dvec3(f.view_x, f.view_y, f.view_z))
                                          : sf.to_tangent(sf.view(f.x + 0.5, f.y + 0.5));
  Fragment g = f;
  cur_relief_ii_ = 0;
  cur_relief_texels_ = 0;
  if (p.relief) {
    relief_reads_.clear();
    const ReliefEffect::Shift sh = p.relief->shift(f.u, f.v, view_ts, sf.u_length(), sf.v_length(),
                                                   p.relief_ops, pipe_ ? &relief_reads_ : nullptr);
    g.u = sh.u;
    g.v = sh.v;
    p.relief_steps += sh.steps;
    p.relief_fetches += sh.fetches;
    cur_relief_ii_ = sh.steps > 0 ? sh.steps * p.relief_step_ii - 1 : 0;
    if (pipe_ && !relief_reads_.empty()) {
      relief_lines(p, relief_reads_, relief_lines_);
      cur_relief_texels_ = relief_reads_.size();
    }
  }
  cur_light_ii_ = p.lighting ? p.light_extra_ii : 0;
  Rgba c = p.relief && p.relief->has_visibility_filter() ? process_visible(g, p, view_ts, sf, front)
                                                         : filter_fragment(g, p, front);
  cur_relief_ii_ = cur_light_ii_ = 0;
  cur_relief_texels_ = 0;
  if (p.lighting) {
    const glm::dvec3 light_ts = sf.to_tangent(p.lighting->setup().light_dir);
    c = p.lighting->shade(c, g.u, g.v, view_ts, light_ts, p.normal_ops, p.shader_ops);
  }
  return c;
}

void TextureUnit::relief_lines(const Path& p, const std::vector<ReliefRead>& reads,
                               std::vector<uint64_t>& lines) const {
  lines.clear();
  const Texture& h = *p.relief_height;
  const Texture& c = *p.relief_colour;
  const ReliefHeightMap& hm = p.relief->height_map();
  const DistanceMap& dm = p.relief->distance_map();
  for (const ReliefRead& r : reads) {
    uint64_t addr = 0;
    if (r.z == ReliefRead::kHeightRead) {
      addr = h.address(0, r.x, r.y);
    } else if (r.z == ReliefRead::kColourRead) {
      // The filter's colour grid is the height map's: texel (x, y) is the colour texel it
      // was resampled from.
      addr = c.address(0, static_cast<int>(int64_t{r.x} * c.width(0) / hm.width),
                       static_cast<int>(int64_t{r.y} * c.height(0) / hm.height));
    } else {
      addr = p.volume_base + dm.index(r.x, r.y, r.z);
    }
    lines.push_back(cache_.line_of(addr));
  }
  std::sort(lines.begin(), lines.end());
  lines.erase(std::unique(lines.begin(), lines.end()), lines.end());
}

uint64_t TextureUnit::relief_lookups(uint64_t start) {
  if (cur_relief_texels_ == 0) return 0;
  return access_lines(relief_lines_.data(), static_cast<int>(relief_lines_.size()),
                      cur_relief_texels_, start);
}

Rgba TextureUnit::process_visible(const Fragment& g, Path& p, const glm::dvec3& view_ts,
                                  const SurfaceFrame& sf, const ItemCost* front) {
  fetched_reads_.clear();
  const VisibilityAwareFilter::Result r = p.relief->filter_visible(
      g, view_ts, sf.u_length(), sf.v_length(), p.vis_ops, pipe_ ? &fetched_reads_ : nullptr);
  ++p.fragments;
  count_frame(g);
  const uint32_t n = r.stats.colour_reads + r.stats.trace_reads;
  p.vis_texels += n;
  if (pipe_) {
    relief_lines(p, fetched_reads_, lines_);
    const uint32_t tpc = setup_.cache.texels_per_cycle;
    const uint32_t scan = std::max<uint32_t>(1, n * p.vis_ii);
    const int addr = base_ + kAddress, cache = base_ + kCache;
    issue_any([&](int s, uint64_t start) {
      if (s < kMaxFront && s < front_) return front_cost(p, front, s);
      ItemCost c;
      add_effect_costs(s, c);
      if (s == addr) c.extra_ii = scan - 1;
      if (s == cache) {
        c.extra_ii = n > 0 ? (n + tpc - 1) / tpc - 1 : 0;
        const uint64_t relief_wait = relief_lookups(start);
        c.extra_latency = std::max(
            relief_wait, access_lines(lines_.data(), static_cast<int>(lines_.size()), n, start));
      }
      return c;
    });
  }
  return {r.colour.x, r.colour.y, r.colour.z, r.colour.w};
}

Rgba TextureUnit::filter_fragment(const Fragment& f, Path& p, const ItemCost* front) {
  // The fragment's own texture: a trace may texture a material's primitive with any texture of
  // its table, and the reference filters the same one.
  if (f.tex >= static_cast<uint32_t>(textures_.size()))
    throw std::out_of_range("texture unit: fragment texture " + std::to_string(f.tex) +
                            " is not loaded");
  const Texture& tex = textures_[static_cast<int>(f.tex)];
  return (this->*p.kernel)(f, p, tex, front);
}

template <class CostFn>
void TextureUnit::issue_any(CostFn&& cost_at) {
  if (!defer_) {
    pipe_->issue_with(0, cost_at);
    return;
  }
  // Every stage's cost now (only the cache stage's wait depends on the cycle, and its
  // look-ups are recorded, not made); the stages in front of the cache now, the rest at commit.
  rec_groups_.clear();
  rec_lines_.clear();
  recording_ = true;
  for (int s = 0; s < pipe_->stage_count(); ++s)
    defer_costs_[static_cast<size_t>(s)] = cost_at(s, 0);
  recording_ = false;
  const int k = base_ + kCache;
  defer_arrival_ = pipe_->issue_head(
      0, k, [&](int s, uint64_t) { return defer_costs_[static_cast<size_t>(s)]; });
  defer_start_ = pipe_->start_at(k, defer_arrival_);
}

void TextureUnit::commit() {
  const int k = base_ + kCache;
  uint64_t wait = 0;
  recording_ = false;
  for (const LineGroup& g : rec_groups_) {
    wait = std::max(wait, access_lines(rec_lines_.data() + g.first, static_cast<int>(g.count),
                                       g.texels, defer_start_));
  }
  defer_costs_[static_cast<size_t>(k)].extra_latency = wait;
  pipe_->issue_tail(k, defer_arrival_,
                    [&](int s, uint64_t) { return defer_costs_[static_cast<size_t>(s)]; });
}

template <int kFront, class Lookups>
void TextureUnit::issue_timed(Path& p, const ItemCost* front, uint32_t probes, Lookups&& lookups) {
  // Per-stage costs: the address stage issues one probe per cycle, cache and blend take
  // their texels in groups, and a miss in the cache stage waits for DRAM.
  if constexpr (kFront == kAnyStages) {
    // A unit with relief or lighting stages: every stage by index, the effects' extra cycles.
    const int addr = base_ + kAddress, cache = base_ + kCache, blend = base_ + kBlend;
    issue_any([&](int s, uint64_t start) {
      if (s < kMaxFront && s < front_) return front_cost(p, front, s);
      ItemCost c;
      add_effect_costs(s, c);
      if (s == addr) c.extra_ii = probes - 1;
      if (s == cache) {
        c.extra_ii = p.cache_extra_ii[probes];
        const uint64_t relief_wait = relief_lookups(start);
        c.extra_latency = std::max(relief_wait, lookups(start));
      }
      if (s == blend) c.extra_ii = p.blend_extra_ii[probes];
      return c;
    });
  } else {
    issue_fixed_stages<kFront>(p, front, probes, lookups);
  }
}

template <int kFront, class Lookups>
void TextureUnit::issue_fixed_stages(Path& p, const ItemCost* front, uint32_t probes,
                                     Lookups& lookups) {
  pipe_->issue_fixed<kFront + kStages>(
      0, [&](auto stage, uint64_t start) __attribute__((always_inline)) {
        constexpr int s = decltype(stage)::value;
        ItemCost c;
        if constexpr (s < kFront) {
          c = front_cost(p, front, s);
        } else if constexpr (s == kFront + kAddress) {
          c.extra_ii = probes - 1;
        } else if constexpr (s == kFront + kCache) {
          c.extra_ii = p.cache_extra_ii[probes];
          c.extra_latency = lookups(start);
        } else if constexpr (s == kFront + kBlend) {
          c.extra_ii = p.blend_extra_ii[probes];
        }
        return c;
      });
}

template <int kFront>
Rgba TextureUnit::process_taps(const Fragment& f, Path& p, const Texture& tex,
                               const ItemCost* front, const LodResult& lod) {
  p.addr.taps(tex, f.u, f.v, lod, taps_);
  const Rgba colour = blend_.blend(taps_, tex);
  const uint32_t probes = TexelAddressGen::issue_cycles(lod);
  count_fragment(f, p, probes);
  if constexpr (kFront >= 0) {
    issue_timed<kFront>(p, front, probes,
                        [&](uint64_t start) { return cache_lookups(taps_, tex, start); });
  }
  return colour;
}

template <int kFront>
Rgba TextureUnit::process_any(const Fragment& f, Path& p, const Texture& tex,
                              const ItemCost* front) {
  if (p.footprint) return process_footprint(f, p, tex, front);
  return process_taps<kFront>(f, p, tex, front, p.lod.eval(f, tex.width(0), tex.height(0)));
}

template <FilterMode kFilter, TexelLayout L, int kFront>
Rgba TextureUnit::process_linear(const Fragment& f, Path& p, const Texture& tex,
                                 const ItemCost* front) {
  const LodResult lod = p.lod.eval(f, tex.width(0), tex.height(0));
  if (TexelAddressGen::issue_cycles(lod) != 1 || tex.layout() != L)
    return process_taps<kFront>(f, p, tex, front, lod);
  // One probe at (u, v): the taps TexelAddressGen::taps() gives, as quads.
  using texel_address_detail::finite_or_zero;
  const TexelAddressGen::LevelSelect sel = p.addr.select_levels(lod.lambda, tex.levels());
  const float uf = finite_or_zero(static_cast<float>(f.u));
  const float vf = finite_or_zero(static_cast<float>(f.v));
  TexelQuad q[2];
  constexpr int n = kFilter == FilterMode::Trilinear ? 2 : 1;
  if constexpr (n == 1) {
    q[0] = p.addr.linear_quad(tex, sel.d_hi, uf, vf, 1.0f);
  } else {
    q[0] = p.addr.linear_quad(tex, sel.d_hi, uf, vf, 1.0f - sel.delta);
    q[1] = p.addr.linear_quad(tex, sel.d_lo, uf, vf, sel.delta);
  }
  const Rgba colour = blend_.blend_quads(q, n, tex);
  count_fragment(f, p, 1);
  if constexpr (kFront >= 0) {
    issue_timed<kFront>(p, front, 1,
                        [&](uint64_t start) { return cache_lookups<L>(q, n, tex, start); });
  }
  return colour;
}

template <FilterMode kFilter, TexelLayout L, int kFront>
void TextureUnit::batch_linear(const Fragment* f, size_t n, Path& p, const Texture& tex,
                               Rgba* out) {
  if (tex.layout() != L || !p.batch->serves(tex)) {
    for (size_t i = 0; i < n; ++i) out[i] = filter_fragment(f[i], p, nullptr);
    return;
  }
  LinearBatch& b = *batch_out_;
  p.batch->filter(f, n, tex, b, kFront >= 0 ? cache_.line_shift() : 0);
  constexpr int nq = kFilter == FilterMode::Trilinear ? 2 : 1;
  for (size_t i = 0; i < n; ++i) {
    if (!b.done[i]) {
      out[i] = filter_fragment(f[i], p, nullptr);  // its own texture, the scalar kernel
      continue;
    }
    count_fragment(f[i], p, 1);
    if constexpr (kFront >= 0) {
      if (b.has_lines) {
        // The batch's distinct lines, in order of first use (as cache_lookups<L> finds them).
        issue_timed<kFront>(p, nullptr, 1, [&](uint64_t start) {
          uint64_t lines[4 * nq];
          int k = 0;
          for (int t = 0; t < 4 * nq; ++t) {
            if (b.first_use[i] & (1 << t)) lines[k++] = static_cast<uint64_t>(b.line[t][i]);
          }
          return access_lines(lines, k, 4 * nq, start);
        });
        out[i] = b.colour(i);
        continue;
      }
      TexelQuad q[nq];
      for (int j = 0; j < nq; ++j) {
        q[j].level = b.level[j][i];
        q[j].x0 = b.x0[j][i];
        q[j].x1 = b.x1[j][i];
        q[j].y0 = b.y0[j][i];
        q[j].y1 = b.y1[j][i];
      }
      issue_timed<kFront>(p, nullptr, 1,
                          [&](uint64_t start) { return cache_lookups<L>(q, nq, tex, start); });
    }
    out[i] = b.colour(i);
  }
}

template <int kFront>
TextureUnit::BatchKernel TextureUnit::pick_batch_kernel(FilterMode filter, TexelLayout layout) {
  constexpr FilterMode kBi = FilterMode::Bilinear, kTri = FilterMode::Trilinear;
  const bool tri = filter == kTri;
  switch (layout) {
    case TexelLayout::Linear:
      return tri ? &TextureUnit::batch_linear<kTri, TexelLayout::Linear, kFront>
                 : &TextureUnit::batch_linear<kBi, TexelLayout::Linear, kFront>;
    case TexelLayout::Tiled4x4:
      return tri ? &TextureUnit::batch_linear<kTri, TexelLayout::Tiled4x4, kFront>
                 : &TextureUnit::batch_linear<kBi, TexelLayout::Tiled4x4, kFront>;
    case TexelLayout::Morton:
      return tri ? &TextureUnit::batch_linear<kTri, TexelLayout::Morton, kFront>
                 : &TextureUnit::batch_linear<kBi, TexelLayout::Morton, kFront>;
  }
  return nullptr;
}

template <int kFront>
TextureUnit::Kernel TextureUnit::pick_kernel(FilterMode filter, TexelLayout layout, bool quads) {
  if (!quads) return &TextureUnit::process_any<kFront>;
  constexpr FilterMode kBi = FilterMode::Bilinear, kTri = FilterMode::Trilinear;
  const bool tri = filter == kTri;
  switch (layout) {
    case TexelLayout::Linear:
      return tri ? &TextureUnit::process_linear<kTri, TexelLayout::Linear, kFront>
                 : &TextureUnit::process_linear<kBi, TexelLayout::Linear, kFront>;
    case TexelLayout::Tiled4x4:
      return tri ? &TextureUnit::process_linear<kTri, TexelLayout::Tiled4x4, kFront>
                 : &TextureUnit::process_linear<kBi, TexelLayout::Tiled4x4, kFront>;
    case TexelLayout::Morton:
      return tri ? &TextureUnit::process_linear<kTri, TexelLayout::Morton, kFront>
                 : &TextureUnit::process_linear<kBi, TexelLayout::Morton, kFront>;
  }
  return &TextureUnit::process_any<kFront>;
}

TextureUnit::Kernel TextureUnit::choose_kernel(const Path& p) const {
  const FilterMode filter = p.addr.config().filter;
  const bool linear = filter != FilterMode::Nearest;
  const bool quads =
      !p.footprint && linear && blend_.quads_in_one_group(filter == FilterMode::Trilinear ? 2 : 1);
  const TexelLayout layout = textures_.layout();
  if (!pipe_) return pick_kernel<-1>(filter, layout, quads);
  if (relief_stage_ >= 0 || light_stage_ >= 0 || defer_)
    return pick_kernel<kAnyStages>(filter, layout, quads);
  switch (front_) {
    case 0:
      return pick_kernel<0>(filter, layout, quads);
    case 1:
      return pick_kernel<1>(filter, layout, quads);
    default:
      return pick_kernel<kMaxFront>(filter, layout, quads);
  }
}

void TextureUnit::check_timing_invariants() const {
  if (!pipe_) return;
  // The run ends at the last exit or at a stage's last issue slot, whichever is later (the
  // last items' slots can outlast the run: a triangle's or row's set-up, and the front-end
  // cycles of dropped fragments, are charged as extra issue cycles after a fragment).
  const uint64_t cycles = pipe_->run_end();
  auto fail = [&](const std::string& what, uint64_t need) {
    throw std::logic_error("timing invariant violated: " + what + " needs " + std::to_string(need) +
                           " cycles but the run took " + std::to_string(cycles));
  };
  for (int s = 0; s < pipe_->stage_count(); ++s) {
    const uint64_t lanes = std::max<uint32_t>(1, pipe_->config(s).timing.lanes);
    const uint64_t busy = pipe_->stats(s).busy;
    if (cycles < busy / lanes) fail("stage '" + pipe_->config(s).name + "'", busy / lanes);
  }
  // A unit of several shares its DRAM: UnitArray checks it against the last unit's cycles.
  const uint64_t dram_busy = own_memory_ ? mem_->dram_totals().busy_cycles : 0;
  if (cycles < dram_busy) fail("the DRAM channel", dram_busy);
}

std::vector<BlockUse> TextureUnit::material_blocks(int material) const {
  const Path& p = paths_[static_cast<size_t>(material)];
  const std::string& m = mats_[static_cast<size_t>(material)].name;
  std::vector<BlockUse> out;
  auto add = [&](const std::string& name, const std::string& arith, const TimingSpec& t,
                 const OpCounts& ops, uint64_t texels = 0) {
    out.push_back({name, arith, t, ops, texels, {m}});
  };
  if (p.coords) {
    const CoordUnitConfig& cc = p.coords->config();
    const std::vector<StageConfig> st = p.coords->stages(tech_);
    const std::string arith = cc.format + ", " + datapath_name(cc.datapath) + " datapath";
    // The format is part of the name: two materials with one method in two formats are two units.
    add("coords." + cc.coords + "[" + cc.format + "]", arith, st[0].timing, p.coord_ops);
    if (p.coords->has_derivs())
      add("derivs." + cc.derivs + "[" + cc.format + "]", arith, st[1].timing, p.deriv_ops);
  }
  if (p.relief) {
    add(p.relief->name(), p.relief->arithmetic(), p.relief->timing(tech_), p.relief_ops,
        p.relief_fetches);
  }
  // Lighting comes after the blend (its blocks last).
  const auto add_lighting = [&] {
    if (!p.lighting) return;
    if (p.lighting->has_normal_unit()) {
      const NormalUnit& n = p.lighting->normal_unit();
      add(n.name(), n.arithmetic(), n.timing(tech_), p.normal_ops);
    }
    const BlinnPhongShader& sh = p.lighting->shader();
    add(sh.name(), sh.arithmetic(), sh.timing(tech_), p.shader_ops);
  };
  if (p.relief && p.relief->has_visibility_filter()) {
    const VisibilityAwareFilter& vf = p.relief->visibility_filter();
    add(vf.name(), vf.arithmetic(), vf.timing(tech_), p.vis_ops, p.vis_texels);
    add_lighting();
    return out;
  }
  if (p.footprint) {
    add(p.footprint->name(), p.footprint->arithmetic(), p.footprint->timing(tech_), p.footprint_ops,
        p.footprint_texels);
    add_lighting();
    return out;
  }
  // Per-fragment and per-probe counts times the fragments and probes seen (see Path).
  const uint64_t iso = p.fragments - p.aniso_fragments;  // one probe each
  const uint64_t aniso_probes = p.probes - iso;
  const uint64_t taps = p.probes * static_cast<uint64_t>(p.addr.taps_per_probe());
  const OpCounts addr_ops =
      p.addr.ops_setup(false) * iso + p.addr.ops_setup(true) * p.aniso_fragments +
      p.addr.ops_per_item(false) * iso + p.addr.ops_per_item(true) * aniso_probes;
  add(p.lod.name(), p.lod.arithmetic(), p.lod.timing(tech_), p.lod.ops_per_item() * p.fragments);
  add(p.addr.name(), p.addr.arithmetic(), p.addr.timing(tech_), addr_ops, taps);
  add(blend_.name(), blend_.arithmetic(), blend_.timing(tech_), TexelBlend::ops_per_item() * taps);
  add_lighting();
  return out;
}

std::vector<BlockUse> TextureUnit::blocks() const {
  // One entry per hardware unit: materials share a unit when they use the same block with the
  // same arithmetic. A block used with two configurations is two units, told apart by their
  // materials ("filter.ewa[floor]").
  std::map<std::pair<std::string, std::string>, BlockUse> by;
  std::map<std::string, int> configs;
  uint64_t texels = 0;
  for (int i = 0; i < material_count(); ++i) {
    for (const BlockUse& u : material_blocks(i)) {
      auto [it, fresh] = by.try_emplace({u.name, u.arithmetic}, u);
      BlockUse& b = it->second;
      if (fresh) {
        ++configs[u.name];
      } else {
        if (u.timing.latency >= b.timing.latency) b.timing = u.timing;
        b.ops += u.ops;
        b.texels += u.texels;
        b.materials.push_back(u.materials.front());
      }
      texels += u.texels;
    }
  }
  std::vector<BlockUse> out;
  for (auto& [k, v] : by) {
    if (configs[v.name] > 1) {
      std::string mats;
      for (const auto& m : v.materials) mats += (mats.empty() ? "" : ",") + m;
      v.name += "[" + mats + "]";
    }
    out.push_back(v);
  }
  BlockUse c;
  c.name = TextureCache::name();
  c.arithmetic = TextureCache::arithmetic();
  c.timing.latency = setup_.cache.hit_latency;
  c.ops.mem = texels;  // every texel a filter fetched is one read through the cache
  c.texels = texels;
  for (const auto& m : mats_) c.materials.push_back(m.name);
  out.push_back(c);
  // Measured areas (e.g. LUTs of the real RTL) replace derived ones, by the reported name.
  for (BlockUse& b : out) b.timing.area = tech_.block_area_or(b.name, b.timing.area);
  return out;
}

}  // namespace texsim
