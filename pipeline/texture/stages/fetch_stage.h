#pragma once
// The texel fetch stage of a texture unit: the tag look-ups of a fragment's distinct cache
// lines in the unit's L1, its misses sent to the level behind it, with quad merging (one
// look-up per distinct line of a 2x2 quad) and the two-step timing of a unit of several (the
// look-ups recorded when the fragment is issued, made when the scheduler commits it). One per
// unit: every material's fetches share the L1. The look-ups are non-virtual and inline: the
// templated kernels of the texture unit call them once per fragment.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/memory/line_memory.h"
#include "blocks/texture/memory/texture_cache.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "pipeline/texture/stages/unit_stage.h"

namespace texsim {

class FetchStage {
 public:
  // l1: the unit's cache; next: where its misses go; unit: the unit's index there.
  FetchStage(TextureCache& l1, LineMemory& next, int unit, const TextureCache::Config& cfg,
             bool quad_merge);

  // Sizes the cache slot: the hit latency, and the miss queue as its in-flight limit.
  void declare(SlotPlan& plan) const;
  const TextureCache& cache() const { return l1_; }
  uint32_t line_shift() const { return l1_.line_shift(); }
  uint64_t line_of(uint64_t addr) const { return l1_.line_of(addr); }
  // Extra issue cycles of a fragment of `texels` texels (texels_per_cycle a cycle).
  uint32_t extra_ii(uint64_t texels) const {
    return texels < kTable ? extra_ii_[texels] : group_cycles(texels);
  }

  // Tag look-ups of lines[0 .. n) (distinct) at cycle `start`, for `texels` texels; returns
  // the cycles the fragment waits beyond the hit latency (the misses' refills).
  [[gnu::always_inline]] inline uint64_t access_lines(const uint64_t* lines, int n, uint64_t texels,
                                                      uint64_t start) {
    if (recording_) {
      // Lines all in the L1 (without quad merging) are hits at any cycle: looked up now, as
      // the unit's next look-ups (they would be, at commit), and nothing is left to record.
      if (!quad_merge_ && hit_all(lines, n, texels)) return 0;
      return record(lines, n, texels);
    }
    return lookup_lines(lines, n, texels, start);
  }
  // The look-ups themselves, at `start`.
  [[gnu::always_inline]] inline uint64_t lookup_lines(const uint64_t* lines, int n, uint64_t texels,
                                                      uint64_t start) {
    if (quad_merge_) return access_quad_lines(lines, n, texels, start);
    const uint64_t hit_ready = start + hit_latency_;
    uint64_t ready = hit_ready;
    const uint32_t shift = l1_.line_shift();
    for (int k = 0; k < n; ++k) {
      if (!l1_.access_line(lines[k]))
        ready = std::max(ready, next_.read_line(start, lines[k] << shift, line_bytes_, unit_));
    }
    l1_.count_texels(texels);
    return ready - hit_ready;
  }
  // Look-ups ahead of the clock (the batched datapath, TextureUnit::process_batch): the L1's
  // contents depend on its own look-ups only, never on the cycle, so a run of fragments' lines
  // can be looked up in order first (TextureCache::Run on l1(), count_texels) and only the lines
  // that missed wait, at their fragment's cycle in the cache slot, for the level behind
  // (read_misses): the same look-ups, fills and reads, in the same order, as lookup_lines() per
  // fragment. Not with quad merging (a merged line is ready when the earlier lane's read is) nor
  // while recording.
  bool looks_up_ahead() const { return !quad_merge_ && !recording_; }
  TextureCache& l1() { return l1_; }
  void count_texels(uint64_t texels) { l1_.count_texels(texels); }
  // The wait beyond the hit latency of a fragment whose lines[0 .. n) missed the L1, read from
  // the level behind at `start`.
  uint64_t read_misses(const uint64_t* lines, size_t n, uint64_t start) {
    const uint64_t hit_ready = start + hit_latency_;
    uint64_t ready = hit_ready;
    const uint32_t shift = l1_.line_shift();
    for (size_t k = 0; k < n; ++k)
      ready = std::max(ready, next_.read_line(start, lines[k] << shift, line_bytes_, unit_));
    return ready - hit_ready;
  }
  // The distinct lines of a fragment's taps, looked up.
  uint64_t lookup_taps(const FilterTaps& taps, const Texture& tex, uint64_t start);
  // The same for the quads of a linear probe (one or two levels) under layout L: the lines
  // lookup_taps() finds for the taps the quads stand for, in the same order.
  template <TexelLayout L>
  [[gnu::always_inline]] inline uint64_t lookup_quads(const TexelQuad* q, int n, const Texture& tex,
                                                      uint64_t start);

  // Decompression after the L1 (PipelineSetup::Decompress::AfterL1): the L1 holds the blocks
  // of compressed textures, so their taps are looked up by block address, and each distinct
  // block of a fragment is one decoder activation; `latency(format)` cycles of the decoder
  // add to the fetch.
  void set_blocks_in_l1(std::function<uint32_t(CompressedFormat)> latency) {
    block_latency_ = std::move(latency);
  }
  uint64_t decoded_blocks() const { return decoded_blocks_; }
  const PerCompressedFormat& decoded_by_format() const { return decoded_by_format_; }

  // Reads an earlier stage made for the current fragment (lines distinct): looked up in the
  // cache slot before the filter's own, as the cache and DRAM see requests in time order.
  void stage_reads(const std::vector<uint64_t>& lines, uint64_t texels) {
    staged_lines_ = &lines;
    staged_texels_ = texels;
  }
  void clear_staged() { staged_texels_ = 0; }
  uint64_t staged_lookups(uint64_t start) {
    if (staged_texels_ == 0) return 0;
    return access_lines(staged_lines_->data(), static_cast<int>(staged_lines_->size()),
                        staged_texels_, start);
  }

  // Quad merging: whether f opens a new quad (QuadAssembler's rule: same frame, primitive and
  // 2x2 square as the previous fragment, and a lane not yet taken, continue it).
  bool quad_merge() const { return quad_merge_; }
  void note_quad(const Fragment& f);
  uint64_t merged_lookups() const { return quad_merged_; }

  // Two-step timing: between begin_recording() and end_recording() look-ups are recorded and
  // return no wait; commit_lookups(start) makes them at `start` and returns the wait.
  void begin_recording() {
    rec_groups_.clear();
    rec_lines_.clear();
    rec_mark_ = missed_.size();
    recording_ = true;
  }
  void end_recording() {
    recording_ = false;
    if (keep_misses_ && !rec_groups_.empty()) look_up_recorded();
  }
  uint64_t commit_lookups(uint64_t start);
  // Whether the recorded look-ups are sure to stay in this unit: nothing was recorded (without
  // quad merging a group whose lines are all in the L1 is looked up as it comes: each hits, a
  // hit evicts nothing, and the L1's contents depend on its own look-ups only, never on the
  // cycle), or every recorded line is in the L1 or in the open quad (merged, no look-up).
  // False may also mean "not sure" (a line the fragment's own earlier group would bring): the
  // caller then treats the fragment as one that misses.
  bool recorded_local() const;
  // Queued timing (TextureUnit::set_queued_timing; never with quad merging): the recorded
  // look-ups are made in the L1 at end_recording() (its contents depend on its own look-ups
  // only, never on the cycle) and only the lines that missed wait, in order, for the level
  // behind. recorded_local() still says whether any group was recorded.
  void set_keep_misses(bool on) { keep_misses_ = on; }
  // Lines missed since begin_recording().
  uint32_t kept_misses() const { return static_cast<uint32_t>(missed_.size() - rec_mark_); }
  // The next n kept misses read from the level behind at `start`; returns the fragment's
  // wait beyond the hit latency (as commit_lookups).
  uint64_t commit_misses(uint32_t n, uint64_t start);

  // The cache's report row: every texel a filter fetched is one read through it.
  BlockUse row(uint64_t texels, std::vector<std::string> materials) const;

 private:
  static constexpr uint64_t kTable = 129;  // up to 16 probes of 8 taps
  uint32_t group_cycles(uint64_t texels) const {
    return texels > 0 ? static_cast<uint32_t>((texels + tpc_ - 1) / tpc_ - 1) : 0;
  }
  // If every line is in the L1: their look-ups (all hits, in order), and true.
  [[gnu::always_inline]] inline bool hit_all(const uint64_t* lines, int n, uint64_t texels) {
    constexpr int kMax = 16;  // a linear probe's lines (8); more (anisotropic taps): recorded
    int64_t way[kMax];
    if (n > kMax) return false;
    for (int k = 0; k < n; ++k) {
      way[k] = l1_.find(lines[k]);
      if (way[k] < 0) return false;
    }
    for (int k = 0; k < n; ++k) l1_.hit_at(way[k]);
    l1_.count_texels(texels);
    return true;
  }
  // Queued timing: the recorded groups' L1 look-ups, made where commit_lookups() would make
  // them (after the fragment's other look-ups, before the unit's next fragment's).
  void look_up_recorded();
  uint64_t record(const uint64_t* lines, int n, uint64_t texels) {
    rec_groups_.push_back({rec_lines_.size(), static_cast<size_t>(n), texels});
    rec_lines_.insert(rec_lines_.end(), lines, lines + n);
    return 0;
  }
  uint64_t access_quad_lines(const uint64_t* lines, int n, uint64_t texels, uint64_t start);
  // Look-ups of a compressed texture's taps by block address (decompression after the L1).
  uint64_t lookup_blocks(const TexelTap* taps, int count, const Texture& tex, uint64_t start);
  uint64_t lookup_block_quads(const TexelQuad* q, int n, const Texture& tex, uint64_t start);

  TextureCache& l1_;
  LineMemory& next_;
  int unit_;
  uint32_t hit_latency_, line_bytes_, miss_queue_;
  uint64_t tpc_;
  uint32_t extra_ii_[kTable] = {};
  bool quad_merge_;
  // The open quad, and the lines its lanes looked up with the cycle each is ready; a later
  // lane reading one of them makes no look-up.
  uint32_t quad_frame_ = 0, quad_prim_ = 0, quad_x_ = 0, quad_y_ = 0, quad_mask_ = 0;
  bool quad_open_ = false;
  std::vector<std::pair<uint64_t, uint64_t>> quad_lines_;  // (line, ready)
  uint64_t quad_merged_ = 0;                               // look-ups saved
  // Two-step timing: the recorded look-ups (groups of lines, each with its texels).
  bool recording_ = false;
  struct LineGroup {
    size_t first, count;
    uint64_t texels;
  };
  std::vector<LineGroup> rec_groups_;
  std::vector<uint64_t> rec_lines_;
  // Queued timing: the kept misses of fragments not yet committed, from missed_head_.
  bool keep_misses_ = false;
  std::vector<uint64_t> missed_;
  size_t missed_head_ = 0, rec_mark_ = 0;
  const std::vector<uint64_t>* staged_lines_ = nullptr;
  uint64_t staged_texels_ = 0;
  std::function<uint32_t(CompressedFormat)> block_latency_;  // set: blocks in the L1
  uint64_t decoded_blocks_ = 0;
  PerCompressedFormat decoded_by_format_{};
};

namespace fetch_detail {
// Adds `line` to lines[0 .. n) unless present (order of first use kept).
[[gnu::always_inline]] inline void add_line(uint64_t line, uint64_t* lines, int& n) {
  int k = 0;
  while (k < n && lines[k] != line) ++k;
  if (k == n) lines[n++] = line;
}
// The distinct lines of one 2x2 quad at rows r0, r1 and columns c0, c1 of a level at `base`:
// the first quad's without a search.
[[gnu::always_inline]] inline void add_quad(uint64_t base, uint64_t r0, uint64_t r1, uint64_t c0,
                                            uint64_t c1, uint64_t bpt, uint32_t shift,
                                            uint64_t* lines, int& n) {
  const uint64_t l00 = (base + (r0 + c0) * bpt) >> shift, l10 = (base + (r0 + c1) * bpt) >> shift;
  const uint64_t l01 = (base + (r1 + c0) * bpt) >> shift, l11 = (base + (r1 + c1) * bpt) >> shift;
  if (n == 0) {
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
}  // namespace fetch_detail

template <TexelLayout L>
inline uint64_t FetchStage::lookup_quads(const TexelQuad* q, int n, const Texture& tex,
                                         uint64_t start) {
  if (block_latency_ && tex.compressed()) return lookup_block_quads(q, n, tex, start);
  const uint32_t shift = l1_.line_shift();
  const auto bpt = static_cast<uint64_t>(tex.bytes_per_texel());
  uint64_t lines[8];
  int k = 0;
  for (int j = 0; j < n; ++j) {
    const Texture::Level& lv = tex.level(q[j].level);
    fetch_detail::add_quad(tex.base() + lv.offset, Texture::row_index(L, lv, q[j].y0),
                           Texture::row_index(L, lv, q[j].y1), Texture::col_index(L, q[j].x0),
                           Texture::col_index(L, q[j].x1), bpt, shift, lines, k);
  }
  return access_lines(lines, k, 4 * static_cast<uint64_t>(n), start);
}

}  // namespace texsim
