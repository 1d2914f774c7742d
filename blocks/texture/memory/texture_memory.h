#pragma once
// Texture memory: mip pyramids of RGBA8 or float texels, and the byte address of every texel
// under a linear, 4x4-tiled or Morton layout (what the texture cache sees). docs/architecture.md.
#include <cstdint>
#include <glm/vec4.hpp>
#include <memory>
#include <string>
#include <vector>

#include "blocks/texture/decode/compressed_format.h"
#include "blocks/texture/memory/storage_format.h"

namespace texsim {

using Rgba = glm::vec4;  // colour in [0,1] (RGBA8) or any float (RGBA32F)

// The store the unit reads texels from: 8-bit channels or floats. What a texel takes in
// simulated memory is the texture's StorageFormat (storage_format.h).
enum class TexelFormat { Rgba8, Rgba32f };
enum class TexelLayout { Linear, Tiled4x4, Morton };
// Vulkan REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT, CLAMP_TO_BORDER, MIRROR_CLAMP_TO_EDGE (the
// order of the scenes' choice lists: "wrap", "clamp", "mirror", "border", "mirror_clamp").
enum class AddressMode { Wrap, Clamp, Mirror, Border, MirrorClamp };

// What a texture's levels hold (docs/texture-types.md). A 2-D texture's levels are its mip
// chain. A layered texture (cube, cube array, 1-D or 2-D array) holds slices, each with its own
// mip chain, slice after slice: level index = slice · mips + mip, so a slice's chain is
// contiguous in memory (a cube's slice = 6 · cube + face, faces in Vulkan's order +X −X +Y −Y
// +Z −Z). A 1-D array is a 2-D array of height-1 slices. A 3-D texture (Volume) holds its
// 3-D mips one after another, each as its depth's z-slices (levels volume_level(mip, z), each
// the mip's width × height); a mip halves all three sizes (at least 1), and its texels'
// addresses follow the layout in 3-D (volume_address(): linear, 4×4×4 bricks, 3-D Morton).
enum class TextureType : uint8_t { Tex2D, Cube, Array, Volume };
struct TextureShape {
  TextureType type = TextureType::Tex2D;
  int slices = 1;  // layers (arrays), 6 × cubes (cube maps), level 0's depth (volumes)
  int mips = 0;    // levels per slice (3-D mips of a volume); 0: all levels (a 2-D texture)
};

const char* to_string(TexelFormat f);
const char* to_string(TexelLayout l);
const char* to_string(AddressMode m);
const char* to_string(TextureType t);

class Texture {
 public:
  struct Level {
    int width = 0;
    int height = 0;
    uint64_t offset = 0;  // byte offset of the level inside the texture (simulated memory)
    size_t first = 0;     // index of its first texel in the texture's texel store
  };

  // Builds a texture from level-0 float RGBA texels (row-major, 4 floats per texel).
  // With `build_mips`, the pyramid is made by 2x2 box filtering down to 1x1 (sizes
  // floor(w/2), as Vulkan); texels are stored in `format` (Rgba8 rounds to nearest).
  static Texture from_rgba(std::string name, int width, int height, const std::vector<float>& rgba,
                           TexelFormat format, bool build_mips);
  // A layered texture (TextureShape): `slices` images of width × height float RGBA texels, each
  // given its own mip chain (with `build_mips`, by the same box filter, faces filtered on
  // their own), stored slice after slice.
  static Texture from_slices(std::string name, TextureType type, int width, int height,
                             const std::vector<std::vector<float>>& slices, TexelFormat format,
                             bool build_mips);
  // A 3-D texture of `slices.size()` z-slices of width × height float RGBA texels; with
  // `build_mips`, its 3-D mip chain by a 2×2×2 box filter (odd edges clamp) down to 1×1×1.
  static Texture from_volume(std::string name, int width, int height,
                             const std::vector<std::vector<float>>& slices, TexelFormat format,
                             bool build_mips);
  // Builds a texture from a complete list of float RGBA levels (e.g. a .tx file's MIP chain).
  static Texture from_levels(std::string name, const std::vector<int>& widths,
                             const std::vector<int>& heights,
                             const std::vector<std::vector<float>>& levels, TexelFormat format);

  // The same texture stored in `storage` (storage_format.h): every texel of every level
  // converted by the format's rules (mips as they were built, each texel converted once). The
  // result keeps this texture as its reference(), the truth its accuracy is judged against.
  Texture converted(StorageFormat storage) const;
  // This texture with every colour channel taken through the sRGB EOTF (alpha kept), in
  // floats: the linear colours an sRGB texture means.
  Texture linearised() const;
  // An srgb8_a8 texture with its store for the sampler's sRGB decode placement
  // (docs/formats.md#srgb-decode-placement): the linear colours in floats (before the filter,
  // the specification's rule), or the 8-bit sRGB codes (after it: the filter sums encoded
  // values and the unit decodes the result). Same storage, bytes and truth.
  Texture srgb_stored(bool decode_after_filter) const;
  // Whether the store holds sRGB codes that the unit decodes after filtering.
  bool srgb_after_filter() const { return srgb_after_filter_; }

  const std::string& name() const { return name_; }
  const TextureShape& shape() const { return shape_; }
  bool layered() const { return shape_.type != TextureType::Tex2D; }
  // Levels of one slice (all levels of a 2-D texture), and the level index of a slice's mip.
  int mips() const { return shape_.mips > 0 ? shape_.mips : levels(); }
  int slice_level(int slice, int mip) const { return slice * mips() + mip; }
  bool volume() const { return shape_.type == TextureType::Volume; }
  // A volume's level index of z-slice z of 3-D mip `mip` (its depth: volume_depth(mip)).
  int volume_level(int mip, int z) const { return volume_first_[static_cast<size_t>(mip)] + z; }
  int volume_depth(int mip) const {
    const auto m = static_cast<size_t>(mip);
    return (m + 1 < volume_first_.size() ? volume_first_[m + 1] : levels()) - volume_first_[m];
  }
  // Byte address of texel (x, y, z) of a volume's 3-D mip `mip` under its layout (after
  // place(); VolumeAddressGen::texel_index). A volume's texels are addressed only so:
  // address() does not know their z.
  uint64_t volume_address(int mip, int x, int y, int z) const;
  TexelFormat format() const { return format_; }
  StorageFormat storage() const { return storage_; }
  // The texture the ground truth samples: the one it was converted from, else itself.
  const Texture& reference() const { return reference_ ? *reference_ : *this; }
  int levels() const { return static_cast<int>(levels_.size()); }
  int width(int level) const { return levels_[level].width; }
  int height(int level) const { return levels_[level].height; }
  const Level& level(int l) const { return levels_[l]; }
  // Bytes of one texel in simulated memory (its storage format's).
  int bytes_per_texel() const { return bytes_per_texel_; }
  // The texels of every level in one store, level after level, each row-major with 4 channels
  // per texel (one store, so a gather with one base reaches every level). Only the store of
  // the texture's format is filled.
  const uint8_t* rgba8(int level) const { return rgba8_.data() + levels_[level].first * 4; }
  const float* rgba32f(int level) const { return rgba32f_.data() + levels_[level].first * 4; }

  // Texel at integer coordinates already inside the level (addressing applied upstream).
  Rgba texel(int level, int x, int y) const {
    const Level& lv = levels_[level];
    const size_t i = (lv.first + static_cast<size_t>(y) * lv.width + x) * 4;
    if (format_ == TexelFormat::Rgba8) {
      constexpr float k = 1.0f / 255.0f;
      return {static_cast<float>(rgba8_[i]) * k, static_cast<float>(rgba8_[i + 1]) * k,
              static_cast<float>(rgba8_[i + 2]) * k, static_cast<float>(rgba8_[i + 3]) * k};
    }
    return {rgba32f_[i], rgba32f_[i + 1], rgba32f_[i + 2], rgba32f_[i + 3]};
  }

  // A block-compressed texture's blocks as memory holds them (compressed_texture.h builds
  // such textures: the texel store then holds the decoded texels).
  struct Blocks {
    CompressedFormat format = CompressedFormat::Bc1Rgb;
    // Per level, the blocks row by row (ceil(w / block_w) × ceil(h / block_h) blocks).
    std::vector<std::vector<uint8_t>> levels;
    std::string provenance;  // the encoder and its options, or the file the blocks came from
  };
  // Marks this texture as decoded from `blocks`: bytes_per_texel() becomes the decoded
  // texel's bytes (what a cache holding decoded texels moves).
  void set_blocks(std::shared_ptr<const Blocks> blocks);
  // The texture the truth samples instead of this one (e.g. the texture a compressed one was
  // encoded from).
  void set_reference(std::shared_ptr<const Texture> reference) {
    reference_ = std::move(reference);
  }
  const Blocks* blocks() const { return blocks_.get(); }
  bool compressed() const { return blocks_ != nullptr; }
  // The blocks' own place in memory (set by TextureSet::place: after every texture's texels).
  uint64_t place_blocks(uint64_t base);
  // Byte address of the block holding texel (x, y) of `level`, blocks laid out by the
  // texture's layout over the level's grid of blocks.
  uint64_t block_address(int level, int x, int y) const {
    const CompressedFormatInfo& f = format_info(blocks_->format);
    const Level& bl = block_levels_[static_cast<size_t>(level)];
    return block_base_ + bl.offset +
           texel_index(layout_, bl, x / f.block_w, y / f.block_h) *
               static_cast<uint64_t>(f.block_bytes);
  }
  // The level holding byte `addr` of this texture's texel range and the texel there, or false
  // (an address past the level's texels, in its padding); used to find the blocks a line of
  // decoded texels needs.
  bool texel_at(uint64_t addr, int& level, int& x, int& y) const;

  // Lays the levels out in memory at `base` with `layout`; returns the bytes used.
  uint64_t place(uint64_t base, TexelLayout layout);
  uint64_t base() const { return base_; }
  TexelLayout layout() const { return layout_; }
  // Byte address of a texel (after place()).
  uint64_t address(int level, int x, int y) const {
    const Level& lv = levels_[level];
    return base_ + lv.offset + texel_index(lv, x, y) * static_cast<uint64_t>(bytes_per_texel());
  }

  // Index of a texel in the level's storage order under `layout` (inline: the cache model
  // computes one per texel read, and the layout switch is the same for a whole run). Every
  // layout's index is a sum of a row part and a column part, so the four texels of a 2x2
  // footprint need two of each.
  static uint64_t texel_index(TexelLayout layout, const Level& lv, int x, int y) {
    return row_index(layout, lv, y) + col_index(layout, x);
  }
  static uint64_t row_index(TexelLayout layout, const Level& lv, int y) {
    const auto uy = static_cast<uint64_t>(y);
    switch (layout) {
      case TexelLayout::Linear:
        return uy * static_cast<uint64_t>(lv.width);
      case TexelLayout::Tiled4x4: {
        // Row of 4x4 tiles (16 texels each), then the row inside the tile.
        const uint64_t tiles_x = (static_cast<uint64_t>(lv.width) + 3) / 4;
        return (uy >> 2) * tiles_x * 16 + (uy & 3) * 4;
      }
      case TexelLayout::Morton:
        return spread_bits(static_cast<uint32_t>(y)) << 1;
    }
    return 0;
  }
  static uint64_t col_index(TexelLayout layout, int x) {
    const auto ux = static_cast<uint64_t>(x);
    switch (layout) {
      case TexelLayout::Linear:
        return ux;
      case TexelLayout::Tiled4x4:
        return (ux >> 2) * 16 + (ux & 3);
      case TexelLayout::Morton:
        return spread_bits(static_cast<uint32_t>(x));  // bits disjoint from y's
    }
    return 0;
  }
  // Bits of v spread to the even bit positions (Morton interleave of one coordinate).
  static uint64_t spread_bits(uint32_t v) {
    uint64_t s = v;
    s = (s | (s << 16)) & 0x0000ffff0000ffffULL;
    s = (s | (s << 8)) & 0x00ff00ff00ff00ffULL;
    s = (s | (s << 4)) & 0x0f0f0f0f0f0f0f0fULL;
    s = (s | (s << 2)) & 0x3333333333333333ULL;
    s = (s | (s << 1)) & 0x5555555555555555ULL;
    return s;
  }

 private:
  uint64_t texel_index(const Level& lv, int x, int y) const {
    return texel_index(layout_, lv, x, y);
  }
  // Sets the store, and the storage format that is that store's own (RGBA8 UNORM, RGBA32F).
  void set_store(TexelFormat format);
  // Appends a level of w × h float RGBA texels (row-major) in the texture's format.
  void add_level(int w, int h, const std::vector<float>& rgba);
  // Level 0 from `rgba` (w × h), then, with build_mips, each box-filtered level down to 1 × 1;
  // returns the levels added.
  int add_mip_chain(int w, int h, const std::vector<float>& rgba, bool build_mips);

  std::string name_;
  TextureShape shape_;
  TexelFormat format_ = TexelFormat::Rgba8;
  StorageFormat storage_ = StorageFormat::Rgba8Unorm;
  int bytes_per_texel_ = 4;
  bool srgb_after_filter_ = false;
  std::shared_ptr<const Texture> reference_;  // set by converted()
  std::shared_ptr<const Blocks> blocks_;      // set by set_blocks()
  uint64_t block_base_ = 0;
  std::vector<Level> block_levels_;  // each level's grid of blocks and its offset
  TexelLayout layout_ = TexelLayout::Linear;
  uint64_t base_ = 0;
  std::vector<Level> levels_;
  std::vector<int> volume_first_;        // a volume's first level of each 3-D mip
  std::vector<uint64_t> volume_offset_;  // and the mip's byte offset (set by place())
  std::vector<uint8_t> rgba8_;           // Rgba8: 4 bytes per texel
  std::vector<float> rgba32f_;           // Rgba32f: 4 floats per texel
};

// All textures of a scene, placed one after another in one address space.
class TextureSet {
 public:
  int add(Texture t);  // returns the texture id
  void place(TexelLayout layout);
  int size() const { return static_cast<int>(textures_.size()); }
  const Texture& operator[](int id) const { return textures_[id]; }
  Texture& operator[](int id) { return textures_[id]; }
  TexelLayout layout() const { return layout_; }
  // The texture whose texel range starts at or below `addr` (the one holding it, if any).
  const Texture* holding(uint64_t addr) const;
  // Every srgb8_a8 texture stored for its decode before or after the filter (srgb_stored()).
  void set_srgb_after_filter(bool after);
  bool any_srgb() const {
    for (const auto& t : textures_)
      if (t.storage() == StorageFormat::Srgb8A8) return true;
    return false;
  }
  bool any_compressed() const {
    for (const auto& t : textures_)
      if (t.compressed()) return true;
    return false;
  }

 private:
  std::vector<Texture> textures_;
  TexelLayout layout_ = TexelLayout::Tiled4x4;
};

}  // namespace texsim
