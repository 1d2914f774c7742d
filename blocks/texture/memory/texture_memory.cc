#include "blocks/texture/memory/texture_memory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "blocks/texture/volume/volume_address_gen.h"

namespace texsim {

const char* to_string(TexelFormat f) { return f == TexelFormat::Rgba8 ? "rgba8" : "rgba32f"; }
const char* to_string(TexelLayout l) {
  switch (l) {
    case TexelLayout::Linear:
      return "linear";
    case TexelLayout::Tiled4x4:
      return "tiled4x4";
    case TexelLayout::Morton:
      return "morton";
  }
  return "?";
}
const char* to_string(TextureType t) {
  switch (t) {
    case TextureType::Tex2D:
      return "2d";
    case TextureType::Cube:
      return "cube";
    case TextureType::Array:
      return "array";
    case TextureType::Volume:
      return "3d";
  }
  return "?";
}

const char* to_string(AddressMode m) {
  switch (m) {
    case AddressMode::Wrap:
      return "wrap";
    case AddressMode::Clamp:
      return "clamp";
    case AddressMode::Mirror:
      return "mirror";
    case AddressMode::Border:
      return "border";
    case AddressMode::MirrorClamp:
      return "mirror_clamp";
  }
  return "?";
}

namespace {

// 2x2 box filter to floor(w/2) x floor(h/2) (at least 1); odd edges clamp.
std::vector<float> downsample(const std::vector<float>& src, int w, int h, int& nw, int& nh) {
  nw = std::max(1, w / 2);
  nh = std::max(1, h / 2);
  std::vector<float> dst(static_cast<size_t>(nw) * nh * 4);
  for (int y = 0; y < nh; ++y) {
    for (int x = 0; x < nw; ++x) {
      const int x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
      const int y0 = std::min(2 * y, h - 1), y1 = std::min(2 * y + 1, h - 1);
      for (int c = 0; c < 4; ++c) {
        auto at = [&](int xx, int yy) { return src[(static_cast<size_t>(yy) * w + xx) * 4 + c]; };
        dst[(static_cast<size_t>(y) * nw + x) * 4 + c] =
            0.25f * (at(x0, y0) + at(x1, y0) + at(x0, y1) + at(x1, y1));
      }
    }
  }
  return dst;
}

// 2×2×2 box filter of a volume's z-slices to the next 3-D mip (each axis ⌊n/2⌋, at least 1;
// odd edges clamp); `size` becomes the new size.
std::vector<std::vector<float>> downsample_volume(const std::vector<std::vector<float>>& src,
                                                  VolumeSize& size) {
  const VolumeSize n = VolumeAddressGen::level_size(size, 1);
  std::vector<std::vector<float>> dst;
  dst.reserve(static_cast<size_t>(n.depth));
  for (int z = 0; z < n.depth; ++z) {
    int nw = 0, nh = 0;
    const auto z0 = static_cast<size_t>(std::min(2 * z, size.depth - 1));
    const auto z1 = static_cast<size_t>(std::min(2 * z + 1, size.depth - 1));
    std::vector<float> a = downsample(src[z0], size.width, size.height, nw, nh);
    const std::vector<float> b = downsample(src[z1], size.width, size.height, nw, nh);
    for (size_t i = 0; i < a.size(); ++i) a[i] = 0.5f * (a[i] + b[i]);
    dst.push_back(std::move(a));
  }
  size = n;
  return dst;
}

}  // namespace

int Texture::add_mip_chain(int w, int h, const std::vector<float>& rgba, bool build_mips) {
  int n = 1;
  add_level(w, h, rgba);
  std::vector<float> cur;  // the last level made (level 0 is read from rgba, not copied)
  while (build_mips && (w > 1 || h > 1)) {
    int nw = 0, nh = 0;
    cur = downsample(cur.empty() ? rgba : cur, w, h, nw, nh);
    w = nw;
    h = nh;
    add_level(w, h, cur);
    ++n;
  }
  return n;
}

void Texture::add_level(int w, int h, const std::vector<float>& rgba) {
  Level lv;
  lv.width = w;
  lv.height = h;
  const size_t texels = static_cast<size_t>(w) * static_cast<size_t>(h);
  const size_t n = texels * 4;
  if (rgba.size() < n) throw std::invalid_argument("texture level data smaller than its size");
  lv.first = levels_.empty()
                 ? 0
                 : levels_.back().first + static_cast<size_t>(levels_.back().width) *
                                              static_cast<size_t>(levels_.back().height);
  if (format_ == TexelFormat::Rgba8) {
    rgba8_.resize(rgba8_.size() + n);
    uint8_t* out = rgba8_.data() + lv.first * 4;
    for (size_t i = 0; i < n; ++i) {
      const float c = std::clamp(rgba[i], 0.0f, 1.0f) * 255.0f;
      if (!(c == c)) {  // NaN: 0, as lround's result cast to 8 bits was on x86-64
        out[i] = 0;
        continue;
      }
      // Nearest, halves up: std::lround for c in [0, 255] without the library call (c minus
      // its integer part is exact in float).
      const int whole = static_cast<int>(c);
      out[i] = static_cast<uint8_t>(whole + (c - static_cast<float>(whole) >= 0.5f ? 1 : 0));
    }
  } else {
    rgba32f_.insert(rgba32f_.end(), rgba.begin(), rgba.begin() + static_cast<std::ptrdiff_t>(n));
  }
  levels_.push_back(lv);
}

Texture Texture::from_rgba(std::string name, int width, int height, const std::vector<float>& rgba,
                           TexelFormat format, bool build_mips) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("texture size must be positive");
  Texture t;
  t.name_ = std::move(name);
  t.set_store(format);
  if (format == TexelFormat::Rgba8) {
    // Every level's bytes in one allocation (the chain is at most 4/3 of level 0).
    size_t total = 0;
    for (int lw = width, lh = height;; lw = std::max(1, lw / 2), lh = std::max(1, lh / 2)) {
      total += static_cast<size_t>(lw) * static_cast<size_t>(lh) * 4;
      if (!build_mips || (lw == 1 && lh == 1)) break;
    }
    t.rgba8_.reserve(total);
  }
  t.add_mip_chain(width, height, rgba, build_mips);
  t.place(0, TexelLayout::Linear);
  return t;
}

Texture Texture::from_slices(std::string name, TextureType type, int width, int height,
                             const std::vector<std::vector<float>>& slices, TexelFormat format,
                             bool build_mips) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("texture size must be positive");
  if (slices.empty()) throw std::invalid_argument("a layered texture needs at least one slice");
  if (type == TextureType::Cube && (slices.size() % 6 != 0 || width != height))
    throw std::invalid_argument("a cube texture needs 6 square faces per cube");
  const size_t texels = static_cast<size_t>(width) * static_cast<size_t>(height) * 4;
  Texture t;
  t.name_ = std::move(name);
  t.set_store(format);
  int mips = 0;
  for (const auto& rgba : slices) {
    if (rgba.size() != texels) throw std::invalid_argument("slice size disagrees");
    mips = t.add_mip_chain(width, height, rgba, build_mips);
  }
  t.shape_ = {type, static_cast<int>(slices.size()), mips};
  t.place(0, TexelLayout::Linear);
  return t;
}

Texture Texture::from_volume(std::string name, int width, int height,
                             const std::vector<std::vector<float>>& slices, TexelFormat format,
                             bool build_mips) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("texture size must be positive");
  if (slices.empty()) throw std::invalid_argument("a 3-D texture needs at least one slice");
  const size_t texels = static_cast<size_t>(width) * static_cast<size_t>(height) * 4;
  for (const auto& rgba : slices)
    if (rgba.size() != texels) throw std::invalid_argument("slice size disagrees");
  Texture t;
  t.name_ = std::move(name);
  t.set_store(format);
  VolumeSize size{width, height, static_cast<int>(slices.size())};
  std::vector<std::vector<float>> cur = slices;
  for (;;) {
    t.volume_first_.push_back(t.levels());
    for (const auto& rgba : cur) t.add_level(size.width, size.height, rgba);
    if (!build_mips || (size.width == 1 && size.height == 1 && size.depth == 1)) break;
    cur = downsample_volume(cur, size);
  }
  t.shape_ = {TextureType::Volume, static_cast<int>(slices.size()),
              static_cast<int>(t.volume_first_.size())};
  t.place(0, TexelLayout::Linear);
  return t;
}

uint64_t Texture::volume_address(int mip, int x, int y, int z) const {
  const auto m = static_cast<size_t>(mip);
  const Level& lv = levels_[static_cast<size_t>(volume_first_[m])];
  const VolumeSize s{lv.width, lv.height, volume_depth(mip)};
  return base_ + volume_offset_[m] +
         VolumeAddressGen::texel_index(layout_, s, x, y, z) *
             static_cast<uint64_t>(bytes_per_texel());
}

Texture Texture::from_levels(std::string name, const std::vector<int>& widths,
                             const std::vector<int>& heights,
                             const std::vector<std::vector<float>>& levels, TexelFormat format) {
  if (levels.empty() || widths.size() != levels.size() || heights.size() != levels.size()) {
    throw std::invalid_argument("texture level lists disagree");
  }
  Texture t;
  t.name_ = std::move(name);
  t.set_store(format);
  for (size_t i = 0; i < levels.size(); ++i) {
    if (widths[i] <= 0 || heights[i] <= 0) throw std::invalid_argument("bad level size");
    t.add_level(widths[i], heights[i], levels[i]);
  }
  t.place(0, TexelLayout::Linear);
  return t;
}

void Texture::set_store(TexelFormat format) {
  format_ = format;
  storage_ = format == TexelFormat::Rgba8 ? StorageFormat::Rgba8Unorm : StorageFormat::Rgba32f;
  bytes_per_texel_ = format_info(storage_).bytes;
}

Texture Texture::converted(StorageFormat storage) const {
  Texture t;
  t.name_ = name_;
  t.shape_ = shape_;
  t.volume_first_ = volume_first_;
  t.set_store(decodes_to_bytes(storage) ? TexelFormat::Rgba8 : TexelFormat::Rgba32f);
  t.storage_ = storage;
  t.bytes_per_texel_ = format_info(storage).bytes;
  std::vector<float> px;
  for (int l = 0; l < levels(); ++l) {
    const int w = width(l), h = height(l);
    px.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const glm::vec4 c = convert_texel(storage, texel(l, x, y));
        float* d =
            &px[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4];
        for (int k = 0; k < 4; ++k) d[k] = c[k];
      }
    }
    t.add_level(w, h, px);
  }
  if (format_info(storage).coding == ChannelCoding::Srgb) {
    // The texels mean sRGB-encoded colours: the truth is their linear value, decoded without
    // the format's 8-bit step.
    t.reference_ = std::make_shared<const Texture>(reference().linearised());
  } else {
    t.reference_ = std::make_shared<const Texture>(reference());
  }
  t.place(base_, layout_);
  return t;
}

Texture Texture::linearised() const {
  Texture t;
  t.name_ = name_;
  t.shape_ = shape_;
  t.volume_first_ = volume_first_;
  t.set_store(TexelFormat::Rgba32f);
  std::vector<float> px;
  for (int l = 0; l < levels(); ++l) {
    const int w = width(l), h = height(l);
    px.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const glm::vec4 c = texel(l, x, y);
        float* d =
            &px[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4];
        for (int k = 0; k < 3; ++k) d[k] = srgb_eotf(c[k]);
        d[3] = c[3];
      }
    }
    t.add_level(w, h, px);
  }
  t.place(base_, layout_);
  return t;
}

Texture Texture::srgb_stored(bool decode_after_filter) const {
  if (storage_ != StorageFormat::Srgb8A8 || decode_after_filter == srgb_after_filter_) return *this;
  Texture t;
  t.name_ = name_;
  t.shape_ = shape_;
  t.volume_first_ = volume_first_;
  t.set_store(decode_after_filter ? TexelFormat::Rgba8 : TexelFormat::Rgba32f);
  t.storage_ = storage_;
  t.bytes_per_texel_ = bytes_per_texel_;
  t.srgb_after_filter_ = decode_after_filter;
  t.reference_ = reference_;
  std::vector<float> px;
  for (int l = 0; l < levels(); ++l) {
    const int w = width(l), h = height(l);
    px.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    for (size_t i = 0; i < px.size(); i += 4) {
      const size_t x = (i / 4) % static_cast<size_t>(w), y = (i / 4) / static_cast<size_t>(w);
      const Rgba c = texel(l, static_cast<int>(x), static_cast<int>(y));
      // Codes and linear values map one to one (srgb_code inverts the EOTF's table exactly);
      // alpha is c / 255 either way.
      for (int k = 0; k < 3; ++k) {
        px[i + static_cast<size_t>(k)] =
            decode_after_filter ? static_cast<float>(srgb_code(c[k])) / 255.0f
                                : srgb_to_linear(static_cast<uint8_t>(std::lround(c[k] * 255.0f)));
      }
      px[i + 3] = c[3];
    }
    t.add_level(w, h, px);
  }
  t.place(base_, layout_);
  return t;
}

void Texture::set_blocks(std::shared_ptr<const Blocks> blocks) {
  blocks_ = std::move(blocks);
  bytes_per_texel_ = format_info(blocks_->format).decoded_bytes;
  block_levels_.clear();
  const CompressedFormatInfo& f = format_info(blocks_->format);
  for (const Level& lv : levels_) {
    Level b;
    b.width = (lv.width + f.block_w - 1) / f.block_w;
    b.height = (lv.height + f.block_h - 1) / f.block_h;
    block_levels_.push_back(b);
  }
  place(base_, layout_);
}

namespace {
// Texels (or blocks) a level of w × h takes under `layout`, padding included.
uint64_t stored_units(TexelLayout layout, uint64_t w, uint64_t h) {
  switch (layout) {
    case TexelLayout::Linear:
      return w * h;
    case TexelLayout::Tiled4x4:
      return ((w + 3) / 4) * ((h + 3) / 4) * 16;
    case TexelLayout::Morton: {
      uint64_t s = 1;
      while (s < std::max(w, h)) s <<= 1;
      return s * s;
    }
  }
  return 0;
}

// The (x, y) whose index under `layout` is `i` in a level of w × h; false in the padding.
bool position_of(TexelLayout layout, uint64_t i, int w, int h, int& x, int& y) {
  switch (layout) {
    case TexelLayout::Linear:
      x = static_cast<int>(i % static_cast<uint64_t>(w));
      y = static_cast<int>(i / static_cast<uint64_t>(w));
      break;
    case TexelLayout::Tiled4x4: {
      const uint64_t tiles_x = (static_cast<uint64_t>(w) + 3) / 4, tile = i / 16, in = i % 16;
      x = static_cast<int>((tile % tiles_x) * 4 + (in & 3));
      y = static_cast<int>((tile / tiles_x) * 4 + (in >> 2));
      break;
    }
    case TexelLayout::Morton: {
      auto squeeze = [](uint64_t v) {  // the even bits of v, packed
        v &= 0x5555555555555555ULL;
        v = (v | (v >> 1)) & 0x3333333333333333ULL;
        v = (v | (v >> 2)) & 0x0f0f0f0f0f0f0f0fULL;
        v = (v | (v >> 4)) & 0x00ff00ff00ff00ffULL;
        v = (v | (v >> 8)) & 0x0000ffff0000ffffULL;
        v = (v | (v >> 16)) & 0x00000000ffffffffULL;
        return v;
      };
      x = static_cast<int>(squeeze(i));
      y = static_cast<int>(squeeze(i >> 1));
      break;
    }
  }
  return x < w && y < h;
}
}  // namespace

bool Texture::texel_at(uint64_t addr, int& level, int& x, int& y) const {
  if (addr < base_) return false;
  const uint64_t rel = addr - base_;
  for (int l = levels() - 1; l >= 0; --l) {
    const Level& lv = levels_[static_cast<size_t>(l)];
    if (rel < lv.offset) continue;
    level = l;
    return position_of(layout_, (rel - lv.offset) / static_cast<uint64_t>(bytes_per_texel_),
                       lv.width, lv.height, x, y);
  }
  return false;
}

uint64_t Texture::place_blocks(uint64_t base) {
  block_base_ = base;
  uint64_t off = 0;
  const auto bytes = static_cast<uint64_t>(format_info(blocks_->format).block_bytes);
  for (Level& b : block_levels_) {
    b.offset = off;
    off += (stored_units(layout_, static_cast<uint64_t>(b.width), static_cast<uint64_t>(b.height)) *
                bytes +
            255) &
           ~uint64_t{255};
  }
  return off;
}

uint64_t Texture::place(uint64_t base, TexelLayout layout) {
  base_ = base;
  layout_ = layout;
  uint64_t off = 0;
  if (volume()) {
    // Each 3-D mip as one block of its layout's texel slots (VolumeAddressGen::level_texels);
    // a z-slice's level starts where its first texel is (linear) or at its mip (others).
    volume_offset_.assign(volume_first_.size(), 0);
    for (size_t m = 0; m < volume_first_.size(); ++m) {
      const Level& first = levels_[static_cast<size_t>(volume_first_[m])];
      const VolumeSize s{first.width, first.height, volume_depth(static_cast<int>(m))};
      volume_offset_[m] = off;
      for (int z = 0; z < s.depth; ++z)
        levels_[static_cast<size_t>(volume_first_[m]) + static_cast<size_t>(z)].offset = off;
      const uint64_t texels = VolumeAddressGen::level_texels(layout, s);
      off += (texels * static_cast<uint64_t>(bytes_per_texel()) + 255) & ~uint64_t{255};
    }
    return off;
  }
  for (auto& lv : levels_) {
    lv.offset = off;
    const uint64_t texels =
        stored_units(layout, static_cast<uint64_t>(lv.width), static_cast<uint64_t>(lv.height));
    off += (texels * static_cast<uint64_t>(bytes_per_texel()) + 255) & ~uint64_t{255};
  }
  return off;
}

int TextureSet::add(Texture t) {
  textures_.push_back(std::move(t));
  place(layout_);
  return size() - 1;
}

void TextureSet::set_srgb_after_filter(bool after) {
  for (Texture& t : textures_) {
    if (t.storage() == StorageFormat::Srgb8A8 && t.srgb_after_filter() != after)
      t = t.srgb_stored(after);
  }
}

void TextureSet::place(TexelLayout layout) {
  layout_ = layout;
  uint64_t base = 0;
  for (auto& t : textures_) {
    const uint64_t used = t.place(base, layout);
    base += (used + 4095) & ~uint64_t{4095};  // each texture starts on a 4 KiB page
  }
  // Compressed textures' blocks after every texture's texels: a cache holding blocks and one
  // holding decoded texels never alias.
  for (auto& t : textures_) {
    if (!t.compressed()) continue;
    const uint64_t used = t.place_blocks(base);
    base += (used + 4095) & ~uint64_t{4095};
  }
}

const Texture* TextureSet::holding(uint64_t addr) const {
  // Textures are placed in order, so the last one starting at or below addr holds it.
  const Texture* found = nullptr;
  for (const auto& t : textures_) {
    if (t.base() > addr) break;
    found = &t;
  }
  return found;
}

}  // namespace texsim
