#pragma once
// Workload characterisation: what a stream of fragments asks of a texture unit, independent of
// the unit's configuration (docs/reports.md "workload"). Per frame: fragments and quads, textures
// touched, distinct texels and cache lines (working sets), LOD and anisotropy histograms, the
// magnified share and the reuse distance of cache lines.
//
// Model (an approximation of what any filter reads, so that scenes and traces compare):
// - LOD: Vulkan's isotropic λ = log2 max(ρx, ρy) + the fragment's lod_bias, ρx = |(du/dx·w,
//   dv/dx·h)|, unclamped; non-finite derivatives give λ = 0 (as the LOD unit).
// - Anisotropy: η = ρmax/ρmin (Vulkan's ratio), binned by log2 η rounded to the nearest integer.
// - Texels: the bilinear 2x2 footprint of (u, v) with wrap addressing, at level 0 and at the
//   nearest mip level to λ (clamped to the pyramid). Lines, working sets and reuse use the
//   footprint at that level, at the textures' byte addresses (the run's layout).
// - Reuse distance: per frame, exact LRU stack distance on 64-byte lines (distinct other lines
//   between two uses; a fragment's texels in one line are one use), for at most kReuseMaxLines
//   distinct lines per frame; uses of further lines are counted as untracked.
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

// One texture as the characterisation sees it: its levels' sizes and byte addresses.
struct WorkloadTexture {
  uint64_t base = 0;
  int bytes_per_texel = 4;
  TexelLayout layout = TexelLayout::Tiled4x4;
  std::vector<Texture::Level> levels;
  uint64_t address(int level, int x, int y) const {
    const Texture::Level& lv = levels[static_cast<size_t>(level)];
    return base + lv.offset +
           Texture::texel_index(layout, lv, x, y) * static_cast<uint64_t>(bytes_per_texel);
  }
  static WorkloadTexture of(const Texture& t);  // a placed texture's own levels and addresses
};

// Places textures (their levels' sizes and bytes per texel) one after another as
// Texture::place and TextureSet::place do: each level rounded up to 256 bytes, each texture on a
// 4 KiB page.
std::vector<WorkloadTexture> place_workload_textures(std::vector<WorkloadTexture> textures,
                                                     TexelLayout layout);
// Textures of the given level-0 sizes with full RGBA8 mip chains (sizes floor(w/2) down to 1x1),
// placed: a trace's texture table gives only the sizes.
std::vector<WorkloadTexture> place_workload_textures(const std::vector<std::array<int, 2>>& sizes,
                                                     TexelLayout layout);
// The textures of a placed set, at their own addresses.
std::vector<WorkloadTexture> workload_textures(const TextureSet& set);

// Open-addressing hash table of 64-bit keys (all but ~0) with a 32-bit value each; grows by
// doubling. Faster than std::unordered_map for the per-texel inserts of every fragment.
class FlatTable {
 public:
  // The value slot of `key`; `inserted` tells whether the key is new (its value is then 0).
  uint32_t& find_or_insert(uint64_t key, bool& inserted);
  uint32_t* find(uint64_t key);  // null when absent
  // Set use: adds `key`. A small direct-mapped memory of recent keys skips most repeats (the
  // texels and lines of neighbouring fragments) before the table's own, cache-missing probe.
  void insert(uint64_t key) {
    uint64_t& r = recent_[(key * 0x9E3779B97F4A7C15ULL) >> 58];
    if (r == key) return;
    r = key;
    bool inserted = false;
    find_or_insert(key, inserted);
  }
  size_t size() const { return size_; }
  void clear();
  template <class F>
  void for_each(F&& f) {
    for (size_t i = 0; i < keys_.size(); ++i)
      if (keys_[i] != kEmpty) f(keys_[i], vals_[i]);
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t{0};
  void grow();
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> vals_;
  size_t size_ = 0;
  std::array<uint64_t, 64> recent_ = filled_recent();
  static std::array<uint64_t, 64> filled_recent() {
    std::array<uint64_t, 64> a;
    a.fill(kEmpty);
    return a;
  }
};

// One bit per granule of the textures' address space: distinct texels (4-byte granules) and
// lines (a granule per line) are counted by direct indexing (a texel set: 1/32 of the textures'
// bytes), faster than any hash set.
class Bitmap {
 public:
  void resize(uint64_t bits) { words_.assign((bits + 63) / 64, 0); }
  void set(uint64_t i) {
    uint64_t& w = words_[i >> 6];
    const uint64_t m = uint64_t{1} << (i & 63);
    count_ += (w & m) == 0;
    w |= m;
  }
  uint64_t count() const { return count_; }
  void clear() {
    if (count_ == 0) return;
    std::fill(words_.begin(), words_.end(), 0);
    count_ = 0;
  }

 private:
  std::vector<uint64_t> words_;
  uint64_t count_ = 0;
};

// Exact LRU stack distances: a Fenwick tree over access times marks each line's last use.
class ReuseDistance {
 public:
  static constexpr size_t kMaxLines = size_t{1} << 20;
  static constexpr int kBins = 21;  // 0, [1,2), [2,4), ..., [2^19, 2^20)
  // One use of `line`: its distance's bin is counted, or a first use, or untracked.
  void use(uint64_t line);
  void reset();  // a new frame: every line is new again
  std::array<uint64_t, kBins> hist{};
  uint64_t uses = 0, first_uses = 0, untracked = 0;

 private:
  void add(uint32_t t, int d);
  uint32_t prefix(uint32_t t) const;  // marks at times < t
  void compact();
  FlatTable last_;                     // line -> last use time
  std::vector<int32_t> tree_;          // Fenwick tree over times
  uint32_t now_ = 0, live_ = 0;        // next time; marks in the tree
  uint64_t last_line_ = ~uint64_t{0};  // the line of the latest use
};

struct FrameWorkload {
  static constexpr double kLodLo = -4, kLodStep = 0.5;
  static constexpr int kLodBins = 32;   // [-4, 12) in steps of 0.5
  static constexpr int kAnisoBins = 6;  // 1, 2, 4, 8, 16, >16
  static constexpr std::array<int, 3> kLineBytes = {32, 64, 128};
  static constexpr int kReuseLineBytes = 64;

  uint32_t frame = 0;
  uint64_t fragments = 0, quads = 0;
  uint64_t textures = 0;            // distinct textures touched
  uint64_t texels_level0 = 0;       // distinct texels of the footprints at level 0
  uint64_t texels_lod = 0;          // ... at the nearest level to λ
  std::array<uint64_t, 3> lines{};  // distinct lines at kLineBytes (working set)
  std::array<uint64_t, kLodBins> lod{};
  uint64_t lod_under = 0, lod_over = 0;
  std::array<uint64_t, kAnisoBins> aniso{};
  uint64_t magnified = 0, minified = 0;  // λ < 0, λ ≥ 0
  double footprint_texels = 0;  // sum over fragments of the footprint's area in level-0 texels
  uint64_t line_uses = 0, first_uses = 0, untracked_uses = 0;
  std::array<uint64_t, ReuseDistance::kBins> reuse{};

  double per_fragment(double v) const { return fragments ? v / static_cast<double>(fragments) : 0; }
};

class WorkloadStats {
 public:
  WorkloadStats() = default;
  explicit WorkloadStats(std::vector<WorkloadTexture> textures);
  // `tex`: index into the textures given (a trace's id mapped to its table position).
  void add(const Fragment& f, uint32_t tex);
  void finish();  // closes the last frame
  const std::vector<FrameWorkload>& frames() const { return frames_; }
  FrameWorkload total() const;  // additive figures summed; distinct counts summed over frames
  std::string layout() const;
  bool empty() const { return textures_.empty(); }

 private:
  void close_frame();
  std::vector<WorkloadTexture> textures_;
  std::vector<FrameWorkload> frames_;
  FrameWorkload cur_;
  bool open_ = false;
  uint32_t qprim_ = 0, qx_ = 0, qy_ = 0;  // the open quad (a new frame opens one too)
  std::vector<uint8_t> touched_;
  Bitmap texels0_, texels_, lines_[3];
  ReuseDistance reuse_;
};

}  // namespace texsim
