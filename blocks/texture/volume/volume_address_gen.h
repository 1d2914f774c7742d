#pragma once
// 3-D texture addressing (Vulkan "Texel Selection" for VK_IMAGE_TYPE_3D; docs/texture-types.md
// §7): the level of detail from all three coordinates' screen derivatives, eight taps per
// level (i0 = ⌊u·w − ½⌋, j0 = ⌊v·h − ½⌋, k0 = ⌊r·d − ½⌋ and their +1 neighbours, each axis
// addressed by its own mode), trilinear across 3-D mips (levels halve all three sizes, at
// least 1), and the texel's place in memory under a linear, 4×4×4-brick or 3-D Morton layout.
// The texture unit's 3-D path (TextureUnit::process_volume) takes its taps from here, and the
// texture store its texels' addresses (Texture::volume_address).
#include <array>
#include <cstdint>

#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

struct VolumeSize {
  int width = 1, height = 1, depth = 1;
};

struct VolumeTap {
  int level = 0;
  int x = 0, y = 0, z = 0;  // inside the level; x < 0: a border tap (the border colour)
  float weight = 0;
};

class VolumeAddressGen {
 public:
  struct Config {
    FilterMode filter = FilterMode::Trilinear;
    AddressMode address_u = AddressMode::Wrap, address_v = AddressMode::Wrap,
                address_w = AddressMode::Wrap;
  };
  static constexpr int kMaxTaps = 16;  // two levels of eight
  using Taps = std::array<VolumeTap, kMaxTaps>;

  explicit VolumeAddressGen(const Config& c) : config_(c) {}

  // Size of level `level` of a volume whose level 0 is `base` (each axis ⌊·/2⌋, at least 1).
  static VolumeSize level_size(VolumeSize base, int level);
  // Levels of the full chain down to 1 × 1 × 1.
  static int level_count(VolumeSize base);
  // λ = log2 ρ, ρ = max(|∂(u,v,r)/∂x ⊙ size|, |∂(u,v,r)/∂y ⊙ size|) with level 0's size: the
  // footprint's three-dimensional extent (a 2-D footprint would leave ∂r out). Non-finite
  // derivatives are taken as 0; a zero footprint gives −∞ (magnified).
  static float lambda(const double ddx[3], const double ddy[3], VolumeSize base);
  // The taps of a sample at (u, v, r) with level of detail λ (clamped to the chain): nearest
  // gives one tap of level round(λ) (λ ≤ ½: level 0), bilinear eight taps of that level,
  // trilinear eight of each of ⌊λ⌋ and ⌊λ⌋ + 1 weighted by the fraction. Non-finite coordinates
  // are taken as 0. Returns the number of taps written.
  int taps(VolumeSize base, double u, double v, double r, float lambda, Taps& out) const;

  // Index of texel (x, y, z) in its level's storage order; the level then takes
  // level_texels(layout, size) texel slots (Morton pads each axis to a power of two).
  static uint64_t texel_index(TexelLayout layout, VolumeSize size, int x, int y, int z);
  static uint64_t level_texels(TexelLayout layout, VolumeSize size);

  // One texel coordinate under an address mode; −1 for a border texel.
  static int address(int64_t i, int size, AddressMode m);

 private:
  int level_taps(VolumeSize s, int level, double u, double v, double r, float weight,
                 VolumeTap* out) const;
  Config config_;
};

}  // namespace texsim
