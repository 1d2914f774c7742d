#include "pipeline/report/workload_stats.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

namespace texsim {

WorkloadTexture WorkloadTexture::of(const Texture& t) {
  WorkloadTexture w;
  w.base = t.base();
  w.bytes_per_texel = t.bytes_per_texel();
  w.layout = t.layout();
  for (int l = 0; l < t.levels(); ++l) w.levels.push_back(t.level(l));
  return w;
}

std::vector<WorkloadTexture> place_workload_textures(std::vector<WorkloadTexture> textures,
                                                     TexelLayout layout) {
  uint64_t base = 0;
  for (WorkloadTexture& t : textures) {
    t.base = base;
    t.layout = layout;
    uint64_t off = 0;
    for (Texture::Level& lv : t.levels) {
      lv.offset = off;
      const auto w = static_cast<uint64_t>(lv.width), h = static_cast<uint64_t>(lv.height);
      uint64_t texels = w * h;
      if (layout == TexelLayout::Tiled4x4) texels = ((w + 3) / 4) * ((h + 3) / 4) * 16;
      if (layout == TexelLayout::Morton) {
        uint64_t s = 1;
        while (s < std::max(w, h)) s <<= 1;
        texels = s * s;
      }
      off += (texels * static_cast<uint64_t>(t.bytes_per_texel) + 255) & ~uint64_t{255};
    }
    base += (off + 4095) & ~uint64_t{4095};
  }
  return textures;
}

std::vector<WorkloadTexture> place_workload_textures(const std::vector<std::array<int, 2>>& sizes,
                                                     TexelLayout layout) {
  std::vector<WorkloadTexture> out;
  for (const auto& [w0, h0] : sizes) {
    WorkloadTexture t;
    int w = std::max(w0, 1), h = std::max(h0, 1);
    while (true) {
      Texture::Level lv;
      lv.width = w;
      lv.height = h;
      t.levels.push_back(lv);
      if (w == 1 && h == 1) break;
      w = std::max(w / 2, 1);
      h = std::max(h / 2, 1);
    }
    out.push_back(std::move(t));
  }
  return place_workload_textures(std::move(out), layout);
}

std::vector<WorkloadTexture> workload_textures(const TextureSet& set) {
  std::vector<WorkloadTexture> out;
  out.reserve(static_cast<size_t>(set.size()));
  for (int i = 0; i < set.size(); ++i) out.push_back(WorkloadTexture::of(set[i]));
  return out;
}

// --- FlatTable ----------------------------------------------------------------------------------

namespace {
size_t slot_of(uint64_t key, size_t mask) {
  return static_cast<size_t>((key * 0x9E3779B97F4A7C15ULL) >> 20) & mask;
}
}  // namespace

uint32_t& FlatTable::find_or_insert(uint64_t key, bool& inserted) {
  if ((size_ + 1) * 2 > keys_.size()) grow();
  const size_t mask = keys_.size() - 1;
  for (size_t i = slot_of(key, mask);; i = (i + 1) & mask) {
    if (keys_[i] == key) {
      inserted = false;
      return vals_[i];
    }
    if (keys_[i] == kEmpty) {
      keys_[i] = key;
      vals_[i] = 0;
      ++size_;
      inserted = true;
      return vals_[i];
    }
  }
}

uint32_t* FlatTable::find(uint64_t key) {
  if (keys_.empty()) return nullptr;
  const size_t mask = keys_.size() - 1;
  for (size_t i = slot_of(key, mask);; i = (i + 1) & mask) {
    if (keys_[i] == key) return &vals_[i];
    if (keys_[i] == kEmpty) return nullptr;
  }
}

void FlatTable::grow() {
  std::vector<uint64_t> keys = std::move(keys_);
  std::vector<uint32_t> vals = std::move(vals_);
  const size_t cap = std::max<size_t>(1024, keys.size() * 2);
  keys_.assign(cap, kEmpty);
  vals_.assign(cap, 0);
  size_ = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (keys[i] == kEmpty) continue;
    bool ins = false;
    find_or_insert(keys[i], ins) = vals[i];
  }
}

void FlatTable::clear() {
  recent_.fill(kEmpty);
  if (size_ == 0) return;
  std::fill(keys_.begin(), keys_.end(), kEmpty);
  size_ = 0;
}

// --- ReuseDistance ------------------------------------------------------------------------------

void ReuseDistance::add(uint32_t t, int d) {
  for (size_t i = t + 1; i < tree_.size(); i += i & (~i + 1)) tree_[i] += d;
}

uint32_t ReuseDistance::prefix(uint32_t t) const {
  int64_t s = 0;
  for (size_t i = t; i > 0; i -= i & (~i + 1)) s += tree_[i];
  return static_cast<uint32_t>(s);
}

// Renumbers the live lines' last uses 0..live-1 in order (stack distances only depend on the
// order), doubling the tree when more than half of it would stay in use.
void ReuseDistance::compact() {
  std::vector<std::pair<uint32_t, uint32_t*>> live;
  live.reserve(last_.size());
  last_.for_each([&](uint64_t, uint32_t& t) { live.emplace_back(t, &t); });
  std::sort(live.begin(), live.end());
  size_t n = tree_.empty() ? 0 : tree_.size() - 1;
  if (n == 0) n = 4096;
  while (live.size() * 4 > n) n *= 2;  // at least 3/4 of the tree free: few compactions
  for (size_t i = 0; i < live.size(); ++i) *live[i].second = static_cast<uint32_t>(i);
  tree_.assign(n + 1, 0);
  for (size_t i = 1; i <= n; ++i) {
    if (i - 1 < live.size()) tree_[i] += 1;
    const size_t j = i + (i & (~i + 1));
    if (j <= n) tree_[j] += tree_[i];
  }
  now_ = static_cast<uint32_t>(live.size());
  live_ = now_;
}

void ReuseDistance::use(uint64_t line) {
  ++uses;
  if (line == last_line_) {
    ++hist[0];  // the latest line again: distance 0, and the order of last uses is unchanged
    return;
  }
  if (tree_.empty() || now_ + 1 >= tree_.size()) compact();
  uint32_t* last = last_.find(line);
  if (last == nullptr) {
    if (last_.size() >= kMaxLines) {
      ++untracked;
      return;
    }
    ++first_uses;
    last_line_ = line;
    bool ins = false;
    last_.find_or_insert(line, ins) = now_;
  } else {
    // Lines used since the last use of this one: the marks after its time.
    const uint32_t d = live_ - prefix(*last + 1);
    ++hist[static_cast<size_t>(std::bit_width(d))];
    add(*last, -1);
    --live_;
    *last = now_;
    last_line_ = line;
  }
  add(now_, 1);
  ++live_;
  ++now_;
}

void ReuseDistance::reset() {
  last_.clear();
  std::fill(tree_.begin(), tree_.end(), 0);
  now_ = live_ = 0;
  last_line_ = ~uint64_t{0};
  hist.fill(0);
  uses = first_uses = untracked = 0;
}

// --- WorkloadStats ------------------------------------------------------------------------------

WorkloadStats::WorkloadStats(std::vector<WorkloadTexture> textures)
    : textures_(std::move(textures)), touched_(textures_.size(), 0) {
  // The end of the address space: every layout's last texel is the one at (w-1, h-1).
  uint64_t end = 0;
  for (const WorkloadTexture& t : textures_) {
    for (size_t l = 0; l < t.levels.size(); ++l) {
      const Texture::Level& lv = t.levels[l];
      end = std::max(end, t.address(static_cast<int>(l), lv.width - 1, lv.height - 1) +
                              static_cast<uint64_t>(t.bytes_per_texel));
    }
  }
  texels0_.resize(end / 4 + 1);
  texels_.resize(end / 4 + 1);
  for (size_t k = 0; k < 3; ++k)
    lines_[k].resize(end / static_cast<uint64_t>(FrameWorkload::kLineBytes[k]) + 1);
}

namespace {

// Texel column (row) of the bilinear footprint's first texel at coordinate u of a level of
// `size` texels, wrapped into the level.
int wrapped_first(double u, int size) {
  double s = std::floor(u * size - 0.5);
  if (s >= 0 && s < size) return static_cast<int>(s);
  if (!std::isfinite(s)) return 0;
  s = std::fmod(s, static_cast<double>(size));
  if (s < 0) s += size;
  return static_cast<int>(s);
}

// The footprint's four texel addresses at `level`.
std::array<uint64_t, 4> footprint(const WorkloadTexture& t, int level, double u, double v) {
  const Texture::Level& lv = t.levels[static_cast<size_t>(level)];
  const int x0 = wrapped_first(u, lv.width), y0 = wrapped_first(v, lv.height);
  const int x1 = x0 + 1 == lv.width ? 0 : x0 + 1, y1 = y0 + 1 == lv.height ? 0 : y0 + 1;
  return {t.address(level, x0, y0), t.address(level, x1, y0), t.address(level, x0, y1),
          t.address(level, x1, y1)};
}

}  // namespace

void WorkloadStats::add(const Fragment& f, uint32_t tex) {
  if (!open_ || f.frame != cur_.frame) {
    if (open_) close_frame();
    cur_ = FrameWorkload{};
    cur_.frame = f.frame;
    open_ = true;
  }
  // A quad: consecutive fragments of one frame, primitive and 2x2 pixel block (QuadAssembler).
  if (cur_.fragments == 0 || f.prim != qprim_ || (f.x >> 1) != qx_ || (f.y >> 1) != qy_)
    ++cur_.quads;
  qprim_ = f.prim;
  qx_ = f.x >> 1;
  qy_ = f.y >> 1;
  ++cur_.fragments;
  if (tex >= textures_.size()) return;  // not characterised (callers check ids first)
  if (!touched_[tex]) {
    touched_[tex] = 1;
    ++cur_.textures;
  }
  const WorkloadTexture& t = textures_[tex];
  const double w = t.levels[0].width, h = t.levels[0].height;

  // λ and η from the derivatives in level-0 texels.
  double lambda = 0;
  int aniso = 0;
  const double mux = f.dudx * w, mvx = f.dvdx * h, muy = f.dudy * w, mvy = f.dvdy * h;
  const double px2 = mux * mux + mvx * mvx, py2 = muy * muy + mvy * mvy;
  if (std::isfinite(px2) && std::isfinite(py2)) {
    const double rmax2 = std::max(px2, py2), rmin2 = std::min(px2, py2);
    lambda = 0.5 * std::log2(rmax2) + f.lod_bias;  // -inf for a point footprint
    if (rmax2 > 0) {
      // log2 η rounded: η² against 2^(2k+1), the squares of the bins' edges 2^(k+½).
      static constexpr double kEdges2[] = {2, 8, 32, 128, 512};
      const double ratio2 = rmin2 == 0 ? HUGE_VAL : rmax2 / rmin2;
      while (aniso < FrameWorkload::kAnisoBins - 1 && ratio2 >= kEdges2[aniso]) ++aniso;
    }
    const double area = std::abs(mux * mvy - mvx * muy);
    if (std::isfinite(area)) cur_.footprint_texels += area;
  } else {
    lambda = f.lod_bias;
  }
  if (std::isnan(lambda)) lambda = 0;
  ++cur_.aniso[static_cast<size_t>(aniso)];
  if (lambda < FrameWorkload::kLodLo) {
    ++cur_.lod_under;
  } else if (lambda >= FrameWorkload::kLodLo + FrameWorkload::kLodStep * FrameWorkload::kLodBins) {
    ++cur_.lod_over;
  } else {
    const int b = static_cast<int>((lambda - FrameWorkload::kLodLo) / FrameWorkload::kLodStep);
    ++cur_.lod[static_cast<size_t>(std::min(b, FrameWorkload::kLodBins - 1))];
  }
  ++(lambda < 0 ? cur_.magnified : cur_.minified);

  for (uint64_t a : footprint(t, 0, f.u, f.v)) texels0_.set(a / 4);
  const int top = static_cast<int>(t.levels.size()) - 1;
  const int level =
      lambda <= 0 ? 0 : (lambda >= top ? top : static_cast<int>(std::floor(lambda + 0.5)));
  const std::array<uint64_t, 4> a = footprint(t, std::min(level, top), f.u, f.v);
  for (uint64_t x : a) texels_.set(x / 4);
  for (size_t k = 0; k < FrameWorkload::kLineBytes.size(); ++k) {
    const auto bytes = static_cast<uint64_t>(FrameWorkload::kLineBytes[k]);
    for (size_t i = 0; i < 4; ++i) {
      const uint64_t line = a[i] / bytes;
      bool seen = false;  // the fragment's texels in one line are one use
      for (size_t j = 0; j < i; ++j) seen = seen || a[j] / bytes == line;
      if (seen) continue;
      lines_[k].set(line);
      if (FrameWorkload::kLineBytes[k] == FrameWorkload::kReuseLineBytes) reuse_.use(line);
    }
  }
}

void WorkloadStats::close_frame() {
  cur_.texels_level0 = texels0_.count();
  cur_.texels_lod = texels_.count();
  for (size_t k = 0; k < 3; ++k) cur_.lines[k] = lines_[k].count();
  cur_.line_uses = reuse_.uses;
  cur_.first_uses = reuse_.first_uses;
  cur_.untracked_uses = reuse_.untracked;
  cur_.reuse = reuse_.hist;
  frames_.push_back(cur_);
  texels0_.clear();
  texels_.clear();
  for (Bitmap& l : lines_) l.clear();
  reuse_.reset();
  std::fill(touched_.begin(), touched_.end(), 0);
  open_ = false;
}

void WorkloadStats::finish() {
  if (open_) close_frame();
}

FrameWorkload WorkloadStats::total() const {
  FrameWorkload s;
  if (!frames_.empty()) s.frame = frames_.front().frame;
  for (const FrameWorkload& f : frames_) {
    s.fragments += f.fragments;
    s.quads += f.quads;
    s.textures += f.textures;
    s.texels_level0 += f.texels_level0;
    s.texels_lod += f.texels_lod;
    for (size_t k = 0; k < s.lines.size(); ++k) s.lines[k] += f.lines[k];
    for (size_t k = 0; k < s.lod.size(); ++k) s.lod[k] += f.lod[k];
    s.lod_under += f.lod_under;
    s.lod_over += f.lod_over;
    for (size_t k = 0; k < s.aniso.size(); ++k) s.aniso[k] += f.aniso[k];
    s.magnified += f.magnified;
    s.minified += f.minified;
    s.footprint_texels += f.footprint_texels;
    s.line_uses += f.line_uses;
    s.first_uses += f.first_uses;
    s.untracked_uses += f.untracked_uses;
    for (size_t k = 0; k < s.reuse.size(); ++k) s.reuse[k] += f.reuse[k];
  }
  return s;
}

std::string WorkloadStats::layout() const {
  return textures_.empty() ? "tiled4x4" : to_string(textures_.front().layout);
}

}  // namespace texsim
