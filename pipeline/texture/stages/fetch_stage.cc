#include "pipeline/texture/stages/fetch_stage.h"

namespace texsim {

FetchStage::FetchStage(TextureCache& l1, LineMemory& next, int unit,
                       const TextureCache::Config& cfg, bool quad_merge)
    : l1_(l1),
      next_(next),
      unit_(unit),
      hit_latency_(cfg.hit_latency),
      line_bytes_(cfg.line_bytes),
      miss_queue_(cfg.miss_queue),
      tpc_(cfg.texels_per_cycle),
      quad_merge_(quad_merge) {
  for (uint64_t t = 0; t < kTable; ++t) extra_ii_[t] = group_cycles(t);
}

void FetchStage::declare(SlotPlan& plan) const {
  TimingSpec t;
  t.latency = hit_latency_;
  plan.set(Slot::Cache, t, miss_queue_);
}

uint64_t FetchStage::access_quad_lines(const uint64_t* lines, int n, uint64_t texels,
                                       uint64_t start) {
  const uint64_t hit_ready = start + hit_latency_;
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
    if (!l1_.access_line(lines[k]))
      r = std::max(r, next_.read_line(start, lines[k] << l1_.line_shift(), line_bytes_, unit_));
    quad_lines_.emplace_back(lines[k], r);
    ready = std::max(ready, r);
  }
  l1_.count_texels(texels);
  return ready - hit_ready;
}

void FetchStage::note_quad(const Fragment& f) {
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

namespace {

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
    fetch_detail::add_quad(tex.base() + lv.offset, Texture::row_index(L, lv, q[0].y),
                           Texture::row_index(L, lv, q[2].y), Texture::col_index(L, q[0].x),
                           Texture::col_index(L, q[1].x), bpt, shift, lines, n);
  }
  for (; i < taps.count; ++i) {  // nearest taps, or anything not in quads
    const TexelTap& t = taps.tap[static_cast<size_t>(i)];
    const Texture::Level& lv = tex.level(t.level);
    fetch_detail::add_line(
        (tex.base() + lv.offset + Texture::texel_index(L, lv, t.x, t.y) * bpt) >> shift, lines, n);
  }
  return n;
}

}  // namespace

uint64_t FetchStage::lookup_blocks(const TexelTap* taps, int count, const Texture& tex,
                                   uint64_t start) {
  const uint32_t shift = l1_.line_shift();
  uint64_t blocks[128], lines[128];
  int nb = 0, n = 0;
  for (int i = 0; i < count && nb < 128; ++i) {
    const TexelTap& t = taps[i];
    const uint64_t b = tex.block_address(t.level, t.x, t.y);
    int k = 0;
    while (k < nb && blocks[k] != b) ++k;
    if (k < nb) continue;
    blocks[nb++] = b;
    fetch_detail::add_line(b >> shift, lines, n);
  }
  decoded_blocks_ += static_cast<uint64_t>(nb);
  decoded_by_format_[static_cast<size_t>(tex.blocks()->format)] += static_cast<uint64_t>(nb);
  return access_lines(lines, n, static_cast<uint64_t>(count), start) +
         block_latency_(tex.blocks()->format);
}

uint64_t FetchStage::lookup_block_quads(const TexelQuad* q, int n, const Texture& tex,
                                        uint64_t start) {
  TexelTap taps[32];
  int count = 0;
  for (int j = 0; j < n && j < 8; ++j) {
    for (const int y : {q[j].y0, q[j].y1}) {
      for (const int x : {q[j].x0, q[j].x1}) taps[count++] = {q[j].level, x, y, 0.0f};
    }
  }
  return lookup_blocks(taps, count, tex, start);
}

uint64_t FetchStage::lookup_taps(const FilterTaps& taps, const Texture& tex, uint64_t start) {
  if (taps.border_taps > 0) {
    // Border taps read the sampler's colour: no line, no texel through the cache.
    FilterTaps read;
    for (int i = 0; i < taps.count; ++i) {
      const TexelTap& t = taps.tap[static_cast<size_t>(i)];
      if (t.x != kBorderTexel && t.y != kBorderTexel)
        read.tap[static_cast<size_t>(read.count++)] = t;
    }
    return lookup_taps(read, tex, start);
  }
  if (block_latency_ && tex.compressed())
    return lookup_blocks(taps.tap.data(), taps.count, tex, start);
  // Each distinct line of the fragment's taps is one tag look-up.
  const uint32_t shift = l1_.line_shift();
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

uint64_t FetchStage::commit_lookups(uint64_t start) {
  recording_ = false;
  uint64_t wait = 0;
  for (const LineGroup& g : rec_groups_) {
    wait = std::max(wait, lookup_lines(rec_lines_.data() + g.first, static_cast<int>(g.count),
                                       g.texels, start));
  }
  return wait;
}

void FetchStage::look_up_recorded() {
  for (const LineGroup& g : rec_groups_) {
    for (size_t k = 0; k < g.count; ++k) {
      const uint64_t line = rec_lines_[g.first + k];
      if (!l1_.access_line(line)) missed_.push_back(line);
    }
    l1_.count_texels(g.texels);
  }
}

uint64_t FetchStage::commit_misses(uint32_t n, uint64_t start) {
  const uint64_t hit_ready = start + hit_latency_;
  uint64_t ready = hit_ready;
  const uint32_t shift = l1_.line_shift();
  for (uint32_t k = 0; k < n; ++k) {
    const uint64_t line = missed_[missed_head_++];
    ready = std::max(ready, next_.read_line(start, line << shift, line_bytes_, unit_));
  }
  if (missed_head_ == missed_.size()) {  // every kept miss committed: start over
    missed_.clear();
    missed_head_ = 0;
  }
  return ready - hit_ready;
}

bool FetchStage::recorded_local() const {
  if (!quad_merge_) return rec_groups_.empty();  // the hits were looked up as they came
  for (const uint64_t line : rec_lines_) {
    if (quad_merge_ && std::any_of(quad_lines_.begin(), quad_lines_.end(),
                                   [&](const auto& e) { return e.first == line; }))
      continue;
    if (!l1_.contains(line)) return false;
  }
  return true;
}

BlockUse FetchStage::row(uint64_t texels, std::vector<std::string> materials) const {
  BlockUse c;
  c.name = TextureCache::name();
  c.arithmetic = TextureCache::arithmetic();
  c.timing.latency = hit_latency_;
  c.ops.mem = texels;  // every texel a filter fetched is one read through the cache
  c.texels = texels;
  c.materials = std::move(materials);
  return c;
}

}  // namespace texsim
