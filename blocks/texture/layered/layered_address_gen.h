#pragma once
// Texel address generator of layered textures (docs/texture-types.md): cube maps and cube
// arrays (the face's coordinates from CubeFaceSelect, seamless or per-face addressing), and
// 1-D / 2-D arrays (the layer, then the 2-D address generator's taps on that layer's mip
// chain). It uses the material's TexelAddressGen for its configuration (filter, address modes,
// border, offsets, precisions) and level selection, so a layered texture filters as a 2-D one
// does on each slice; what it adds is the slice and, for a cube, the edge unit (CubeSeam).
#include <algorithm>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/texture/layered/cube_face_select.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

class LayeredAddressGen {
 public:
  // `seamless` false: each face is addressed on its own with the sampler's address modes
  // (VK_EXT_non_seamless_cube_map); true: taps across an edge read the neighbouring face.
  LayeredAddressGen(const TexelAddressGen& base, bool seamless)
      : base_(base), seamless_(seamless) {}
  bool seamless() const { return seamless_; }

  // Vulkan "Array Layer Selection": layer = clamp(RNE(a), 0, d − 1), with round-to-nearest-even
  // (the spec's RNE); a non-finite a selects layer 0.
  static int select_layer(float a, int layers);

  // The taps of a cube (cube array: cube index `cube`, already selected) at face coordinate
  // `c`, with λ and probes from the LOD unit on the face's derivatives. Anisotropic probes
  // stay on the face (their centres clamped to it). A corner tap becomes three taps of a third
  // of its weight. Writes out.count; no border taps (a seamless cube has no border; a
  // non-seamless one with the border mode has them as a 2-D texture does).
  // Returns the taps read from another face than c.face (the edge unit's work).
  int cube_taps(const Texture& tex, const CubeFaceCoord& c, int cube, const LodResult& lod,
                FilterTaps& out) const;
  // The taps of an array texture at (u, v) on `layer` (already selected).
  void array_taps(const Texture& tex, double u, double v, int layer, const LodResult& lod,
                  FilterTaps& out) const;

  // Probes of a cube fragment: the LOD unit's, at most kMaxCubeProbes (a probe's quads make up
  // to 6 taps each with a corner, and FilterTaps holds 128).
  static constexpr int kMaxCubeProbes = 10;
  static int cube_probes(const LodResult& lod) {
    return std::min(static_cast<int>(TexelAddressGen::issue_cycles(lod)), kMaxCubeProbes);
  }

  // Operations of the edge unit per tap it resolves on another face.
  static OpCounts ops_per_edge_tap();

 private:
  // One probe on `slice` at (u, v) with weight w (nearest, or a linear quad on one level).
  TexelTap* emit(const Texture& tex, int slice, int32_t mip, float u, float v, float w, bool cube,
                 TexelTap* t) const;
  TexelTap* emit_cube_linear(const Texture& tex, int cube, int face, int32_t mip, float s, float t,
                             float w, TexelTap* out) const;
  void finish(const Texture& tex, FilterTaps& out, TexelTap* t) const;
  const TexelAddressGen& base_;
  bool seamless_;
};

}  // namespace texsim
