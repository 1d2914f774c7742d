#pragma once
// Batched linear sampler: the functional datapath of a bilinear or trilinear material — LOD
// unit, level selection, quad addresses and weights, RGBA8 texel fetch and blend — over a batch
// of fragments at once, SIMD across fragments (Google Highway; the widest instruction set the
// CPU has is chosen at run time, so one binary runs on any x86-64).
//
// Bit-identical to the scalar blocks (LodUnit::eval, TexelAddressGen::select_levels and
// linear_quad, TexelBlend::blend_quads): the same float32 operations in the same order, no
// fused multiply-add; the fixed-point level from log2 in double where an error interval
// decides it, else by the scalar float32 arithmetic with the same libm log2f (the arithmetic
// is stated in linear_batch.cc and docs/architecture.md). A fragment the batch cannot treat the
// same way — a non-finite input, anisotropic N > 1, another texture, a coordinate of 2^(31 −
// sub_texel_bits) texels or more — is left undone (`done[i]` = 0) for the scalar path.
// test_linear_batch compares the two.
#include <cstddef>
#include <cstdint>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

// One batch's results, structure of arrays. Quad j of fragment i (j = 0, and j = 1 for the
// coarser level of trilinear) is level[j][i], columns x0/x1[j][i], rows y0/y1[j][i]: what the
// cache model looks up.
struct LinearBatch {
  static constexpr size_t kMax = 256;
  alignas(64) int32_t done[kMax];
  // Whether every fragment is done, and whether they all share one frame (Fragment::frame):
  // then the caller counts the batch at once.
  bool all_done = false;
  bool one_frame = false;
  alignas(64) int32_t level[2][kMax];
  alignas(64) int32_t x0[2][kMax];
  alignas(64) int32_t x1[2][kMax];
  alignas(64) int32_t y0[2][kMax];
  alignas(64) int32_t y1[2][kMax];
  alignas(64) float rgba[4 * kMax];  // colour of fragment i at 4i .. 4i + 3
  // With lines (filter() given a line size): the cache line of each tap, taps in quad order
  // (x0,y0) (x1,y0) (x0,y1) (x1,y1), quad 0 then quad 1, and which taps open a line no earlier
  // tap of the fragment uses (bit k for tap k): the distinct lines in order of first use.
  bool has_lines = false;
  alignas(64) int32_t line[8][kMax];
  alignas(64) int32_t first_use[kMax];
  Rgba colour(size_t i) const {
    return {rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2], rgba[4 * i + 3]};
  }
};

class LinearBatchSampler {
 public:
  // The material's LOD unit and address generator configurations (filter bilinear or
  // trilinear).
  LinearBatchSampler(const LodUnit::Config& lod, const TexelAddressGen::Config& addr);

  // Whether the batch serves texture `tex`: RGBA8, at most 32 levels, fewer than 2^31 texels,
  // and power-of-two level sizes along an axis that wraps or mirrors.
  bool serves(const Texture& tex) const;

  // Filters fragments f[0 .. n) (n <= LinearBatch::kMax) on `tex`, the texture of f[0]
  // (serves(tex) must hold); fragments whose Fragment::tex differs from f[0].tex are undone.
  // With line_shift > 0 also the taps' cache lines of 2^line_shift bytes at the texture's
  // placed addresses (tex.address()), when every address of the texture is below 2^31
  // (out.has_lines says whether they were computed).
  // With `colours`, the colours go to colours[0 .. n) (done fragments only; the others' are
  // unspecified) instead of out.rgba: the caller's array, saving a copy per fragment.
  void filter(const Fragment* f, size_t n, const Texture& tex, LinearBatch& out,
              uint32_t line_shift = 0, Rgba* colours = nullptr) const;

  // The instruction set the batch runs on (e.g. "AVX2", "AVX3").
  static const char* target();

 private:
  LodUnit::Config lod_;
  TexelAddressGen::Config addr_;
};

}  // namespace texsim
