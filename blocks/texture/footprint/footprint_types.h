#pragma once
// Types the anisotropic footprint filters share (EWA, multi-probe, Feline, SPAF): the texels a
// filter read (TexelRef, what the texture cache sees), what a lookup did (FilterStats,
// FilterOutput), the footprint set-up with its max-anisotropy clamp, and the bilinear
// fallback, so that a cache model and the pipeline see every filter the same way.
#include <cstdint>
#include <limits>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

// A texel a filter read: level and addressed coordinates (what the texture cache sees).
struct TexelRef {
  int32_t level;
  int32_t x, y;
};

// What one filtered lookup did besides producing a colour.
struct FilterStats {
  uint32_t visited = 0;    // scan slots: texels (or probes) whose weight was evaluated
  uint32_t texels = 0;     // texels read from texture memory
  uint32_t map_reads = 0;  // weight-map entries read (4 per bilinear map read)
  uint32_t probes = 0;     // probes issued (probe-based filters)
  int32_t level = 0;       // finest level read
  bool fallback = false;   // all weights were zero: the bilinear fallback was used
  bool bad_input = false;  // non-finite coordinates or derivatives were replaced
};

// Cycles a scanning filter (EWA, SPAF) spends on one lookup: its scan slots over `lanes`
// weight units, at least one.
inline uint32_t scan_issue_cycles(const FilterStats& s, int lanes) {
  const auto n = static_cast<uint32_t>(lanes > 1 ? lanes : 1);
  return s.visited > n ? (s.visited + n - 1) / n : 1;
}

// Whether a weight sum can be normalised: at least the smallest normal number of its type, so
// that its reciprocal is finite. A sum of subnormal weights counts as zero (every weight
// underflowed): the caller's fallback, never an infinite colour.
template <class A>
bool normalisable(A wsum) {
  return wsum >= std::numeric_limits<A>::min();
}

struct FilterOutput {
  Rgba colour{0, 0, 0, 0};
  FilterStats stats;
};

// Per-coordinate operations of the addressing modes (the table of docs/derivations/filters.md §3).
OpCounts address_mode_ops(AddressMode m);

// A footprint filter's `address_u`/`address_v` key: wrap (default), clamp, mirror or
// mirror_clamp. Border is refused with a message: the footprint filters have no border colour
// (their taps always read texels).
AddressMode footprint_address_mode(const ConfigReader& r, std::string_view key);

// Footprint of one fragment in level-0 texels as the covariance Σ = R²·J·Jᵀ of the pixel
// footprint (J = derivatives in texels per pixel, R = footprint radius in pixels), after the
// max-anisotropy clamp: the ellipse Q(U, V) = (U, V)·Σ⁻¹·(U, V)ᵀ ≤ 1 is the footprint.
struct Footprint {
  double suu = 0, suv = 0, svv = 0;  // Σ (level 0 texels²)
  double major2 = 0, minor2 = 0;     // eigenvalues of Σ after the clamp (major ≥ minor)
  double aniso = 1;                  // √(major2/minor2) before the clamp (∞ for det = 0)
  bool clamped = false;              // the minor axis was stretched to major/max_aniso
  bool bad_input = false;            // non-finite derivatives: point footprint used
  bool overflow = false;             // Σ overflowed the set-up format: most minified level
};

// Set-up shared by the family: Σ from the derivatives, eigenvalues, and the clamp
// Σ' = Σ + δ·e_min·e_minᵀ with e_min·e_minᵀ = (λ₊I − Σ)/(λ₊ − λ₋), δ = λ₊/maxAniso² − λ₋
// (no angle needed). In S = float or double. Adds its operations to `ops`.
template <class S>
Footprint footprint_setup(const Fragment& f, int w0, int h0, double radius_px, double max_aniso,
                          OpCounts& ops);
OpCounts footprint_setup_ops();

// Bilinear sample of one level at normalised (u, v): the family's fallback when every weight
// is zero. Appends its four texels to `fetched` and counts its operations.
Rgba bilinear_fallback(const Texture& tex, int level, double u, double v, AddressMode au,
                       AddressMode av, std::vector<TexelRef>* fetched, OpCounts& ops);

}  // namespace texsim
