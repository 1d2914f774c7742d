#pragma once
// Legality envelope of anisotropic texture filtering (docs/derivations/anisotropic-filters.md
// §9). Neither Vulkan nor its CTS gives a numeric rule for anisotropic filtering; what exists is
// EXT_texture_filter_anisotropic's recipe and the freedom it grants, plus D3D's fixed 8
// sub-texel and 8 LOD-fraction bits. The checker turns those into four tests on what a filter
// observably did for one lookup: how many probes it issued, which mip levels and which texels
// it read, and the colour it returned. Independent of the filter blocks: it shares only
// Texture, TexelRef and AddressMode. Arithmetic: double.
#include <string>
#include <vector>

#include "blocks/texture/footprint/footprint_types.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

struct AnisoEnvelopeSpec {
  int max_aniso = 16;                   // TEXTURE_MAX_ANISOTROPY
  bool power_of_two_rates = true;       // N may be rounded up to the next supported rate 2^k
  int lod_fraction_bits = 8;            // D3D: λ within ±2^-8 of the rule's value
  int sub_texel_bits = 8;               // D3D: sample positions within 2^-8 texel
  double colour_eps = 1.0 / 4096;       // float arithmetic in the weighted sum
  long long max_hull_texels = 1 << 20;  // colour hull larger than this: colour not judged
};

// What a filter did for one lookup.
struct AnisoObservation {
  Rgba colour{0, 0, 0, 0};
  std::vector<TexelRef> texels;  // texels read with a non-zero weight (addressed coordinates)
  int probes = 0;                // probes issued; 0 for filters that do not probe (EWA, SPAF)
};

// The envelope of one query (level-0 texels; λ after the [0, levels − 1] clamp).
struct AnisoBounds {
  double px_lo = 0, px_hi = 0, py_lo = 0, py_hi = 0;  // max(|a|,|b|) ≤ F ≤ |a| + |b| per axis
  int n_lo = 1, n_hi = 1;                             // probe counts allowed
  double lambda_lo = 0, lambda_hi = 0;                // λ' = log2(Pmax / N) over the above
  int level_lo = 0, level_hi = 0;                     // levels a trilinear probe may read
};

struct AnisoVerdict {
  bool probes_ok = true;  // probe count inside [n_lo, n_hi] (always true when probes = 0)
  bool levels_ok = true;  // every level read inside [level_lo, level_hi]
  bool too_fine = false, too_coarse = false;  // which side a level outside lay on
  bool region_ok = true;      // every texel within a bilinear support of the pixel's footprint
  bool colour_ok = true;      // colour inside the per-channel hull of the footprint's texels
  bool colour_judged = true;  // false: hull too large to enumerate (colour_ok then true)
  std::string reason;         // first failure, with the numbers; "ok" when all pass
  bool pass() const { return probes_ok && levels_ok && region_ok && colour_ok; }
};

// One lookup at normalised (u, v) with normalised screen derivatives, bias 0, the whole
// pyramid in view.
struct AnisoQuery {
  double u = 0, v = 0;
  double dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;
};

class AnisoEnvelope {
 public:
  explicit AnisoEnvelope(const AnisoEnvelopeSpec& spec) : spec_(spec) {}

  // The envelope of `q` on `tex`: N = min(⌈Pmax/Pmin⌉, max_aniso) over every Pmax, Pmin the
  // per-axis footprint estimates F allow, N_hi rounded up to a supported rate; λ' = log2(Pmax/N)
  // over the same, widened by the LOD-fraction accuracy; levels ⌊λ_lo⌋ … ⌈λ_hi⌉.
  AnisoBounds bounds(const Texture& tex, const AnisoQuery& q) const;

  // Whether the observation lies inside the envelope. The footprint is the pixel's
  // parallelogram centre ± ½·J_x ± ½·J_y: EXT_texture_filter_anisotropic samples "within the
  // texture footprint of the pixel". A texel of level L is inside when its centre lies within
  // one level-L texel (+ sub-texel slack) of it on each axis: a bilinear probe there may read
  // it. Wrap and clamp addressing are judged; mirror addressing is not (region_ok stays true).
  AnisoVerdict check(const Texture& tex, const AnisoQuery& q, const AnisoObservation& obs,
                     AddressMode au, AddressMode av) const;

  const AnisoEnvelopeSpec& spec() const { return spec_; }

 private:
  AnisoEnvelopeSpec spec_;
};

}  // namespace texsim
